// The built-in procedural relief library (strata/relief/patterns.h): every pattern is normalised,
// tileable, deterministic per seed, resolution independent, and its normals follow its depth.
#include "strata/relief/patterns.h"

#include "strata/core/error.h"
#include "strata/image/image_ops.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace strata {
namespace {

const std::vector<std::string> kExpectedOrder{"base",      "fabric",      "jeans",        "metal",
                                              "cushion",   "mini-bricks", "stone-bricks", "scales",
                                              "hex-tiles", "wood-planks"};

// Patterns are generated once per (name, size, seed) and shared by the tests below.
const ReliefTexture& pattern(const std::string& name, int size, std::uint32_t seed = 1) {
    static std::map<std::tuple<std::string, int, std::uint32_t>, ReliefTexture> cache;
    const auto key = std::make_tuple(name, size, seed);
    auto it = cache.find(key);
    if (it == cache.end()) {
        PatternParams params;
        params.size = size;
        params.seed = seed;
        it = cache.emplace(key, makePattern(name, params)).first;
    }
    return it->second;
}

// Neighbour jumps of one channel along one axis: the largest inside the image, and the largest
// across the wrap-around border (last column/row to the first).
struct Jumps {
    double interior = 0.0;
    double seam = 0.0;
};

double absDiff(float a, float b) {
    return std::abs(static_cast<double>(a) - static_cast<double>(b));
}

Jumps horizontalJumps(const Image& image, int channel) {
    Jumps jumps;
    const int w = image.width();
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x + 1 < w; ++x)
            jumps.interior =
                std::max(jumps.interior, absDiff(image.at(x + 1, y, channel), image.at(x, y, channel)));
        jumps.seam = std::max(jumps.seam, absDiff(image.at(0, y, channel), image.at(w - 1, y, channel)));
    }
    return jumps;
}

Jumps verticalJumps(const Image& image, int channel) {
    Jumps jumps;
    const int h = image.height();
    for (int x = 0; x < image.width(); ++x) {
        for (int y = 0; y + 1 < h; ++y)
            jumps.interior =
                std::max(jumps.interior, absDiff(image.at(x, y + 1, channel), image.at(x, y, channel)));
        jumps.seam = std::max(jumps.seam, absDiff(image.at(x, 0, channel), image.at(x, h - 1, channel)));
    }
    return jumps;
}

// A tileable image shows no edge where it wraps: the jump from the last column to the first (and the
// last row to the first) is no larger than the largest jump between neighbours inside it. A tile
// cut out of a larger non-periodic image has a discontinuity there instead.
::testing::AssertionResult wrapsWithoutSeam(const Image& image) {
    // Float noise only: the values compared are the same floats.
    constexpr double kSlack = 1e-6;
    for (int c = 0; c < image.channels(); ++c) {
        const Jumps across = horizontalJumps(image, c);
        const Jumps down = verticalJumps(image, c);
        if (across.seam > across.interior + kSlack)
            return ::testing::AssertionFailure()
                   << "channel " << c << ": jump across the left/right border " << across.seam
                   << " > largest interior jump " << across.interior;
        if (down.seam > down.interior + kSlack)
            return ::testing::AssertionFailure() << "channel " << c << ": jump across the top/bottom border "
                                                 << down.seam << " > largest interior jump " << down.interior;
    }
    return ::testing::AssertionSuccess();
}

double meanAbsDiff(const Image& a, const Image& b) {
    EXPECT_EQ(a.pixels().size(), b.pixels().size());
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i) sum += absDiff(a.pixels()[i], b.pixels()[i]);
    return sum / static_cast<double>(a.pixels().size());
}

// The image moved by one texel to the right, with wrap-around.
Image shiftedByOneTexel(const Image& image) {
    Image out(image.width(), image.height(), image.channels());
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            for (int c = 0; c < image.channels(); ++c) out.at(x, y, c) = image.atWrapped(x - 1, y, c);
    return out;
}

// --- The list ----------------------------------------------------------------------------------------

TEST(PatternLibrary, ListsTheDocumentedPatternsInAStableOrder) {
    const auto& list = patternList();
    ASSERT_EQ(list.size(), kExpectedOrder.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
        EXPECT_EQ(list[i].name, kExpectedOrder[i]);
        EXPECT_FALSE(list[i].description.empty()) << list[i].name;
        EXPECT_EQ(list[i].description.find('\n'), std::string::npos) << list[i].name << ": one line";
        EXPECT_TRUE(isPattern(list[i].name));
    }
    EXPECT_EQ(&patternList(), &list);
}

TEST(PatternLibrary, RecognisesOnlyExactNames) {
    EXPECT_FALSE(isPattern(""));
    EXPECT_FALSE(isPattern("Fabric"));
    EXPECT_FALSE(isPattern("mini_bricks"));
    EXPECT_FALSE(isPattern("fabric "));
}

