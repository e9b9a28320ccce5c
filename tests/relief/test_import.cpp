// Relief from a colour photo (the band model of import.h) and the normal-map convention check.
#include "strata/relief/import.h"

#include "strata/core/error.h"
#include "strata/image/image_ops.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

// A tileable synthetic "photo", defined in tile units so that every resolution samples the same
// scene: bright discs (radius 0.09 of the tile, edges smoothed over 0.01) centred on the 4 x 4
// lattice (i/4, j/4), so that discs straddle the tile border, on a dark background; plus an additive
// lighting wave `lighting * sin(2 pi u)`, brightest at u = 1/4 and darkest at u = 3/4. Slightly
// warm-tinted RGB. Everything in it has period 1 in u and v, so it tiles exactly.
constexpr double kDiscRadius = 0.09;
constexpr double kLighting = 0.25;

Image discPhoto(int size, double lighting = kLighting) {
    Image photo(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double u = photo.texelU(x);
            const double v = photo.texelV(y);
            // Offset from the nearest lattice point, in tile units.
            const double du = u - std::round(u * 4.0) / 4.0;
            const double dv = v - std::round(v * 4.0) / 4.0;
            double t = std::clamp((kDiscRadius - std::hypot(du, dv)) / 0.01 + 0.5, 0.0, 1.0);
            t = t * t * (3.0 - 2.0 * t);
            const double l = 0.3 + 0.4 * t + lighting * std::sin(2.0 * kPi * u);
            const double tint[3] = {1.0, 0.9, 0.8};
            for (int c = 0; c < 3; ++c) photo.at(x, y, c) = static_cast<float>(l * tint[c]);
        }
    return photo;
}

// Disc centres (the lattice) and background points (the middle between four discs), as (u, v).
std::vector<std::pair<double, double>> discCentres() {
    std::vector<std::pair<double, double>> points;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) points.emplace_back(i / 4.0, j / 4.0);
    return points;
}

std::vector<std::pair<double, double>> backgroundPoints() {
    std::vector<std::pair<double, double>> points;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) points.emplace_back(i / 4.0 + 0.125, j / 4.0 + 0.125);
    return points;
}

// ---------------------------------------------------------------------------------------------

TEST(ImportFromPhoto, BrightDiscsBecomeHigh) {
    const Image photo = discPhoto(256);
    const ReliefTexture relief = reliefFromPhoto(photo);

    ASSERT_EQ(relief.depth.channels(), 1);
    ASSERT_EQ(relief.depth.width(), 256);
    ASSERT_EQ(relief.depth.height(), 256);
    const ValueRange range = valueRange(relief.depth);
    // Normalised to exactly [0, 1]: (max - min) / (max - min) is 1 in IEEE arithmetic.
    EXPECT_EQ(range.min, 0.0f);
    EXPECT_EQ(range.max, 1.0f);

    // Every disc centre is near the top and every background point near the bottom. The margins:
    // the lighting wave left in the bands moves points by up to +-0.07 (0.14 between the brightest and
    // the darkest, see LightingGradientDoesNotDominate), so 0.25 and 0.6 still separate "high" from
    // "low" with room to spare (measured: centres <= 0.17, background >= 0.82).
    for (const auto& [u, v] : discCentres())
        EXPECT_LT(relief.depth.sample(u, v), 0.25) << "disc at " << u << ", " << v;
    for (const auto& [u, v] : backgroundPoints())
        EXPECT_GT(relief.depth.sample(u, v), 0.6) << "background at " << u << ", " << v;

    // The other maps: normals at the requested S from this depth, colour = the photo.
    EXPECT_EQ(relief.depthScale, PhotoImportParams{}.depthScale);
    EXPECT_EQ(relief.normal, normalsFromDepth(relief.depth, relief.depthScale));
    EXPECT_EQ(relief.color, photo);
    EXPECT_TRUE(relief.ao.empty());
}

TEST(ImportFromPhoto, InvertMakesDarkHigh) {
    PhotoImportParams params;
    params.invert = true;
    const ReliefTexture relief = reliefFromPhoto(discPhoto(128), params);
    const ValueRange range = valueRange(relief.depth);
    EXPECT_EQ(range.min, 0.0f);
    EXPECT_EQ(range.max, 1.0f);
    // Mirror image of the test above: h -> -h, renormalised, is d -> 1 - d.
    const ReliefTexture plain = reliefFromPhoto(discPhoto(128));
    // 1e-6: the two normalisations round differently in the last float bit.
    EXPECT_LT(test::maxAbsDiff(relief.depth, heightToDepth(plain.depth)), 1e-6);
}

