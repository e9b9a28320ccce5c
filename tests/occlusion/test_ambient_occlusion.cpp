// Texture-space AO (meta-relief paper, Section IV): the horizon search against closed-form horizons,
// the paper's polygon against the cosine-weighted sum, the rescale formulas, 8-bit horizons, layer
// combination, the filter, and the shared GLSL header compiled by glslangValidator.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/relief/patterns.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

// d(x) = |x - 32| / 32 for texel columns x = 0..63, constant along v: a triangle wave of period one
// tile, ridges (d = 0) at column 32, valley (d = 1) at column 0. Its kinks lie on texel centres, so the
// bilinear reconstruction is exactly the continuous triangle wave: the closed-form horizons below are
// the horizons of the very surface the search samples.
Image triangleWave(int height) {
    Image depth(64, height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < 64; ++x) depth.at(x, y) = static_cast<float>(std::abs(x - 32)) / 32.0f;
    return depth;
}

// Closed-form tan(h) of the triangle wave at the valley column 0 (d0 = 1) for direction cosine c = cos phi,
// depth scale s, R = 1: the wall rises 2 depth units per tile along u, 2 |c| along the direction,
// so every sample up to the ridge (t = 0.5 / |c|) sees the same elevation and beyond it the ground falls.
double tanValley(double c, double s) {
    return 2.0 * s * std::abs(c);
}

// The same at column 16 (d0 = 0.5, half way up the wall), R = 1. Towards +u (c > 0) the wall rises
// to the ridge at column 32: tan = 2 s c. Towards -u the ground falls to the valley (column 0, distance
// 16 / (64 |c|)) and rises to the next ridge at column -32, reached at t = 0.75 / |c|:
//   tan(t) = s (2 |c| - 1 / t) on that wall, largest at the ridge if it is within R (|c| >= 0.75):
//   s (2 |c| - 4 |c| / 3) = (2/3) s |c|; else at t = R = 1: s (2 |c| - 1), clamped at 0.
double tanMidWall(double c, double s) {
    if (c >= 0.0) return 2.0 * s * c;
    const double a = -c;
    if (a >= 0.75) return 2.0 / 3.0 * s * a;
    return std::max(0.0, s * (2.0 * a - 1.0));
}

double cosineWeightedAo(int m, double s, double (*tanOf)(double, double)) {
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
        const double t = tanOf(std::cos(2.0 * kPi * i / m), s);
        sum += 1.0 / (1.0 + t * t);
    }
    return sum / m;
}

AoParams paramsFor(AoMethod method, double depthScale, int directions = 50) {
    AoParams params;
    params.method = method;
    params.depthScale = depthScale;
    params.directions = directions;
    params.filter = AoFilter::None;
    return params;
}

TEST(AmbientOcclusion, FlatReliefIsFullyOpen) {
    const Image flat(16, 16, 1, 0.5f);
    const Image brute = bakeAo(flat, paramsFor(AoMethod::Brute, 0.3));
    AoParams paper = paramsFor(AoMethod::Paper, 0.3);
    paper.filter = AoFilter::Paper;  // nothing is occluded, so the filter must change nothing
    const Image open = bakeAo(flat, paper);
    paper.normalize = AoNormalize::Paper;
    const Image paperNorm = bakeAo(flat, paper);
    // The paper divides the open M-gon's area by pi: (M/2) sin(2 pi / M) / pi.
    const double openPaper = 25.0 * std::sin(2.0 * kPi / 50.0) / kPi;
    EXPECT_NEAR(openPaper, 0.99737, 5e-6);  // the value quoted in docs/occlusion.md, to its 5 digits
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            EXPECT_EQ(brute.at(x, y), 1.0f);  // exact: every term is 1 / (1 + 0)
            EXPECT_EQ(open.at(x, y), 1.0f);   // exact: sum of M ones times 1/M
            // float rounding of a double product of 0.997...: half an ulp of 1
            EXPECT_NEAR(paperNorm.at(x, y), openPaper, 6e-8);
        }
    EXPECT_DOUBLE_EQ(polygonOpenValue(50, AoNormalize::Paper), openPaper);
    EXPECT_EQ(polygonOpenValue(50, AoNormalize::Open), 1.0);
}