TEST(PatternLibrary, UnknownNameIsInvalidInputListingTheKnownNames) {
    try {
        makePattern("velvet");
        FAIL() << "no error";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
        const std::string message = error.what();
        EXPECT_NE(message.find("velvet"), std::string::npos) << message;
        for (const std::string& name : kExpectedOrder)
            EXPECT_NE(message.find(name), std::string::npos) << message;
    }
}

TEST(PatternLibrary, SizeOutsideTheRangeIsInvalidInputNamingTheValue) {
    for (const int size : {-5, 0, 63, 4097, 100000}) {
        PatternParams params;
        params.size = size;
        try {
            makePattern("fabric", params);
            FAIL() << "no error for size " << size;
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
            EXPECT_NE(std::string(error.what()).find(std::to_string(size)), std::string::npos)
                << error.what();
        }
    }
}

TEST(PatternLibrary, NonPositiveDepthScaleIsInvalidInput) {
    for (const double scale : {0.0, -0.1, std::nan("")}) {
        PatternParams params;
        params.size = 64;
        params.depthScale = scale;
        try {
            makePattern("metal", params);
            FAIL() << "no error for depth scale " << scale;
        } catch (const Error& error) {
            EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
        }
    }
}

TEST(PatternLibrary, AcceptsTheSmallestSizeAndOddSizes) {
    for (const int size : {kMinPatternSize, 97}) {
        PatternParams params;
        params.size = size;
        const ReliefTexture texture = makePattern("scales", params);
        EXPECT_EQ(texture.depth.width(), size);
        EXPECT_EQ(texture.depth.height(), size);
    }
}

// --- The seam check itself ---------------------------------------------------------------------------

TEST(PatternSeamCheck, FailsOnANonPeriodicRamp) {
    Image ramp(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) ramp.at(x, y) = static_cast<float>(x) / 63.0f;
    EXPECT_FALSE(wrapsWithoutSeam(ramp));
}

TEST(PatternSeamCheck, FailsOnAPatternCutShort) {
    // The left 3/4 of a tileable pattern: each column still continues smoothly into the next, but the
    // last one no longer meets the first.
    const Image& depth = pattern("base", 256).depth;
    Image cut(192, 256, 1);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 192; ++x) cut.at(x, y) = depth.at(x, y);
    EXPECT_TRUE(wrapsWithoutSeam(depth));
    EXPECT_FALSE(wrapsWithoutSeam(cut));
}

TEST(PatternSeamCheck, PassesOnAPeriodicSine) {
    Image wave(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            wave.at(x, y) =
                static_cast<float>(0.5 + 0.5 * std::sin(2.0 * 3.14159265358979 * (x + 0.5) / 64.0));
    EXPECT_TRUE(wrapsWithoutSeam(wave));
}

// --- Every pattern -----------------------------------------------------------------------------------

class PatternProperties : public ::testing::TestWithParam<std::string> {};

TEST_P(PatternProperties, DepthIsNormalisedToTheUnitRange) {
    for (const int size : {64, 256}) {
        const Image& depth = pattern(GetParam(), size).depth;
        ASSERT_EQ(depth.width(), size);
        ASSERT_EQ(depth.height(), size);
        ASSERT_EQ(depth.channels(), 1);
        const ValueRange range = valueRange(depth);
        EXPECT_GE(range.min, 0.0f) << size;
        EXPECT_LE(range.max, 1.0f) << size;
        // makePattern stretches depth to [0, 1]; 0.5 is the least the brief accepts as "using the range".
        EXPECT_GE(range.max - range.min, 0.5f) << size;
    }
}

TEST_P(PatternProperties, TilesWithoutSeam) {
    for (const int size : {64, 256}) {
        const ReliefTexture& texture = pattern(GetParam(), size);
        EXPECT_TRUE(wrapsWithoutSeam(texture.depth)) << "depth at " << size;
        EXPECT_TRUE(wrapsWithoutSeam(texture.color)) << "colour at " << size;
    }
}

TEST_P(PatternProperties, IsDeterministicForASeed) {
    PatternParams params;
    params.size = 64;
    params.seed = 7;
    const ReliefTexture a = makePattern(GetParam(), params);
    const ReliefTexture b = makePattern(GetParam(), params);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.color, b.color);
}

TEST_P(PatternProperties, DifferentSeedsGiveDifferentPatterns) {
    // Every pattern draws something from its seed (layout, per-block variation or noise), so two
    // seeds differ somewhere in depth or colour by more than float noise.
    const ReliefTexture& a = pattern(GetParam(), 64, 1);
    const ReliefTexture& b = pattern(GetParam(), 64, 2);
    EXPECT_GT(std::max(test::maxAbsDiff(a.depth, b.depth), test::maxAbsDiff(a.color, b.color)), 0.01);
}

