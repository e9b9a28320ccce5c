// strata/relief/cone_map.h: conservative cone maps for whole bilinear cells, and their 16-bit quantisation.
#include "strata/core/error.h"
#include "strata/relief/cone_map.h"
#include "strata/relief/patterns.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace strata {
namespace {

// The depth surface in max_mip.h's frame: frame point (x, y), texel centres at integers, frame row y is
// image row H - 1 - y; bilinear with wrap-around (CONVENTIONS §1). Written here independently of the
// generator so that the tests check its frame rather than share it.
double frameDepth(const Image& depth, double x, double y) {
    const int width = depth.width(), height = depth.height();
    const double fx = std::floor(x), fy = std::floor(y);
    const double s = x - fx, t = y - fy;
    const int i = static_cast<int>(fx), j = static_cast<int>(fy);
    const auto texel = [&](int a, int b) {
        return static_cast<double>(depth.at(Image::wrap(a, width), height - 1 - Image::wrap(b, height)));
    };
    return (1 - s) * (1 - t) * texel(i, j) + s * (1 - t) * texel(i + 1, j) + (1 - s) * t * texel(i, j + 1) +
           s * t * texel(i + 1, j + 1);
}

Image randomMap(int width, int height, unsigned seed) {
    Image depth(width, height, 1);
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (float& d : depth.pixels()) d = uniform(random);
    return depth;
}

// A smooth, tileable map: a sum of sines with whole periods across the tile, in [0, 1].
Image sinesMap(int width, int height) {
    Image depth(width, height, 1);
    constexpr double kTwoPi = 2.0 * std::numbers::pi;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double u = (x + 0.5) / width, v = (y + 0.5) / height;
            const double s =
                std::sin(kTwoPi * u) * std::cos(kTwoPi * v) + 0.5 * std::sin(kTwoPi * (2 * u + v));
            depth.at(x, y) = static_cast<float>(0.5 + s / 3.0);
        }
    return depth;
}

// Dense samples of the surface, on a grid of `perTexel` points per texel along each axis (frame coordinates
// k / perTexel), for the brute-force checks.
struct Samples {
    int perTexel = 0;
    int countX = 0;
    int countY = 0;
    std::vector<double> depth;
};

Samples sampleSurface(const Image& depth, int perTexel) {
    Samples samples;
    samples.perTexel = perTexel;
    samples.countX = depth.width() * perTexel;
    samples.countY = depth.height() * perTexel;
    for (int b = 0; b < samples.countY; ++b)
        for (int a = 0; a < samples.countX; ++a)
            samples.depth.push_back(
                frameDepth(depth, static_cast<double>(a) / perTexel, static_cast<double>(b) / perTexel));
    return samples;
}

// For one cell: checks (*) of cone_map.h at a 5 x 5 grid of apexes over the closed cell against every
// sample, and returns the brute-force cone, min |y - x| / (d(x) - d(y)) over those pairs (capped): an upper
// bound of the true cone, since the true one is a minimum over more points.
struct CellCheck {
    double brute = 0.0;
    double worstViolation = 0.0;  // the largest d(x) - |y - x| / c - d(y) found; <= 0 when conservative
};

CellCheck checkCell(const Image& depth, const Samples& samples, int i, int j, double ratio, double maxRatio) {
    const double width = depth.width(), height = depth.height();
    CellCheck check;
    check.brute = maxRatio;
    check.worstViolation = -1e30;
    for (int b = 0; b <= 4; ++b)
        for (int a = 0; a <= 4; ++a) {
            const double x = i + a / 4.0, y = j + b / 4.0;
            const double apex = frameDepth(depth, x, y);
            for (int sy = 0; sy < samples.countY; ++sy) {
                // The nearest copy on the torus, per axis.
                double dy = std::fabs(static_cast<double>(sy) / samples.perTexel - y);
                dy = std::fmod(dy, height);
                dy = std::min(dy, height - dy);
                const double* row = samples.depth.data() + static_cast<std::size_t>(sy) * samples.countX;
                for (int sx = 0; sx < samples.countX; ++sx) {
                    const double rise = apex - row[sx];
                    if (rise <= 0.0) continue;
                    double dx = std::fabs(static_cast<double>(sx) / samples.perTexel - x);
                    dx = std::fmod(dx, width);
                    dx = std::min(dx, width - dx);
                    const double distance = std::sqrt(dx * dx + dy * dy);
                    check.brute = std::min(check.brute, distance / rise);
                    check.worstViolation = std::max(check.worstViolation, rise - distance / ratio);
                }
            }
        }
    return check;
}