TEST(ImportFromPhoto, LightingGradientDoesNotDominate) {
    const Image photo = discPhoto(256);
    const ReliefTexture relief = reliefFromPhoto(photo);
    // Two discs at the brightest (u = 1/4) and the darkest (u = 3/4) part of the lighting wave.
    const double lit = relief.depth.sample(0.25, 0.5);
    const double dark = relief.depth.sample(0.75, 0.5);
    // Taking the luminance as height directly, the wave (amplitude 0.25 against a disc contrast of
    // 0.4) puts those two discs 0.5 of the range apart: the lighting would dominate.
    const Image raw = normalizeToUnit(luminance(photo));
    const double rawDifference = std::fabs(raw.sample(0.25, 0.5) - raw.sample(0.75, 0.5));
    EXPECT_GT(rawDifference, 0.4);
    // The bands pass only G_sigmaLarge - G_sigmaHuge of a once-per-tile wave, a gain of
    // exp(-2 pi^2 0.015^2) - exp(-2 pi^2 0.08^2) = 0.11 at the defaults: 0.057 of the 0.5 luminance
    // difference between the two discs is left, in an h whose range (discs and their edges) is about
    // 0.42, so 0.135 of the depth range is expected (measured: 0.136, against 0.56 raw). 0.2 leaves
    // room for the filter approximations, and would fail if sigmaHuge were twice as wide (gain 0.40).
    // The second check states the point: at least two thirds of the lighting is gone.
    EXPECT_LT(std::fabs(lit - dark), 0.2);
    EXPECT_LT(std::fabs(lit - dark), rawDifference / 3.0);
}

TEST(ImportFromPhoto, TileablePhotoGivesTileableDepth) {
    const ReliefTexture relief = reliefFromPhoto(discPhoto(256));
    const Image& d = relief.depth;
    const int w = d.width();
    const int h = d.height();
    // Across the tile border the depth must be as continuous as inside: no jump between the last and
    // the first column (or row) larger than the largest jump between neighbours inside the tile.
    // Discs straddle both borders and the lighting wave is steepest at u = 0, so the border is not
    // a flat region where this would hold trivially.
    double interior = 0.0;
    double seam = 0.0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x + 1 < w; ++x)
            interior = std::max(interior, static_cast<double>(std::fabs(d.at(x + 1, y) - d.at(x, y))));
        seam = std::max(seam, static_cast<double>(std::fabs(d.at(0, y) - d.at(w - 1, y))));
    }
    for (int x = 0; x < w; ++x) {
        for (int y = 0; y + 1 < h; ++y)
            interior = std::max(interior, static_cast<double>(std::fabs(d.at(x, y + 1) - d.at(x, y))));
        seam = std::max(seam, static_cast<double>(std::fabs(d.at(x, 0) - d.at(x, h - 1))));
    }
    EXPECT_LE(seam, interior);

    // Stronger: the scene is symmetric under a shift by a quarter tile in v (the lighting depends on
    // u only), so the depth must be too, to float rounding, which only wrap-around filters give.
    Image shifted(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) shifted.at(x, y) = d.atWrapped(x, y + h / 4);
    // 1e-5: the blurs sum a few hundred float terms in double and round back to float (1e-7 each),
    // and the running sums start at different rows, so exact equality is not guaranteed (measured: 0).
    EXPECT_LT(test::maxAbsDiff(shifted, d), 1e-5);
}