TEST(AmbientOcclusion, TriangleWaveHorizonsMatchClosedForm) {
    const double s = 0.5;
    const Image depth = triangleWave(8);
    const HorizonMap horizons = computeHorizons(depth, paramsFor(AoMethod::Brute, s));
    AoParams texelByTexel = paramsFor(AoMethod::Brute, s);
    texelByTexel.marchStep = 1.0;
    const HorizonMap marched = computeHorizons(depth, texelByTexel);
    ASSERT_EQ(horizons.directions, 50);
    for (int i = 0; i < 50; ++i) {
        const double c = std::cos(2.0 * kPi * i / 50);
        // The exact walk visits the ridge wherever it falls: float rounding only.
        EXPECT_NEAR(horizons.texel(0, 3)[static_cast<std::size_t>(i)], tanValley(c, s), 1e-5) << i;
        EXPECT_NEAR(horizons.texel(16, 3)[static_cast<std::size_t>(i)], tanMidWall(c, s), 1e-5) << i;
        // Marching texel by texel, the ridge at -u can fall between two samples. Both sides of it slope
        // 1/32 depth per texel of u and a step moves |c| texels along u, so the missed height is at most
        // s |c| / 32 at distance t >= 0.75 / |c|: an error in tan(h) of at most s c^2 / 24.
        const double bound = s * c * c / 24.0 + 1e-6;
        const double got = marched.texel(16, 3)[static_cast<std::size_t>(i)];
        EXPECT_LE(got, tanMidWall(c, s) + 1e-6) << i;  // a sample never sees above the true horizon
        EXPECT_GE(got, tanMidWall(c, s) - bound) << i;
    }
}

TEST(AmbientOcclusion, TriangleWaveAoMatchesClosedForm) {
    const double s = 0.5;
    const Image depth = triangleWave(8);
    const Image brute = bakeAo(depth, paramsFor(AoMethod::Brute, s));
    const double valley = cosineWeightedAo(50, s, tanValley);
    const double mid = cosineWeightedAo(50, s, tanMidWall);
    // Same M on both sides and an exact search: float rounding only.
    EXPECT_NEAR(brute.at(0, 5), valley, 1e-6);
    EXPECT_NEAR(brute.at(16, 5), mid, 1e-6);
    AoParams marched = paramsFor(AoMethod::Brute, s);
    marched.marchStep = 1.0;  // texel by texel misses the ridge between samples: within 0.002
    EXPECT_NEAR(bakeAo(depth, marched).at(16, 5), mid, 0.002);
    marched.marchStep = 0.125;  // 8 samples per texel: the peak miss shrinks 8x
    EXPECT_NEAR(bakeAo(depth, marched).at(16, 5), mid, 0.0003);

    // The azimuth discretisation: M = 50 against the continuous integral (M = 20000), for the record.
    const double continuousValley = cosineWeightedAo(20000, s, tanValley);
    const double continuousMid = cosineWeightedAo(20000, s, tanMidWall);
    std::cout << "triangle wave S=0.5: valley AO(M=50) " << valley << " continuous " << continuousValley
              << "; mid-wall AO(M=50) " << mid << " continuous " << continuousMid << " brute "
              << brute.at(16, 5) << "\n";
    // Smooth in phi at the valley: the M-point rule is spectrally accurate there.
    EXPECT_NEAR(valley, continuousValley, 1e-9);
    // The mid-wall horizon has kinks in phi (|c| = 0.5, 0.75, c = 0): O(1/M^2) error, well below 1e-3.
    EXPECT_NEAR(mid, continuousMid, 1e-3);

    // The polygon from the closed-form horizons, open normalisation: (1/M) sum cos h_i cos h_i+1.
    const Image polygon = polygonAo(computeHorizons(depth, paramsFor(AoMethod::Brute, s)), AoNormalize::Open);
    double expected = 0.0;
    for (int i = 0; i < 50; ++i) {
        const double t0 = tanValley(std::cos(2.0 * kPi * i / 50), s);
        const double t1 = tanValley(std::cos(2.0 * kPi * (i + 1) / 50), s);
        expected += 1.0 / std::sqrt((1.0 + t0 * t0) * (1.0 + t1 * t1));
    }
    EXPECT_NEAR(polygon.at(0, 2), expected / 50.0, 1e-6);  // exact horizons: float rounding only
}