struct Tightness {
    double mean = 0.0;
    double median = 0.0;
    double worst = 0.0;
};

// Runs the conservativeness check over every cell of a map (or every `stride`-th cell), and returns the
// ratio generated / brute force over them.
Tightness checkMap(const Image& depth, const ConeMapOptions& options, const std::string& name,
                   int stride = 1) {
    const Image cones = coneMap(depth, options);
    const double maxRatio = coneMapMaxRatio(depth, options);
    EXPECT_EQ(cones.width(), depth.width());
    EXPECT_EQ(cones.height(), depth.height());
    EXPECT_EQ(cones.channels(), 1);
    const Samples samples = sampleSurface(depth, 4);
    std::vector<double> factors;
    int index = 0;
    for (int j = 0; j < depth.height(); ++j)
        for (int i = 0; i < depth.width(); ++i) {
            if (index++ % stride != 0) continue;
            const double ratio = cones.at(i, j);
            EXPECT_GE(ratio, 0.0) << name << " cell " << i << ", " << j;
            EXPECT_LE(ratio, maxRatio) << name << " cell " << i << ", " << j;
            const CellCheck check = checkCell(depth, samples, i, j, ratio, maxRatio);
            // 1e-5: the float rounding of the stored ratio and of bilinear interpolation in float (the
            // generator works in float; depths here are doubles), far below any relief a tracer resolves.
            EXPECT_LE(check.worstViolation, 1e-5) << name << " cell " << i << ", " << j << ": ratio " << ratio
                                                  << ", brute-force cone " << check.brute;
            factors.push_back(ratio / check.brute);
        }
    std::sort(factors.begin(), factors.end());
    Tightness tightness;
    for (double f : factors) tightness.mean += f;
    tightness.mean /= static_cast<double>(factors.size());
    tightness.median = factors[factors.size() / 2];
    tightness.worst = factors.front();
    std::printf("[ tightness ] %-22s generated / brute force: mean %.3f, median %.3f, min %.3f\n",
                name.c_str(), tightness.mean, tightness.median, tightness.worst);
    return tightness;
}

TEST(ConeMap, ConservativeAndTightOnRandomMaps) {
    // Uniform random depths: every cell is steep, the hardest case for the near bound.
    const Tightness square = checkMap(randomMap(24, 16, 7), {}, "random 24x16");
    const Tightness odd = checkMap(randomMap(7, 5, 11), {}, "random 7x5");
    const Tightness thin = checkMap(randomMap(3, 10, 5), {}, "random 3x10");
    // Measured: mean 0.67 / 0.71 / 0.72, median 0.71 / 0.74 / 0.75 (random 24x16, 7x5, 3x10). The thresholds
    // sit a little below, so that a generator that became much looser fails. Here the near bound (the
    // steepest slope within one cell) decides, and it cannot know in which direction the slope climbs.
    for (const Tightness& t : {square, odd, thin}) {
        EXPECT_GT(t.mean, 0.6);
        EXPECT_GT(t.median, 0.6);
    }
}

TEST(ConeMap, ConservativeAndTightOnSmoothMaps) {
    const Tightness square = checkMap(sinesMap(24, 16), {}, "sines 24x16");
    const Tightness odd = checkMap(sinesMap(10, 6), {}, "sines 10x6");
    // Measured: mean 0.73 / 0.74, median 0.71 / 0.83. Smooth slopes are where the cell-to-cell far bound is
    // loosest (about R / (R + 2) of the truth at radius R); with R = 1 alone the mean was 0.42. The
    // thresholds sit a little below.
    for (const Tightness& t : {square, odd}) {
        EXPECT_GT(t.mean, 0.65);
        EXPECT_GT(t.median, 0.65);
    }
}

TEST(ConeMap, ConservativeWithFewLevelsAndACap) {
    // One band (every cell's far term uses the map's highest point) and a cap below the natural cones.
    ConeMapOptions one;
    one.depthLevels = 1;
    checkMap(randomMap(12, 8, 3), one, "random 12x8, K = 1");
    checkMap(sinesMap(12, 8), one, "sines 12x8, K = 1");
    ConeMapOptions capped;
    capped.maxRatio = 0.5f;
    checkMap(sinesMap(12, 8), capped, "sines 12x8, cap 0.5");
    EXPECT_EQ(coneMapMaxRatio(sinesMap(12, 8), capped), 0.5f);
}