TEST(ImportFromPhoto, IndependentOfResolution) {
    // The same analytic scene at 512^2 and 256^2: with sigmas in tile widths the two depth maps agree
    // once the larger is reduced to the smaller's size.
    const Image fine = resample(reliefFromPhoto(discPhoto(512)).depth, 256, 256);
    const Image coarse = reliefFromPhoto(discPhoto(256)).depth;
    double mean = 0.0;
    for (std::size_t i = 0; i < fine.pixels().size(); ++i)
        mean += std::fabs(static_cast<double>(fine.pixels()[i]) - static_cast<double>(coarse.pixels()[i]));
    mean /= static_cast<double>(fine.pixels().size());
    const double worst = test::maxAbsDiff(fine, coarse);
    std::printf("photo import, 512^2 reduced vs 256^2: max %.4f, mean %.5f of the depth range\n", worst,
                mean);
    // What legitimately differs: the finest band reaches down to the texel (sigmaSmall = 0), and the
    // 0.01-wide disc edges are 5 texels at 512^2 but 2.5 at 256^2, so point samples and 2x2 averages
    // differ there; that band carries 0.25 of the 1.75 total weight. 0.03 of the range for the worst
    // texel (on a disc edge) and 0.005 on average keep a factor of 2-3 over the measured 0.011 and
    // 0.0022, and are far below the 0.6 that separates disc from background.
    EXPECT_LT(worst, 0.03);
    EXPECT_LT(mean, 0.005);
}

TEST(ImportFromPhoto, IsDeterministic) {
    const Image photo = discPhoto(128);
    const ReliefTexture a = reliefFromPhoto(photo);
    const ReliefTexture b = reliefFromPhoto(photo);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.normal, b.normal);
}

TEST(ImportFromPhoto, ColourFromGrayAndRgbaPhotos) {
    Image gray(8, 4, 1);
    Image rgba(8, 4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            gray.at(x, y) = static_cast<float>(x * 4 + y) / 32.0f;
            for (int c = 0; c < 4; ++c) rgba.at(x, y, c) = static_cast<float>(x + y + c) / 16.0f;
        }
    const Image fromGray = reliefFromPhoto(gray).color;
    const Image fromRgba = reliefFromPhoto(rgba).color;
    ASSERT_EQ(fromGray.channels(), 3);
    ASSERT_EQ(fromRgba.channels(), 3);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(fromGray.at(x, y, c), gray.at(x, y));
                EXPECT_EQ(fromRgba.at(x, y, c), rgba.at(x, y, c));
            }
}

TEST(ImportFromPhoto, FeaturelessPhotoIsFlatAtTheTop) {
    const ReliefTexture relief = reliefFromPhoto(Image(32, 32, 3, 0.4f));
    EXPECT_EQ(valueRange(relief.depth).max, 0.0f);
    EXPECT_EQ(valueRange(relief.normal, 2).min, 1.0f);
}

TEST(ImportFromPhoto, WorksOnNonSquarePhotos) {
    // The tile is the unit square whatever the aspect (CONVENTIONS §1): a 256 x 128 photo of the scene
    // gives the 256^2 result squeezed vertically.
    const Image wide = resample(discPhoto(256), 256, 128);
    const Image depth = reliefFromPhoto(wide).depth;
    const Image reference = resample(reliefFromPhoto(discPhoto(256)).depth, 256, 128);
    // 0.03: as in the resolution test (the finest band sees the edges at another texel spacing
    // along v); measured 0.006.
    EXPECT_LT(test::maxAbsDiff(depth, reference), 0.03);
}

