// The render-comparison metrics on hand-made uv images with known errors.
#include "strata/core/error.h"
#include "strata/image/image.h"
#include "strata/image/image_io.h"
#include "strata/trace/render_compare.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace strata {
namespace {

// A 16 x 8 uv image that hits everywhere, u, v at dyadic values (exact in float).
Image fullHitUv() {
    Image uv(16, 8, 3);
    for (int y = 0; y < uv.height(); ++y) {
        for (int x = 0; x < uv.width(); ++x) {
            uv.at(x, y, 0) = static_cast<float>((x + 0.5) / 16.0);
            uv.at(x, y, 1) = static_cast<float>(1.0 - (y + 0.5) / 8.0);
            uv.at(x, y, 2) = 1.0f;
        }
    }
    return uv;
}

// u + delta modulo 1 (the test image of a shifted render).
Image shiftedU(const Image& uv, double delta) {
    Image shifted = uv;
    for (int y = 0; y < uv.height(); ++y) {
        for (int x = 0; x < uv.width(); ++x) {
            const double u = static_cast<double>(uv.at(x, y, 0)) + delta;
            shifted.at(x, y, 0) = static_cast<float>(u - std::floor(u));
        }
    }
    return shifted;
}

TEST(RenderCompare, IdenticalImagesHaveNoError) {
    const Image uv = fullHitUv();
    const UvComparison c = compareUv(uv, uv, 256, 256);
    EXPECT_EQ(c.referenceHits, 128);
    EXPECT_EQ(c.testHits, 128);
    EXPECT_EQ(c.bothHit, 128);
    EXPECT_EQ(c.hitMismatch, 0);
    EXPECT_EQ(c.mismatchFraction, 0.0);
    EXPECT_EQ(c.p50, 0.0);
    EXPECT_EQ(c.p99, 0.0);
    EXPECT_EQ(c.max, 0.0);
    const Image diff = uvDiffImage(uv, uv, 256, 256);
    for (const float value : diff.pixels()) EXPECT_EQ(value, 0.0f);
}

TEST(RenderCompare, ShiftOfKTexelsGivesK) {
    const Image uv = fullHitUv();
    // 3 texels of a 256-wide map along u (crossing u = 1 for the last columns), and 2 texels of a 64-high
    // map along v. Every value is dyadic and exact in float, so the errors are exactly 3 and 2.
    const UvComparison alongU = compareUv(uv, shiftedU(uv, 3.0 / 256.0), 256, 64);
    EXPECT_EQ(alongU.bothHit, 128);
    EXPECT_EQ(alongU.p50, 3.0);
    EXPECT_EQ(alongU.p99, 3.0);
    EXPECT_EQ(alongU.max, 3.0);
    Image alongV = uv;
    for (int y = 0; y < uv.height(); ++y)
        for (int x = 0; x < uv.width(); ++x) {
            const double v = static_cast<double>(uv.at(x, y, 1)) - 2.0 / 64.0;
            alongV.at(x, y, 1) = static_cast<float>(v - std::floor(v));
        }
    const UvComparison c = compareUv(uv, alongV, 256, 64);
    EXPECT_EQ(c.p99, 2.0);
    EXPECT_EQ(c.max, 2.0);
    // Both: the Euclidean length sqrt(3^2 + 4^2) = 5 (4 texels of v at height 128).
    Image both = shiftedU(uv, 3.0 / 256.0);
    for (int y = 0; y < uv.height(); ++y)
        for (int x = 0; x < uv.width(); ++x) {
            const double v = static_cast<double>(uv.at(x, y, 1)) + 4.0 / 128.0;
            both.at(x, y, 1) = static_cast<float>(v - std::floor(v));
        }
    EXPECT_EQ(compareUv(uv, both, 256, 128).max, 5.0);
}

TEST(RenderCompare, PercentilesAreNearestRank) {
    // 10 x 10 hits, all exact except one pixel off by 5 texels and one by 7: sorted errors are 98 zeros,
    // 5, 7. Nearest rank: p50 = the 50th = 0, p99 = the 99th = 5, max = 7.
    Image reference(10, 10, 3, 0.5f);
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 10; ++x) reference.at(x, y, 2) = 1.0f;
    Image test = reference;
    test.at(2, 3, 0) = 0.5f + 5.0f / 64.0f;
    test.at(7, 1, 1) = 0.5f - 7.0f / 64.0f;
    const UvComparison c = compareUv(reference, test, 64, 64);
    EXPECT_EQ(c.p50, 0.0);
    EXPECT_EQ(c.p99, 5.0);
    EXPECT_EQ(c.max, 7.0);
}