TEST(AmbientOcclusion, PolygonIsCosineWeightedMinusHalfTheSquaredJumps) {
    // (1/M) sum c_i^2 - (1/M) sum c_i c_(i+1) = (1/(2M)) sum (c_i - c_(i+1))^2 with c_i = cos h_i:
    // the paper's polygon (open normalisation) is never brighter than the cosine-weighted sum.
    PatternParams pattern;
    pattern.size = 64;
    const Image depth = makePattern("stone-bricks", pattern).depth;
    const HorizonMap horizons = computeHorizons(depth, paramsFor(AoMethod::Brute, 0.08));
    const Image brute = horizons.ao();
    const Image polygon = polygonAo(horizons, AoNormalize::Open);
    const Image paper = polygonAo(horizons, AoNormalize::Paper);
    const double ratio = polygonOpenValue(50, AoNormalize::Paper);
    double largestGap = 0.0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const auto tans = horizons.texel(x, y);
            double jumps = 0.0;
            for (std::size_t i = 0; i < 50; ++i) {
                const double c0 = 1.0 / std::sqrt(1.0 + static_cast<double>(tans[i] * tans[i]));
                const double c1 =
                    1.0 / std::sqrt(1.0 + static_cast<double>(tans[(i + 1) % 50] * tans[(i + 1) % 50]));
                jumps += (c0 - c1) * (c0 - c1);
            }
            // float storage of two values near 1: a few ulps
            EXPECT_NEAR(brute.at(x, y) - polygon.at(x, y), jumps / 100.0, 3e-7);
            EXPECT_LE(polygon.at(x, y), brute.at(x, y) + 1e-7f);
            EXPECT_NEAR(paper.at(x, y), static_cast<double>(polygon.at(x, y)) * ratio,
                        2e-7);  // the two normalisations differ by a constant
            largestGap = std::max(largestGap, static_cast<double>(brute.at(x, y) - polygon.at(x, y)));
        }
    std::cout << "stone-bricks 64^2: largest brute - polygon(open) = " << largestGap << "\n";
}

TEST(AmbientOcclusion, DirectionsFollowTheUvConvention) {
    // A raised ridge (d = 0) along v on column 20 of deep ground (d = 1). From column 16 it lies at +u,
    // so only directions with cos phi > 0 see a horizon. The same with a ridge on row 10 and a texel on
    // row 14: the ridge is at +v (v is up: a smaller row index), so only sin phi > 0 sees it.
    Image columnRidge(32, 32, 1, 1.0f);
    Image rowRidge(32, 32, 1, 1.0f);
    for (int i = 0; i < 32; ++i) {
        columnRidge.at(20, i) = 0.0f;
        rowRidge.at(i, 10) = 0.0f;
    }
    AoParams params = paramsFor(AoMethod::Brute, 0.1, 8);
    params.radius =
        0.25;  // 8 texels: the wrapped copy of the ridge (28 texels the other way) is out of reach
    const HorizonMap a = computeHorizons(columnRidge, params);
    const HorizonMap b = computeHorizons(rowRidge, params);
    for (std::size_t i = 0; i < 8; ++i) {
        const double phi = 2.0 * kPi * static_cast<double>(i) / 8.0;
        EXPECT_EQ(a.texel(16, 5)[i] > 0.0f, std::cos(phi) > 1e-9) << i;
        EXPECT_EQ(b.texel(5, 14)[i] > 0.0f, std::sin(phi) > 1e-9) << i;
    }
    // Direction 0 (+u) meets the ridge 4 texels (4/32 tile) away, 1 depth unit up: tan = 0.1 / 0.125.
    EXPECT_NEAR(a.texel(16, 5)[0], 0.8, 1e-6);
    EXPECT_NEAR(b.texel(5, 14)[2], 0.8, 1e-6);  // direction 2 = +v
}

TEST(AmbientOcclusion, HorizonSearchWrapsToroidally) {
    // The ridge at column 1 seen from column 30 towards +u: 3 texels away across the tile border.
    Image depth(32, 4, 1, 1.0f);
    for (int y = 0; y < 4; ++y) depth.at(1, y) = 0.0f;
    AoParams params = paramsFor(AoMethod::Brute, 0.1, 4);
    params.radius = 0.125;  // 4 texels
    const HorizonMap horizons = computeHorizons(depth, params);
    EXPECT_NEAR(horizons.texel(30, 0)[0], 0.1 / (3.0 / 32.0), 1e-6);
    EXPECT_EQ(horizons.texel(30, 0)[2], 0.0f);  // -u: the ridge is 29 texels away, beyond R
}