// Each invalid parameter is refused with InvalidInput and a message that starts with its field name.
TEST(ImportFromPhoto, InvalidParametersNameTheField) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    struct Case {
        std::string field;
        std::function<void(PhotoImportParams&)> change;
    };
    const std::vector<Case> cases = {
        {"weightLarge", [](PhotoImportParams& p) { p.weightLarge = -1.0; }},
        {"weightMedium", [](PhotoImportParams& p) { p.weightMedium = -0.1; }},
        {"weightSmall", [](PhotoImportParams& p) { p.weightSmall = -1e-9; }},
        {"weightLarge", [=](PhotoImportParams& p) { p.weightLarge = nan; }},
        {"weightSmall", [=](PhotoImportParams& p) { p.weightSmall = inf; }},
        {"weightLarge, weightMedium, weightSmall",
         [](PhotoImportParams& p) { p.weightLarge = p.weightMedium = p.weightSmall = 0.0; }},
        {"sigmaSmall", [](PhotoImportParams& p) { p.sigmaSmall = -0.001; }},
        {"sigmaSmall", [=](PhotoImportParams& p) { p.sigmaSmall = nan; }},
        {"sigmaMedium", [](PhotoImportParams& p) { p.sigmaSmall = p.sigmaMedium; }},
        {"sigmaMedium", [=](PhotoImportParams& p) { p.sigmaMedium = nan; }},
        {"sigmaLarge", [](PhotoImportParams& p) { p.sigmaLarge = 0.001; }},
        {"sigmaHuge", [](PhotoImportParams& p) { p.sigmaHuge = p.sigmaLarge; }},
        {"sigmaHuge", [](PhotoImportParams& p) { p.sigmaHuge = 2.0; }},
        {"sigmaHuge", [=](PhotoImportParams& p) { p.sigmaHuge = inf; }},
        {"depthScale", [](PhotoImportParams& p) { p.depthScale = 0.0; }},
        {"depthScale", [](PhotoImportParams& p) { p.depthScale = -0.1; }},
        {"depthScale", [=](PhotoImportParams& p) { p.depthScale = nan; }},
    };
    const Image photo = discPhoto(32);
    for (const Case& c : cases) {
        PhotoImportParams params;
        c.change(params);
        try {
            reliefFromPhoto(photo, params);
            ADD_FAILURE() << c.field << ": no error";
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
            const std::string message = error.what();
            EXPECT_EQ(message.rfind(c.field + ": ", 0), 0u) << message;
        }
    }
    // Zero weights are fine as long as one is left.
    PhotoImportParams onlySmall;
    onlySmall.weightLarge = onlySmall.weightMedium = 0.0;
    EXPECT_NO_THROW(reliefFromPhoto(photo, onlySmall));

    try {
        reliefFromPhoto(Image{});
        ADD_FAILURE() << "empty photo: no error";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
        EXPECT_EQ(std::string(error.what()).rfind("photo: ", 0), 0u) << error.what();
    }
}

// ---------------------------------------------------------------------------------------------

// A bumpy tileable depth field, with slopes in both directions everywhere but a few lines.
Image bumpyDepth(int size) {
    Image depth(size, size, 1);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double u = depth.texelU(x);
            const double v = depth.texelV(y);
            depth.at(x, y) =
                static_cast<float>(0.5 + 0.3 * std::sin(2.0 * kPi * 3.0 * u) * std::cos(2.0 * kPi * 2.0 * v) +
                                   0.15 * std::sin(2.0 * kPi * (u + 2.0 * v)));
        }
    return depth;
}

TEST(ImportConvention, OpenGLMapIsRecognised) {
    const Image depth = bumpyDepth(128);
    // Another S than the detector's own: the scale changes magnitudes, not signs.
    const Image normals = normalsFromDepth(depth, 0.3);
    const NormalConventionReport report = detectNormalConvention(normals, depth);
    EXPECT_EQ(report.convention, NormalConvention::OpenGL) << report.summary;
    // Same field, same differences: only the normalisation by a different S bends the relation, and
    // at slopes up to S |grad d| = 0.3 * 6.8 = 2 that keeps r above 0.95 (measured 0.990 and 0.992).
    EXPECT_GT(report.correlationX, 0.95);
    EXPECT_GT(report.correlationY, 0.95);
    EXPECT_EQ(report.threshold, kConventionCorrelationThreshold);
    EXPECT_EQ(report.summary.rfind("OpenGL (green up): y agrees with the depth map's normals (r = ", 0), 0u)
        << report.summary;
}

TEST(ImportConvention, FlippedGreenIsDirectX) {
    const Image depth = bumpyDepth(128);
    // The way a DirectX file arrives: green stored downwards, decoded without a flip.
    const Image directX = decodeNormals(encodeNormals(normalsFromDepth(depth, 0.08)), true);
    const NormalConventionReport report = detectNormalConvention(directX, depth);
    EXPECT_EQ(report.convention, NormalConvention::DirectX) << report.summary;
    EXPECT_GT(report.correlationX, 0.95);   // as above
    EXPECT_LT(report.correlationY, -0.95);  // the same relation, negated
    EXPECT_EQ(report.summary.rfind("DirectX (green down)", 0), 0u) << report.summary;
}