TEST(RenderCompare, ErrorIsToroidal) {
    Image reference(1, 1, 3, 1.0f);
    Image test(1, 1, 3, 1.0f);
    reference.at(0, 0, 0) = 0.999f;
    test.at(0, 0, 0) = 0.001f;
    reference.at(0, 0, 1) = 0.25f;
    test.at(0, 0, 1) = 0.25f;
    const UvComparison c = compareUv(reference, test, 1000, 1000);
    // 0.002 tiles = 2 texels, not 998. The float inputs are off by up to 6e-8 tiles each, 6e-5 texels.
    EXPECT_NEAR(c.max, 2.0, 1e-4);
    // The same across v = 0 / 1.
    reference.at(0, 0, 0) = test.at(0, 0, 0) = 0.5f;
    reference.at(0, 0, 1) = 0.0f;
    test.at(0, 0, 1) = 1.0f;  // the same point: a read-back of 65535 / 65535
    EXPECT_EQ(compareUv(reference, test, 1000, 1000).max, 0.0);
}

TEST(RenderCompare, CountsHitMismatches) {
    // Reference hits the 10 pixels x < 10 of row 0; the test hits 8 of them (x = 2..9) and 3 others.
    Image reference(20, 2, 3);
    Image test(20, 2, 3);
    for (int x = 0; x < 10; ++x) reference.at(x, 0, 2) = 1.0f;
    for (int x = 2; x < 10; ++x) test.at(x, 0, 2) = 1.0f;
    for (int x = 15; x < 18; ++x) test.at(x, 1, 2) = 0.75f;  // > 0.5 is a hit
    reference.at(19, 1, 2) = 0.5f;                           // exactly 0.5 is not
    const UvComparison c = compareUv(reference, test, 8, 8);
    EXPECT_EQ(c.referenceHits, 10);
    EXPECT_EQ(c.testHits, 11);
    EXPECT_EQ(c.bothHit, 8);
    EXPECT_EQ(c.hitMismatch, 5);
    EXPECT_EQ(c.mismatchFraction, 0.5);  // 5 / 10, exact in binary
    // No reference hits: the fraction is taken over 1.
    const UvComparison none = compareUv(Image(20, 2, 3), test, 8, 8);
    EXPECT_EQ(none.hitMismatch, 11);
    EXPECT_EQ(none.mismatchFraction, 11.0);
    EXPECT_EQ(none.p99, 0.0);

    const Image diff = uvDiffImage(reference, test, 8, 8);
    EXPECT_EQ(diff.at(0, 0, 0), 1.0f);  // reference only: red
    EXPECT_EQ(diff.at(0, 0, 1), 0.0f);
    EXPECT_EQ(diff.at(0, 0, 2), 0.0f);
    EXPECT_EQ(diff.at(15, 1, 2), 1.0f);  // test only: blue
    EXPECT_EQ(diff.at(15, 1, 0), 0.0f);
    EXPECT_EQ(diff.at(5, 0, 1), 0.0f);  // both, no error: black
}

TEST(RenderCompare, DiffGreenGrowsWithErrorAndSaturates) {
    Image reference(3, 1, 3, 0.5f);
    for (int x = 0; x < 3; ++x) reference.at(x, 0, 2) = 1.0f;
    Image test = reference;
    test.at(0, 0, 0) = 0.5f + 1.0f / 64.0f;  // 1 texel
    test.at(1, 0, 0) = 0.5f + 2.0f / 64.0f;  // 2 texels
    test.at(2, 0, 0) = 0.5f + 9.0f / 64.0f;  // 9 texels: past the saturation
    const Image diff = uvDiffImage(reference, test, 64, 64, 4.0);
    // Dyadic values: exact.
    EXPECT_EQ(diff.at(0, 0, 1), 0.25f);
    EXPECT_EQ(diff.at(1, 0, 1), 0.5f);
    EXPECT_EQ(diff.at(2, 0, 1), 1.0f);
    EXPECT_EQ(diff.at(2, 0, 0), 0.0f);
    EXPECT_EQ(diff.at(2, 0, 2), 0.0f);
}