TEST(ConeMap, ConservativeOnAPattern) {
    // A built-in pattern at its smallest size: flat tops, sharp edges, grooves. Every 17th cell (241 of
    // 4096) keeps the brute force to a second.
    const Image depth = makePattern("stone-bricks", {64, 1, 0.08}).depth;
    const Tightness t = checkMap(depth, {}, "stone-bricks 64x64", 17);
    // Measured: mean 0.54, median 0.58. The loosest cells (0.05) lie on gentle ground beside a steep drop
    // into a groove: the near bound takes the drop's slope although it descends, away from any relief
    // above the apex. The threshold sits a little below the mean.
    EXPECT_GT(t.mean, 0.5);
}

TEST(ConeMap, FlatMapGetsTheCap) {
    // A depth between two of the K = 64 levels, so that no level boundary helps.
    const Image depth(12, 8, 1, 0.37f);
    const Image cones = coneMap(depth);
    ASSERT_EQ(coneMapMaxRatio(depth, {}), 12.0f);  // max(W, H)
    for (const float c : cones.pixels()) EXPECT_EQ(c, 12.0f);
    ConeMapOptions options;
    options.maxRatio = 5.0f;
    const Image capped = coneMap(depth, options);
    for (const float c : capped.pixels()) EXPECT_EQ(c, 5.0f);
}

TEST(ConeMap, LonePitIsExact) {
    // A flat top (depth 0) with one texel at the bottom (depth 1), at image (3, 2) = frame (3, 4) of 9x7.
    // Apexes in the four cells around it: along a diagonal from the pit, d = (1 - t)^2, whose slope at the
    // pit is sqrt(2) per texel, and no point of the surface is steeper, so the true cone is 1 / sqrt(2);
    // the near bound (the corner gradient (1, 1)) gives exactly that. Every other cell lies on the top
    // (its deepest corner is 0): nothing is above it, so it gets the cap.
    Image depth(9, 7, 1, 0.0f);
    depth.at(3, 2) = 1.0f;
    const Image cones = coneMap(depth);
    for (int j = 0; j < 7; ++j)
        for (int i = 0; i < 9; ++i) {
            const bool around = (i == 2 || i == 3) && (j == 3 || j == 4);
            // 2e-6 relative: the generator's 1e-6 rounding margin and float rounding.
            if (around)
                EXPECT_NEAR(cones.at(i, j), 1.0 / std::numbers::sqrt2, 2e-6) << i << ", " << j;
            else
                EXPECT_EQ(cones.at(i, j), 9.0f) << i << ", " << j;
        }
}

TEST(ConeMap, LoneSpikeFollowsTheDistance) {
    // A flat bottom (depth 1) with one texel at the top (depth 0) at image (14, 3) = frame (14, 10) of 20x14.
    // The true cone of a cell is its distance to the spike's tip (the relief rises along straight lines
    // from the flat floor to the tip, so the tip is what an apex sees first), or 1 / sqrt(2) for the four
    // cells around it (as for the pit). The generator's far bound measures from the cell to the four cells
    // around the tip, as squares: D = sqrt(max(ox - 1, 0)^2 + max(oy - 1, 0)^2) with (ox, oy) the cell
    // offsets to that 2x2 block, and the cells next to the block get the near bound, 1 / sqrt(2).
    const int width = 20, height = 14, tipX = 14, tipY = height - 1 - 3;
    Image depth(width, height, 1, 1.0f);
    depth.at(14, 3) = 0.0f;
    const Image cones = coneMap(depth);
    const auto offset = [](int cell, int tip, int size) {
        // Cells tip - 1 and tip touch the tip; the offset is the torus distance to the nearer of them.
        const int a = Image::wrap(cell - (tip - 1), size), b = Image::wrap(cell - tip, size);
        return std::min({a, size - a, b, size - b});
    };
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            const int ox = offset(i, tipX, width), oy = offset(j, tipY, height);
            const double expected =
                std::max(ox, oy) <= 1
                    ? 1.0 / std::numbers::sqrt2
                    : std::min<double>(width, std::hypot(std::max(ox - 1, 0), std::max(oy - 1, 0)));
            // 2e-6 relative: the generator's 1e-6 rounding margin and float rounding.
            EXPECT_NEAR(cones.at(i, j), expected, 2e-6 * expected) << i << ", " << j;
            // The true cone: the distance from the cell to the tip (>= 1 / sqrt(2) for the cells around it).
            double tx = std::fabs(i + 0.5 - tipX), ty = std::fabs(j + 0.5 - tipY);
            tx = std::max(0.0, std::min(tx, width - tx) - 0.5);
            ty = std::max(0.0, std::min(ty, height - ty) - 0.5);
            EXPECT_LE(cones.at(i, j), std::max(std::hypot(tx, ty), 1.0 / std::numbers::sqrt2) + 1e-6);
        }
}