TEST(AmbientOcclusion, EqSixIsIdentityAtUnitScaleAndMatchesThePaper) {
    for (float ao : {0.0f, 0.1f, 0.3f, 0.5f, 0.77f, 0.999f, 1.0f}) {
        EXPECT_EQ(rescaleAoPaper(ao, 1.0f), ao);  // exact by construction (R'^2 = 1 + 0 * H^2)
        for (float s : {0.25f, 0.5f, 2.0f, 4.0f}) {
            // A literal transcription of Eq. 4-6 in double: r = sqrt(AO), H = sqrt(1 - r^2),
            // R'^2 = (s H)^2 + r^2, AO / R'^2.
            const double r = std::sqrt(static_cast<double>(ao));
            const double h = std::sqrt(1.0 - r * r);
            const double sd = static_cast<double>(s);
            const double rPrime2 = (sd * h) * (sd * h) + r * r;
            const double expected = ao == 0.0f ? 0.0 : static_cast<double>(ao) / rPrime2;
            EXPECT_NEAR(rescaleAoPaper(ao, s), expected, 1e-6) << ao << " " << s;  // float vs double
        }
    }
    EXPECT_EQ(rescaleAoPaper(0.0f, 0.0f), 0.0f);  // the guarded 0 / 0
    // Flattened relief is open: 0.4 / (1 - (1 - 0.4)), two float roundings (EXPECT_FLOAT_EQ: 4 ulps).
    EXPECT_FLOAT_EQ(rescaleAoPaper(0.4f, 0.0f), 1.0f);
}

TEST(AmbientOcclusion, ExactRescaleEqualsBakingAtTheScaledDepth) {
    PatternParams pattern;
    pattern.size = 64;
    const Image depth = makePattern("cushion", pattern).depth;
    const double s0 = 0.08;
    const HorizonMap horizons = computeHorizons(depth, paramsFor(AoMethod::Brute, s0));
    const Image baked = bakeAo(depth, paramsFor(AoMethod::Brute, s0));
    EXPECT_EQ(test::maxAbsDiff(rescaleAoExact(horizons, 1.0), baked), 0.0);  // the same sums
    // tan h is linear in S (every elevation is S (d0 - d) / t), so 2 S gives exactly twice the tangents.
    const Image twice = bakeAo(depth, paramsFor(AoMethod::Brute, 2.0 * s0));
    EXPECT_LE(test::maxAbsDiff(rescaleAoExact(horizons, 2.0), twice), 1e-6);  // float rounding
    // The polygon rescales exactly the same way.
    const Image polygonTwice = bakeAo(depth, paramsFor(AoMethod::Paper, 2.0 * s0));
    EXPECT_LE(test::maxAbsDiff(polygonAo(horizons, AoNormalize::Open, 2.0), polygonTwice), 1e-6);
}

TEST(AmbientOcclusion, EqSixAgainstExactRescaleIsMeasured) {
    // A measurement (docs/occlusion.md has the full table), not a bound: Eq. 6 is a disc model.
    for (const char* name : {"fabric", "mini-bricks"}) {
        PatternParams pattern;
        pattern.size = 64;
        const Image depth = makePattern(name, pattern).depth;
        const HorizonMap horizons = computeHorizons(depth, paramsFor(AoMethod::Brute, 0.08));
        const Image ao = horizons.ao();
        EXPECT_EQ(test::maxAbsDiff(rescaleAoPaper(ao, 1.0), ao), 0.0);  // s = 1 is exact
        for (double s : {0.25, 0.5, 2.0, 4.0}) {
            const Image paper = rescaleAoPaper(ao, s);
            const Image exact = rescaleAoExact(horizons, s);
            double sum = 0.0;
            double largest = 0.0;
            for (std::size_t i = 0; i < paper.pixels().size(); ++i) {
                const double diff = static_cast<double>(paper.pixels()[i] - exact.pixels()[i]);
                ASSERT_TRUE(std::isfinite(diff));
                sum += diff;
                largest = std::max(largest, std::abs(diff));
            }
            std::cout << name << " s=" << s << ": Eq.6 - exact bias "
                      << sum / static_cast<double>(paper.pixels().size()) << ", max |diff| " << largest
                      << "\n";
        }
    }
}