TEST(RenderCompare, ShadowAgreementOverBothHitPixels) {
    Image referenceUv(4, 1, 3);
    Image testUv(4, 1, 3);
    for (int x = 0; x < 3; ++x) referenceUv.at(x, 0, 2) = 1.0f;
    for (int x = 1; x < 4; ++x) testUv.at(x, 0, 2) = 1.0f;  // both hit at x = 1, 2
    Image referenceShadow(4, 1, 1);
    Image testShadow(4, 1, 1);
    referenceShadow.at(0, 0) = 1.0f;  // not compared: the test misses
    referenceShadow.at(1, 0) = 1.0f;
    testShadow.at(1, 0) = 0.9f;  // > 0.5: lit, agrees
    referenceShadow.at(2, 0) = 1.0f;
    testShadow.at(2, 0) = 0.2f;  // shadowed: disagrees
    const MaskAgreement a = compareShadow(referenceShadow, testShadow, referenceUv, testUv);
    EXPECT_EQ(a.compared, 2);
    EXPECT_EQ(a.agree, 1);
    EXPECT_EQ(a.fraction, 0.5);
    const MaskAgreement none = compareShadow(referenceShadow, testShadow, Image(4, 1, 3), testUv);
    EXPECT_EQ(none.compared, 0);
    EXPECT_EQ(none.fraction, 1.0);
}

TEST(RenderCompare, RejectsBadShapes) {
    const Image uv = fullHitUv();
    EXPECT_THROW(compareUv(uv, Image(16, 9, 3), 8, 8), Error);
    EXPECT_THROW(compareUv(uv, Image(16, 8, 4), 8, 8), Error);
    EXPECT_THROW(compareUv(Image(), uv, 8, 8), Error);
    EXPECT_THROW(compareUv(uv, uv, 0, 8), Error);
    EXPECT_THROW(uvDiffImage(uv, uv, 8, 8, 0.0), Error);
    EXPECT_THROW(compareShadow(Image(16, 8, 3), Image(16, 8, 1), uv, uv), Error);
    EXPECT_THROW(compareShadow(Image(16, 8, 1), Image(15, 8, 1), uv, uv), Error);
}

TEST(RenderCompare, WritesComparisonImages) {
    test::ScratchDir scratch("render-compare");
    const std::filesystem::path directory = scratch.path() / "nested" / "failures";
    const Image expected = fullHitUv();
    const Image actual = shiftedU(expected, 3.0 / 256.0);
    const Image diff = uvDiffImage(expected, actual, 256, 256);
    const auto paths = writeComparisonImages(directory, "flat", expected, actual, diff);
    ASSERT_EQ(paths.size(), 3u);
    EXPECT_EQ(paths[0], directory / "flat_expected.png");
    EXPECT_EQ(paths[1], directory / "flat_actual.png");
    EXPECT_EQ(paths[2], directory / "flat_diff.png");
    const Image* images[] = {&expected, &actual, &diff};
    for (int i = 0; i < 3; ++i) {
        const ImageInfo info = readImageInfo(paths[i]);
        EXPECT_EQ(info.bitDepth, 16);
        // 16-bit quantisation: half a step, 0.5 / 65535 = 7.6e-6.
        EXPECT_LE(test::maxAbsDiff(readImage(paths[i]), *images[i]), 0.5 / 65535.0 + 1e-9);
    }
    EXPECT_THROW(writeComparisonImages(directory, "", expected, actual, diff), Error);
    EXPECT_THROW(writeComparisonImages(directory, "a/b", expected, actual, diff), Error);
    EXPECT_THROW(writeComparisonImages(directory, "x", Image(), actual, diff), Error);
}

}  // namespace
}  // namespace strata