TEST(ImportConvention, NoiseIsUnknown) {
    const Image depth = bumpyDepth(256);
    std::mt19937 random(7);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    Image noise(256, 256, 3);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            float n[3] = {0.3f * gauss(random), 0.3f * gauss(random), 1.0f};
            const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int c = 0; c < 3; ++c) noise.at(x, y, c) = n[c] / length;
        }
    const NormalConventionReport report = detectNormalConvention(noise, depth);
    EXPECT_EQ(report.convention, NormalConvention::Unknown) << report.summary;
    // Unrelated maps of N = 65536 texels correlate at |r| ~ 1/sqrt(N) = 0.004: 0.05 is 12 of those.
    EXPECT_LT(std::fabs(report.correlationX), 0.05);
    EXPECT_LT(std::fabs(report.correlationY), 0.05);
}

TEST(ImportConvention, DifferentResolutionsAreCompared) {
    // A 256^2 normal map with its 128^2 depth map, and the other way round: the depth is resampled to
    // the normal map's size, which smooths or interpolates it but keeps every slope's sign.
    const Image depthFine = bumpyDepth(256);
    const Image depthCoarse = bumpyDepth(128);
    const NormalConventionReport up = detectNormalConvention(normalsFromDepth(depthFine, 0.08), depthCoarse);
    EXPECT_EQ(up.convention, NormalConvention::OpenGL) << up.summary;
    // 0.9: bilinear magnification or box reduction of this smooth field changes slopes by a few per
    // cent at most (measured: r = 1.00 to two decimals); well above the 0.3 decision threshold.
    EXPECT_GT(up.correlationY, 0.9);
    const NormalConventionReport down = detectNormalConvention(
        decodeNormals(encodeNormals(normalsFromDepth(depthCoarse, 0.08)), true), depthFine);
    EXPECT_EQ(down.convention, NormalConvention::DirectX) << down.summary;
    EXPECT_LT(down.correlationY, -0.9);  // as above, negated
}

TEST(ImportConvention, HeightInsteadOfDepthIsCaught) {
    // A height map given where a depth map belongs negates both derived components: x then disagrees,
    // so nothing is concluded about y (it would wrongly read as DirectX), and the summary says why.
    const Image depth = bumpyDepth(128);
    const NormalConventionReport report =
        detectNormalConvention(normalsFromDepth(depth, 0.08), heightToDepth(depth));
    EXPECT_EQ(report.convention, NormalConvention::Unknown);
    EXPECT_LT(report.correlationX, -0.95);
    EXPECT_NE(report.summary.find("height map"), std::string::npos) << report.summary;
}

TEST(ImportConvention, FlatDepthAndTinyMapsAreUnknown) {
    const NormalConventionReport flat =
        detectNormalConvention(normalsFromDepth(bumpyDepth(64), 0.08), Image(64, 64, 1, 0.5f));
    EXPECT_EQ(flat.convention, NormalConvention::Unknown);
    EXPECT_NE(flat.summary.find("flat"), std::string::npos) << flat.summary;

    // At 4 x 4 texels, chance alone correlates at |r| ~ 0.25: the threshold rises to 4/sqrt(16) = 1,
    // which no correlation exceeds.
    const Image tiny = bumpyDepth(4);
    const NormalConventionReport small = detectNormalConvention(normalsFromDepth(tiny, 0.08), tiny);
    EXPECT_EQ(small.threshold, 1.0);
    EXPECT_EQ(small.convention, NormalConvention::Unknown) << small.summary;
    EXPECT_NE(small.summary.find("too few"), std::string::npos) << small.summary;
}

TEST(ImportConvention, WrongChannelCountsAreInvalidInput) {
    const Image depth = bumpyDepth(16);
    EXPECT_THROW(detectNormalConvention(depth, depth), Error);
    EXPECT_THROW(detectNormalConvention(normalsFromDepth(depth, 0.1), Image(16, 16, 3)), Error);
    EXPECT_THROW(detectNormalConvention(Image{}, depth), Error);
    try {
        detectNormalConvention(normalsFromDepth(depth, 0.1), Image{});
        ADD_FAILURE() << "empty depth: no error";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
    }
}

TEST(ImportConvention, Names) {
    EXPECT_STREQ(toString(NormalConvention::OpenGL), "OpenGL");
    EXPECT_STREQ(toString(NormalConvention::DirectX), "DirectX");
    EXPECT_STREQ(toString(NormalConvention::Unknown), "unknown");
}

}  // namespace
}  // namespace strata