TEST(AmbientOcclusion, EightBitHorizonsStayWithinTheirBound) {
    // Codes are monotonic and round-trip to within half a step of the angle.
    for (int code = 0; code < 255; ++code) {
        const auto c = static_cast<std::uint8_t>(code);
        EXPECT_EQ(encodeHorizon8(decodeHorizon8(c)), c);
        EXPECT_LT(decodeHorizon8(c), decodeHorizon8(static_cast<std::uint8_t>(code + 1)));
    }
    EXPECT_EQ(encodeHorizon8(0.0f), 0);
    PatternParams pattern;
    pattern.size = 64;
    const Image depth = makePattern("stone-bricks", pattern).depth;
    const HorizonMap horizons = computeHorizons(depth, paramsFor(AoMethod::Brute, 0.3));
    const HorizonMap quantized = quantizeHorizons8(horizons);
    const Image exact = horizons.ao();
    const Image coarse = quantized.ao();
    // The angle is off by at most (pi/2)/255/2 and |d cos^2 h / dh| = |sin 2h| <= 1, so each direction's
    // term, and so their mean, is off by at most pi/1020 (plus float rounding).
    const double maxError = test::maxAbsDiff(exact, coarse);
    EXPECT_LE(maxError, kPi / 1020.0 + 1e-6);
    std::cout << "8-bit horizons, stone-bricks S=0.3: max AO error " << maxError << "\n";
}

TEST(AmbientOcclusion, FilterTouchesOnlyOccludedTexels) {
    // One raised texel (d = 0) on deep flat ground (d = 1): only texels that see it are occluded.
    Image depth(16, 16, 1, 1.0f);
    depth.at(8, 8) = 0.0f;
    AoParams params = paramsFor(AoMethod::Paper, 0.2);
    params.radius = 0.125;  // 2 texels
    const HorizonMap horizons = computeHorizons(depth, params);
    const Image raw = polygonAo(horizons, AoNormalize::Open);
    params.filter = AoFilter::Auto;  // = paper for the paper method
    const Image filtered = bakeAo(depth, params);
    // The 3 x 3 Gaussian of sigma 1: weights e^0, e^-1/2, e^-1 for centre, edge and corner taps.
    const double wc = 1.0, we = std::exp(-0.5), wk = std::exp(-1.0);
    const double total = wc + 4.0 * we + 4.0 * wk;
    int changed = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            bool occluded = false;
            for (const float t : horizons.texel(x, y)) occluded = occluded || t > 0.0f;
            if (!occluded) {
                EXPECT_EQ(filtered.at(x, y), raw.at(x, y)) << x << "," << y;
                EXPECT_EQ(filtered.at(x, y), 1.0f);
                continue;
            }
            double expected = 0.0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    expected += (dx == 0 && dy == 0     ? wc
                                 : (dx == 0 || dy == 0) ? we
                                                        : wk) *
                                static_cast<double>(raw.atWrapped(x + dx, y + dy));
            EXPECT_NEAR(filtered.at(x, y), expected / total, 1e-6);  // float storage
            ++changed;
        }
    EXPECT_GT(changed, 0);
    EXPECT_LT(changed, 16 * 16 / 4);  // the raised texel is seen from a small neighbourhood only
}

TEST(AmbientOcclusion, CombineMultipliesOrTakesTheMinimum) {
    const std::vector<AoLayer> layers{{Image(8, 8, 1, 0.8f), 1.0, "a"}, {Image(4, 4, 1, 0.5f), 3.0, "b"}};
    const Image product = combineAo(layers, AoCombine::Multiply, 16);
    const Image smallest = combineAo(layers, AoCombine::Min, 16);
    for (const float v : product.pixels()) EXPECT_FLOAT_EQ(v, 0.4f);
    for (const float v : smallest.pixels()) EXPECT_EQ(v, 0.5f);
}

TEST(AmbientOcclusion, CombineSamplesEachLayerAtItsTiling) {
    Image noise(8, 8, 1);
    unsigned state = 12345u;
    for (float& value : noise.pixels()) {
        state = state * 1664525u + 1013904223u;
        value = static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
    }
    const std::vector<AoLayer> layers{{noise, 2.5, "noise"}};
    const Image out = combineAo(layers, AoCombine::Multiply, 20);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 20; ++x)
            EXPECT_EQ(out.at(x, y), noise.sample(2.5 * out.texelU(x), 2.5 * out.texelV(y)));  // same call
}