TEST(ConeMap, CellsAreInMaxMipFrame) {
    // One deep texel at image (5, 1) of 12x8: frame row 8 - 1 - 1 = 6, so the cells around it are (4..5,
    // 5..6). In the unflipped frame they would be rows 0..1. Everything else is the flat top: the cap.
    Image depth(12, 8, 1, 0.2f);
    depth.at(5, 1) = 0.9f;
    const Image cones = coneMap(depth);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 12; ++i) {
            const bool around = (i == 4 || i == 5) && (j == 5 || j == 6);
            if (around)
                EXPECT_LT(cones.at(i, j), 2.0f) << i << ", " << j;  // 1 / (0.7 sqrt(2)) = 1.01
            else
                EXPECT_EQ(cones.at(i, j), 12.0f) << i << ", " << j;
        }
}

TEST(ConeMap, QuantisationRoundsDown) {
    std::mt19937 random(1);
    for (const float maxRatio : {1.0f, 3.7f, 24.0f, 1024.0f, 4096.0f}) {
        std::vector<float> ratios = {0.0f, maxRatio, maxRatio * 0.5f, 1e-9f, 1e-3f * maxRatio};
        std::uniform_real_distribution<float> uniform(0.0f, maxRatio);
        for (int k = 0; k < 20000; ++k) ratios.push_back(uniform(random));
        // The decoded values themselves and their float neighbours: where rounding up would show first.
        for (int q = 1; q < 65535; q += 97) {
            const float r = decodeConeRatio(static_cast<std::uint16_t>(q), maxRatio);
            ratios.push_back(r);
            ratios.push_back(std::nextafter(r, 0.0f));
            ratios.push_back(std::nextafter(r, maxRatio));
        }
        for (const float r : ratios) {
            const std::uint16_t q = encodeConeRatio(r, maxRatio);
            const float decoded = decodeConeRatio(q, maxRatio);
            ASSERT_LE(decoded, r) << "max ratio " << maxRatio << ", q " << q;
            if (q < 65535) {
                // Within one step of the code: below the next code's value. 1e-6 of the cap allows for the
                // float rounding of that next value (a few ulps).
                ASSERT_LT(r, decodeConeRatio(static_cast<std::uint16_t>(q + 1), maxRatio) + 1e-6f * maxRatio)
                    << "max ratio " << maxRatio << ", ratio " << r << ", q " << q;
            }
        }
        EXPECT_EQ(encodeConeRatio(maxRatio, maxRatio), 65535);
        EXPECT_EQ(decodeConeRatio(65535, maxRatio), maxRatio);
        EXPECT_EQ(encodeConeRatio(2.0f * maxRatio, maxRatio), 65535);
        EXPECT_EQ(encodeConeRatio(0.0f, maxRatio), 0);
        EXPECT_EQ(encodeConeRatio(-1.0f, maxRatio), 0);
        EXPECT_EQ(encodeConeRatio(std::nanf(""), maxRatio), 0);
    }
}

void expectInvalid(const Image& depth, const ConeMapOptions& options, const std::string& mention) {
    try {
        coneMap(depth, options);
        ADD_FAILURE() << "no error; expected one mentioning \"" << mention << "\"";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(error.what()).find(mention), std::string::npos) << error.what();
    }
}

TEST(ConeMap, RejectsInvalidInput) {
    expectInvalid(Image(4, 4, 3), {}, "3 channels");
    expectInvalid(Image(), {}, "empty");
    ConeMapOptions levels;
    levels.depthLevels = 0;
    expectInvalid(Image(4, 4, 1), levels, "depth levels = 0");
    ConeMapOptions negative;
    negative.maxRatio = -1.0f;
    expectInvalid(Image(4, 4, 1), negative, "max ratio = -1");
    Image nan(4, 4, 1);
    nan.at(2, 1) = std::nanf("");
    expectInvalid(nan, {}, "(2, 1) is not finite");
}

}  // namespace
}  // namespace strata