TEST_P(PatternProperties, NormalsAreUnitAndFollowTheDepth) {
    for (const int size : {64, 256}) {
        const ReliefTexture& texture = pattern(GetParam(), size);
        ASSERT_EQ(texture.normal.channels(), 3);
        EXPECT_EQ(texture.depthScale, kDefaultDepthScale);
        EXPECT_EQ(texture.normal, normalsFromDepth(texture.depth, kDefaultDepthScale));
        double worst = 0.0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const double nx = texture.normal.at(x, y, 0);
                const double ny = texture.normal.at(x, y, 1);
                const double nz = texture.normal.at(x, y, 2);
                worst = std::max(worst, std::abs(std::sqrt(nx * nx + ny * ny + nz * nz) - 1.0));
                EXPECT_GT(nz, 0.0);
            }
        // Unit to float precision.
        EXPECT_LT(worst, 1e-5) << size;
    }
    PatternParams params;
    params.size = 64;
    params.depthScale = 0.25;
    const ReliefTexture steep = makePattern(GetParam(), params);
    EXPECT_EQ(steep.depthScale, 0.25);
    EXPECT_EQ(steep.normal, normalsFromDepth(steep.depth, 0.25));
}

TEST_P(PatternProperties, ColourIsRgbInTheUnitRange) {
    for (const int size : {64, 256}) {
        const Image& color = pattern(GetParam(), size).color;
        ASSERT_EQ(color.channels(), 3);
        ASSERT_EQ(color.width(), size);
        ASSERT_EQ(color.height(), size);
        for (int c = 0; c < 3; ++c) {
            const ValueRange range = valueRange(color, c);
            EXPECT_GE(range.min, 0.0f);
            EXPECT_LE(range.max, 1.0f);
        }
        // Not a flat fill: a colour map that follows the relief varies.
        EXPECT_GT(valueRange(luminance(color)).max - valueRange(luminance(color)).min, 0.1f);
    }
}

// Mean |difference| allowed between a pattern made small and the same pattern made larger and then
// reduced with resample()'s area average.
//  - Up to 512, makePattern box-filters each texel itself with 512 / size samples per axis, so 64 and
//    128, and 256 reduced to either, average the same sample positions per texel: only float rounding
//    (two summation orders) remains. Measured: at most 2e-8.
//  - At 1024 a texel is one point sample, at 512 too: 1024 reduced to 512 averages 4 samples where 512
//    takes one, a real difference in filtering, largest where thin features (threads, mortar edges)
//    are a few texels wide. Measured: at most 0.0061 (jeans), hence 0.0075.
// A shape that changed with resolution (feature counts following the size) differs by far more, and so
// does a misplacement by 1/64 of the tile: ResolutionCheckDetectsAOneTexelShift.
constexpr double kSameSamplesTolerance = 1e-5;
constexpr double kFilterTolerance = 0.0075;

TEST_P(PatternProperties, ShapeDoesNotDependOnResolution) {
    const Image& large = pattern(GetParam(), 256).depth;
    EXPECT_LT(meanAbsDiff(pattern(GetParam(), 128).depth, resample(large, 128, 128)), kSameSamplesTolerance);
    EXPECT_LT(meanAbsDiff(pattern(GetParam(), 64).depth, resample(large, 64, 64)), kSameSamplesTolerance);
}

TEST_P(PatternProperties, ShapeDoesNotDependOnResolutionAbove512) {
    PatternParams params;
    params.size = 1024;
    const ReliefTexture large = makePattern(GetParam(), params);
    params.size = 512;
    const ReliefTexture small = makePattern(GetParam(), params);
    EXPECT_LT(meanAbsDiff(small.depth, resample(large.depth, 512, 512)), kFilterTolerance);
}

TEST_P(PatternProperties, ResolutionCheckDetectsAOneTexelShift) {
    // Moved by 1/64 of the tile (a texel at 64), every pattern changes by more than either tolerance:
    // measured 0.016 for wood-planks (mostly flat) up to 0.2 for hex-tiles.
    const Image& small = pattern(GetParam(), 64).depth;
    const double shifted = meanAbsDiff(small, shiftedByOneTexel(small));
    EXPECT_GT(shifted, kSameSamplesTolerance);
    EXPECT_GT(shifted, kFilterTolerance);
}

std::string testName(const ::testing::TestParamInfo<std::string>& info) {
    std::string name = info.param;
    std::replace(name.begin(), name.end(), '-', '_');
    return name;
}

INSTANTIATE_TEST_SUITE_P(Patterns, PatternProperties, ::testing::ValuesIn(kExpectedOrder), testName);

}  // namespace
}  // namespace strata