TEST(AmbientOcclusion, BadInputIsRejectedWithTheValue) {
    const Image depth(8, 8, 1, 0.0f);
    auto expectInvalid = [&](const AoParams& params, const std::string& words) {
        try {
            (void)bakeAo(depth, params);
            ADD_FAILURE() << "no error for " << words;
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
            EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
        }
    };
    AoParams p;
    p.directions = 2;
    expectInvalid(p, "directions = 2");
    p = {};
    p.radius = 0.0;
    expectInvalid(p, "radius = 0");
    p = {};
    p.depthScale = std::nan("");
    expectInvalid(p, "depth scale = nan");
    p = {};
    p.marchStep = 0.001;  // 0 is the exact walk; steps start at 1/64
    expectInvalid(p, "march step = 0.001");
    p = {};
    p.filterSigma = -1.0;
    expectInvalid(p, "filter sigma = -1");
    EXPECT_THROW((void)bakeAo(Image(4, 4, 3), AoParams{}), Error);
    EXPECT_THROW((void)combineAo(std::vector<AoLayer>{}, AoCombine::Min, 8), Error);
    EXPECT_THROW((void)combineAo(std::vector<AoLayer>{{Image(4, 4, 1), 0.0, "x"}}, AoCombine::Min, 8), Error);
    EXPECT_THROW((void)combineAo(std::vector<AoLayer>{{Image(4, 4, 1), 1.0, "x"}}, AoCombine::Min, 0), Error);
    EXPECT_EQ(parseAoMethod("paper"), AoMethod::Paper);
    EXPECT_EQ(parseAoFilter(toString(AoFilter::None)), AoFilter::None);
    EXPECT_EQ(parseAoNormalize("open"), AoNormalize::Open);
    EXPECT_EQ(parseAoCombine("min"), AoCombine::Min);
    EXPECT_EQ(parseAoMethod("sweep"), AoMethod::Sweep);
    EXPECT_THROW((void)parseAoMethod("exact"), Error);
}

TEST(AmbientOcclusion, BruteBakesAPatternAt128) {
    // The size the issue asks to stay fast; also a sanity range on real data.
    PatternParams pattern;
    pattern.size = 128;
    const Image depth = makePattern("scales", pattern).depth;
    const Image ao = bakeAo(depth, paramsFor(AoMethod::Brute, kDefaultDepthScale));
    const auto [lo, hi] = std::minmax_element(ao.pixels().begin(), ao.pixels().end());
    EXPECT_GT(*lo, 0.0f);
    EXPECT_LE(*hi, 1.0f);
    EXPECT_LT(*lo, 0.95f);  // a scaled relief has occluded places
}

TEST(AmbientOcclusion, SharedRescaleHeaderCompilesAsGlsl) {
    const std::string validator = STRATA_GLSLANG_VALIDATOR;
    if (validator.empty() || validator.find("NOTFOUND") != std::string::npos)
        FAIL() << "glslangValidator not found: install glslang-tools: scripts/install-deps.sh";
    const test::ScratchDir dir("strata_ao_glsl");
    // The header after the prelude it includes, pasted as the shader library does (strata::gl resolves
    // `#include "prelude.h"`; glslangValidator alone does not).
    std::ostringstream text;
    for (const char* name : {"prelude.h", "ao_rescale.h"}) {
        std::ifstream file(std::string(STRATA_SOURCE_DIR) + "/shaders/shared/" + name);
        ASSERT_TRUE(file.good()) << name;
        for (std::string line; std::getline(file, line);) {
            if (line != "#include \"prelude.h\"") text << line << "\n";
        }
    }
    const auto shader = dir / "ao_rescale_test.comp";
    {
        std::ofstream out(shader);
        out << "#version 450\n"
            << text.str()
            << "layout(local_size_x = 1) in;\n"
               "layout(std430, binding = 0) buffer Values { float v[]; };\n"
               "void main() { v[0] = aoRescalePaper(v[1], v[2]) * aoDirectionExact(v[3], v[2]); }\n";
    }
    const std::string command =
        "\"" + validator + "\" \"" + shader.string() + "\" > \"" + (dir / "log.txt").string() + "\" 2>&1";
    const int rc = std::system(command.c_str());
    std::ifstream log(dir / "log.txt");
    std::ostringstream output;
    output << log.rdbuf();
    EXPECT_EQ(rc, 0) << output.str();
}

}  // namespace
}  // namespace strata
