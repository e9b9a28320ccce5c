// Environments: the §9 equirectangular conventions, projection with exact solid angles, EXR reading and its
// errors, and the built-in skies.
#include "strata/core/error.h"
#include "strata/environment/environment.h"
#include "strata/image/image_io.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

template <typename Function>
Error errorOf(Function&& function) {
    try {
        function();
    } catch (const Error& error) {
        return error;
    }
    ADD_FAILURE() << "no strata::Error thrown";
    return Error(ErrorKind::Runtime, "");
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(Equirect, TexelCentresFollowConventionsSection9) {
    // 8 x 4: row 0's centre is at polar pi / 8 (near +z); column 0's at azimuth pi / 8 (just past +x,
    // towards +y).
    const glm::dvec3 first = equirectTexelDirection(0, 0, 8, 4);
    EXPECT_NEAR(first.z, std::cos(kPi / 8.0), 1e-15);  // one cos: rounding
    EXPECT_NEAR(first.x, std::sin(kPi / 8.0) * std::cos(kPi / 8.0), 1e-15);
    EXPECT_NEAR(first.y, std::sin(kPi / 8.0) * std::sin(kPi / 8.0), 1e-15);
    EXPECT_GT(first.y, 0.0);  // azimuth grows towards +y
    // The last row is next to the nadir.
    EXPECT_NEAR(equirectTexelDirection(3, 3, 8, 4).z, -std::cos(kPi / 8.0), 1e-15);

    // The cells that hold the axes: +x starts column 0 on the equator (polar pi / 2 is the start of row 2 of
    // 4), +y is a quarter of the way round, -x half way; the poles are rows 0 and H - 1.
    const auto texel = [](glm::dvec3 d) { return equirectTexelOf(d, 8, 4); };
    EXPECT_EQ(texel({1, 0, 0}).column, 0);
    EXPECT_EQ(texel({1, 0, 0}).row, 2);
    EXPECT_EQ(texel({0, 1, 0.1}).column, 2);
    EXPECT_EQ(texel({0, 1, 0.1}).row, 1);
    EXPECT_EQ(texel({-1, -0.01, 0}).column, 4);
    EXPECT_EQ(texel({0, -1, 0}).column, 6);
    EXPECT_EQ(texel({0, 0, 1}).row, 0);
    EXPECT_EQ(texel({0, 0, -1}).row, 3);
    // Every texel centre maps back to its own texel.
    for (int row = 0; row < 4; ++row)
        for (int column = 0; column < 8; ++column) {
            const EquirectTexel t = texel(equirectTexelDirection(column, row, 8, 4));
            EXPECT_EQ(t.column, column);
            EXPECT_EQ(t.row, row);
        }
}

TEST(Equirect, TexelSolidAnglesAreExactAndAddUpTo4Pi) {
    // A 4 x 2 map: each texel is a quarter of a hemisphere, pi / 2.
    EXPECT_NEAR(equirectTexelSolidAngle(0, 4, 2), kPi / 2.0, 1e-15);  // rounding of cos(pi / 2) ~ 6e-17
    EXPECT_NEAR(equirectTexelSolidAngle(1, 4, 2), kPi / 2.0, 1e-15);
    double sum = 0.0;
    for (int row = 0; row < 256; ++row) sum += 512 * equirectTexelSolidAngle(row, 512, 256);
    EXPECT_NEAR(sum, 4.0 * kPi, 1e-12);  // telescoping cosines: 256 terms' rounding
}

// Projection values each texel at its centre direction and weights it by its cell's exact solid angle: in
// azimuth that is exact for bands <= 3 (uniform samples of cos(m p), m < W), in the polar angle it is a
// midpoint rule. For a zonal g(t) its error (rule - exact) is, to leading order,
//     E = -(dt^2 / 24) 2 pi * integral of (2 g' cos t + g'' sin t) dt,   dt = pi / H,
// (expand g and sin t about each row's centre). A constant map has E = 0 for c_00 (the weights add up to
// 4 pi), 0 for odd l (equator symmetry) and for m != 0, and E = (pi / 3) K_20 dt^2 for c_20 (g = K_20 (3
// cos^2 t
// - 1): the integral is -4 K_20).
TEST(Equirect, ConstantMapProjectsWithTheMidpointRulesError) {
    const double k20 = 0.25 * std::sqrt(5.0 / kPi);
    for (const int height : {32, 64}) {
        const ShColor sh = projectEquirect(Image(2 * height, height, 3, 1.0f));
        EXPECT_NEAR(sh[0].x, std::sqrt(4.0 * kPi), 1e-12);  // exact weights: rounding only
        for (int k = 1; k < kShCount; ++k) {
            if (k == shIndex(2, 0)) continue;
            EXPECT_NEAR(sh[k].y, 0.0, 1e-12) << k;  // exact cancellation: rounding
        }
        const double dt = kPi / height;
        // The next term is O(dt^4), relative dt^2 ~ 1% at H = 32: 2% bounds it.
        EXPECT_NEAR(sh[shIndex(2, 0)].z, kPi / 3.0 * k20 * dt * dt, 0.02 * kPi / 3.0 * k20 * dt * dt)
            << height;
    }
    // One channel means grey.
    const ShColor grey = projectEquirect(Image(64, 32, 1, 2.0f));
    EXPECT_NEAR(grey[0].z, 2.0 * std::sqrt(4.0 * kPi), 1e-12);  // rounding
}

// The clamped cosine rendered into a 512 x 256 map and projected. The kink at the equator lies on a row
// boundary (H even), so the midpoint rule's leading error above holds on each hemisphere; with g =
// max(cos t, 0) K_l P_l(cos t) the bound (dt^2 / 24) 2 pi * integral of |2 g' cos t + g'' sin t| dt is
// {0.111, 0.256, 0.467, 0.741} dt^2 for l = 0..3 (integrated numerically while writing this test), i.e.
// 1.7e-5, 3.9e-5, 7.0e-5, 1.1e-4 at dt = pi / 256; measured errors 1.67e-5, 1.28e-5, 0.93e-5, 2.94e-5 (the
// signed leading terms exactly). 5% on the bound covers the O(dt^4) terms.
TEST(Equirect, ClampedCosineMapMatchesRamamoorthiHanrahan) {
    const Image map =
        renderEquirect([](const glm::dvec3& d) { return glm::dvec3(std::max(d.z, 0.0)); }, 512, 256);
    const ShColor sh = projectEquirect(map);
    const double dt = kPi / 256.0;
    constexpr double kBound[kShBands] = {0.111, 0.256, 0.467, 0.741};
    for (int l = 0; l < kShBands; ++l)
        for (int m = -l; m <= l; ++m) {
            const double expected =
                m == 0 ? kClampedCosineBands[l] * std::sqrt((2 * l + 1) / (4.0 * kPi)) : 0.0;
            // m != 0: exact in azimuth, rounding only.
            const double tolerance = m == 0 ? 1.05 * kBound[l] * dt * dt : 1e-12;
            EXPECT_NEAR(sh[shIndex(l, m)].x, expected, tolerance) << "l " << l << " m " << m;
        }
}

// §9's orientation end to end: an EXR written with Strata's own writer, black but for one texel at
// (column 5, row 2) of 16 x 8, projects to SH whose band 1 points at that texel's centre direction
// (polar 2.5 pi / 8, azimuth 5.5 * 2 pi / 16). The projection values the texel at its centre, so the
// direction is exact up to rounding.
TEST(Environment, SingleBrightTexelGivesItsCentreDirection) {
    test::ScratchDir dir("environment-orientation");
    Image map(16, 8, 3, 0.0f);
    for (int c = 0; c < 3; ++c) map.at(5, 2, c) = 10.0f;
    writeExr(dir / "one.exr", map);
    const Environment environment = loadEnvironment(dir / "one.exr");
    EXPECT_FALSE(environment.isProcedural());
    const glm::dvec3 expected = sphericalDirection(2.5 * kPi / 8.0, 5.5 * 2.0 * kPi / 16.0);
    const glm::dvec3 found = shDominantDirection(shLuminance(environment.sh()));
    EXPECT_NEAR(found.x, expected.x, 1e-12);  // rounding of a normalised multiple of the direction
    EXPECT_NEAR(found.y, expected.y, 1e-12);
    EXPECT_NEAR(found.z, expected.z, 1e-12);
    // In words: azimuth 123.75 degrees (towards +y, past it towards -x), 56.25 degrees from the zenith.
    EXPECT_LT(found.x, 0.0);
    EXPECT_GT(found.y, 0.0);
    EXPECT_GT(found.z, 0.0);
    // DC: radiance times the texel's solid angle times Y_00.
    EXPECT_NEAR(environment.sh()[0].x, 10.0 * equirectTexelSolidAngle(2, 16, 8) * 0.5 / std::sqrt(kPi),
                1e-12);
    // The map's radiance lookup is the nearest texel.
    EXPECT_EQ(environment.radiance(expected), glm::dvec3(10.0));
    EXPECT_EQ(environment.radiance({0, 0, 1}), glm::dvec3(0.0));
}

TEST(Environment, GreyExrBecomesRgb) {
    test::ScratchDir dir("environment-grey");
    writeExr(dir / "grey.exr", Image(4, 2, 1, 0.5f));
    const Image map = readEnvironmentMap(dir / "grey.exr");
    ASSERT_EQ(map.channels(), 3);
    EXPECT_EQ(map.at(3, 1, 2), 0.5f);
}

TEST(Environment, BadFilesGiveClearErrors) {
    test::ScratchDir dir("environment-bad");
    const Error missing = errorOf([&] { readEnvironmentMap(dir / "missing.exr"); });
    EXPECT_EQ(missing.kind(), ErrorKind::Io);
    EXPECT_TRUE(contains(missing.what(), "missing.exr")) << missing.what();

    writePng(dir / "sky.png", Image(4, 2, 3, 0.5f));
    const Error png = errorOf([&] { readEnvironmentMap(dir / "sky.png"); });
    EXPECT_EQ(png.kind(), ErrorKind::InvalidInput);
    EXPECT_TRUE(contains(png.what(), "sky.png") && contains(png.what(), "OpenEXR") &&
                contains(png.what(), "PNG"))
        << png.what();

    test::writeBytes(dir / "corrupt.exr", std::string("\x76\x2f\x31\x01\x02\x00\x00\x00garbage", 15));
    const Error corrupt = errorOf([&] { loadEnvironment(dir / "corrupt.exr"); });
    EXPECT_EQ(corrupt.kind(), ErrorKind::InvalidInput);
    EXPECT_TRUE(contains(corrupt.what(), "corrupt.exr")) << corrupt.what();

    Image negative(4, 2, 3, 1.0f);
    negative.at(3, 1, 1) = -2.0f;
    writeExr(dir / "negative.exr", negative);
    const Error bad = errorOf([&] { loadEnvironment(dir / "negative.exr"); });
    EXPECT_EQ(bad.kind(), ErrorKind::InvalidInput);
    EXPECT_TRUE(contains(bad.what(), "negative.exr") && contains(bad.what(), "column 3, row 1") &&
                contains(bad.what(), "channel G") && contains(bad.what(), "-2"))
        << bad.what();

    Image notFinite(4, 2, 3, 1.0f);
    notFinite.at(0, 0, 0) = std::numeric_limits<float>::infinity();
    writeExr(dir / "inf.exr", notFinite);
    const Error inf = errorOf([&] { loadEnvironment(dir / "inf.exr"); });
    EXPECT_EQ(inf.kind(), ErrorKind::InvalidInput);
    EXPECT_TRUE(contains(inf.what(), "inf.exr") && contains(inf.what(), "column 0, row 0")) << inf.what();
}

TEST(Environment, UnknownNamesListTheBuiltIns) {
    const std::vector<std::string> expected = {"sky-clear", "sky-overcast", "sky-sunset", "studio"};
    EXPECT_EQ(environmentList(), expected);
    const Error unknown = errorOf([] { makeEnvironment("sky-cloudy"); });
    EXPECT_EQ(unknown.kind(), ErrorKind::InvalidInput);
    EXPECT_TRUE(contains(unknown.what(), "'sky-cloudy'") &&
                contains(unknown.what(), "sky-clear, sky-overcast, sky-sunset, studio"))
        << unknown.what();
    const Error neither = errorOf([] { openEnvironment("no-such-sky.exr"); });
    EXPECT_EQ(neither.kind(), ErrorKind::InvalidInput);
    EXPECT_TRUE(contains(neither.what(), "no-such-sky.exr") && contains(neither.what(), "studio"))
        << neither.what();
    const Error size = errorOf([] { makeEnvironment("studio", 0, 256); });
    EXPECT_EQ(size.kind(), ErrorKind::InvalidInput);
    EXPECT_TRUE(contains(size.what(), "0x256")) << size.what();
    EXPECT_EQ(openEnvironment("studio", 8, 4).name(), "studio");
}

// The CIE overcast sky, analytically: the sky L = (1 + 2z) / 3 on z >= 0 integrates to 2 pi (1 + 1) / 3 =
// 4 pi / 3, the ground 0.2 * 7/9 over 2 pi sr. Its map's DC term must be Y_00 times that, within the midpoint
// rule's error: the ground's step lies on a row boundary and the sky is smooth in each row, so it is the
// second-order term above, about (pi / 256)^2 / 24 ~ 6e-6 of the value (measured 7.6e-6 relative); 1e-5
// relative is the bound.
TEST(Skies, OvercastDcTermIsTheAnalyticIntegral) {
    const Environment overcast = makeEnvironment("sky-overcast");
    const double integral = 4.0 * kPi / 3.0 + 2.0 * kPi * 0.2 * 7.0 / 9.0;
    const double expected = integral * 0.5 / std::sqrt(kPi);
    EXPECT_NEAR(overcast.sh()[0].y, expected, 1e-5 * expected);
    // Irradiance at +z: the ground is below the horizon, so it is the sky's 7 pi / 9. The SH irradiance drops
    // the clamped cosine's bands >= 4 (Ramamoorthi & Hanrahan, Sec. 3, bound that loss by 9% for any
    // lighting, 3% on average); for this smooth sky it is measured 0.43% low; 1% is the bound.
    const double zenithIrradiance = shReconstruct(shIrradiance(overcast.sh()), {0, 0, 1}).x;
    EXPECT_NEAR(zenithIrradiance, 7.0 * kPi / 9.0, 0.01 * 7.0 * kPi / 9.0);
}

// Every sky: its map is finite and non-negative, and its DC term is Y_00 times the integral of its radiance.
// The integral is measured independently with a spherical Fibonacci lattice of 2^20 equal-area points (each
// 4 pi / N sr). The skies are discontinuous at the horizon and at the discs' edges, and the map point-samples
// discs a few texels across, so both rules err by about the share of cells a boundary cuts: measured worst
// 9.3e-4 relative (sky-clear, red); 1% is the bound.
TEST(Skies, FiniteNonNegativeAndDcIsTheMeanTimes4Pi) {
    constexpr int kPoints = 1 << 20;
    const double goldenAngle = kPi * (3.0 - std::sqrt(5.0));
    for (const std::string& name : environmentList()) {
        const Environment sky = makeEnvironment(name, 512, 256);
        EXPECT_TRUE(sky.isProcedural());
        for (const float value : sky.map().pixels()) {
            ASSERT_TRUE(std::isfinite(value)) << name;
            ASSERT_GE(value, 0.0f) << name;
        }
        glm::dvec3 sum(0.0);
        for (int i = 0; i < kPoints; ++i) {
            const double z = 1.0 - (2.0 * i + 1.0) / kPoints;
            const double r = std::sqrt(1.0 - z * z);
            const double azimuth = goldenAngle * i;
            sum += sky.radiance({r * std::cos(azimuth), r * std::sin(azimuth), z});
        }
        const glm::dvec3 mean = sum / static_cast<double>(kPoints);
        for (int c = 0; c < 3; ++c) {
            const double expected = 4.0 * kPi * mean[c] * 0.5 / std::sqrt(kPi);
            EXPECT_NEAR(sky.sh()[0][c], expected, 0.01 * expected) << name << " channel " << c;
        }
    }
}

}  // namespace
}  // namespace strata
