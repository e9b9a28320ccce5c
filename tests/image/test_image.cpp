// strata::Image sampling (CONVENTIONS §1) and the operations of image_ops.h, on tiny literal images.
#include "strata/image/image.h"
#include "strata/image/image_ops.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>

namespace strata {
namespace {

double mean(const Image& image, int c = 0) {
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) sum += static_cast<double>(image.at(x, y, c));
    return sum / static_cast<double>(image.texelCount());
}

// Values chosen so that no two texels are equal and no bilinear mix coincides with a texel.
Image ramp(int width, int height, int channels = 1) {
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                image.at(x, y, c) =
                    static_cast<float>(1 + x + 10 * y + 100 * c) + 0.125f * static_cast<float>(x * y);
    return image;
}

TEST(ImageSample, TexelCentresReturnTexelsExactly) {
    const Image image = ramp(5, 3, 2);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            for (int c = 0; c < 2; ++c)
                EXPECT_EQ(image.sample(image.texelU(x), image.texelV(y), c), image.at(x, y, c));
}

TEST(ImageSample, TexelCentreFormulaMatchesTheConvention) {
    const Image image(4, 2, 1);
    EXPECT_DOUBLE_EQ(image.texelU(0), 0.125);
    EXPECT_DOUBLE_EQ(image.texelU(3), 0.875);
    EXPECT_DOUBLE_EQ(image.texelV(0), 0.75);  // row 0 is the top: v near 1
    EXPECT_DOUBLE_EQ(image.texelV(1), 0.25);
}

TEST(ImageSample, RowZeroIsNearVOne) {
    Image image(1, 2, 1);
    image.at(0, 0) = 7.0f;  // top row
    image.at(0, 1) = 3.0f;
    EXPECT_EQ(image.sample(0.5, 0.75), 7.0f);
    EXPECT_EQ(image.sample(0.5, 0.25), 3.0f);
    // Halfway between the two centres, and across the v = 0 / v = 1 seam (wrap), the mean of both.
    EXPECT_EQ(image.sample(0.5, 0.5), 5.0f);
    EXPECT_EQ(image.sample(0.5, 0.0), 5.0f);
    EXPECT_EQ(image.sample(0.5, 1.0), 5.0f);
}

TEST(ImageSample, WrapsAroundInBothDirections) {
    const Image image = ramp(4, 3);
    for (double u : {0.1, 0.25, 0.4, 0.93})
        for (double v : {0.05, 0.5, 0.77}) {
            const float base = image.sample(u, v);
            // Shifts by whole tiles; the tolerance covers the rounding of u + k in double.
            EXPECT_NEAR(image.sample(u + 1.0, v), base, 1e-4);
            EXPECT_NEAR(image.sample(u - 1.0, v), base, 1e-4);
            EXPECT_NEAR(image.sample(u - 3.0, v + 2.0), base, 1e-4);
            EXPECT_NEAR(image.sample(u, v - 1.0), base, 1e-4);
        }
    // Exactly representable shifts land on texel centres exactly.
    EXPECT_EQ(image.sample(1.125, image.texelV(1)), image.at(0, 1));
    EXPECT_EQ(image.sample(-0.875, image.texelV(1)), image.at(0, 1));
    EXPECT_EQ(image.sample(1.25, 0.5), image.sample(0.25, 0.5));
}

TEST(ImageSample, NegativeUBlendsAcrossTheSeam) {
    Image image(4, 1, 1);
    image.at(0, 0) = 2.0f;
    image.at(3, 0) = 6.0f;
    // u = 0 is halfway between the last texel's centre (0.875 - 1) and the first's (0.125).
    EXPECT_EQ(image.sample(0.0, 0.5), 4.0f);
    // u = -0.125 is the last texel's centre.
    EXPECT_EQ(image.sample(-0.125, 0.5), 6.0f);
}

TEST(ImageSample, BilinearMidpointIsTheMeanOfNeighbours) {
    const Image image = ramp(4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const int x1 = (x + 1) % 4;
            const double u = (x + 1.0) / 4.0;  // between the centres of x and x + 1 (wrapping at x = 3)
            EXPECT_FLOAT_EQ(image.sample(u, image.texelV(y)), 0.5f * (image.at(x, y) + image.at(x1, y)));
        }
    // The centre of four texels is their mean.
    const float four = 0.25f * (image.at(1, 1) + image.at(2, 1) + image.at(1, 2) + image.at(2, 2));
    EXPECT_FLOAT_EQ(image.sample(0.5, 0.5), four);
}

TEST(ImageSample, AllChannelsAtOnceMatchOneByOne) {
    const Image image = ramp(3, 3, 4);
    float all[4];
    image.sample(0.37, 0.61, all);
    for (int c = 0; c < 4; ++c) EXPECT_EQ(all[c], image.sample(0.37, 0.61, c));
}

TEST(ImageBasics, WrappedAccessAndFill) {
    const Image filled(3, 2, 2, 0.5f);
    for (float v : filled.pixels()) EXPECT_EQ(v, 0.5f);
    const Image image = ramp(3, 2);
    EXPECT_EQ(image.atWrapped(-1, 0), image.at(2, 0));
    EXPECT_EQ(image.atWrapped(3, -1), image.at(0, 1));
    EXPECT_EQ(image.atWrapped(7, 5), image.at(1, 1));
    EXPECT_EQ(Image::wrap(-4, 3), 2);
}

TEST(Resample, MagnifyMatchesSamplingAtNewCentres) {
    const Image image = ramp(4, 4, 2);
    const Image big = resample(image, 8, 8);
    ASSERT_EQ(big.width(), 8);
    ASSERT_EQ(big.channels(), 2);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 2; ++c)
                // Separable vs. direct bilinear differ only by float rounding (values up to ~140).
                EXPECT_NEAR(big.at(x, y, c), image.sample(big.texelU(x), big.texelV(y), c), 1e-4);
}

TEST(Resample, MinifyPreservesTheMean) {
    const Image image = ramp(8, 8);
    const Image half = resample(image, 4, 4);
    // Exact box weights sum to 1; 1e-6 relative to values of ~100 covers float accumulation.
    EXPECT_NEAR(mean(half), mean(image), 1e-6 * 100);
    // 8 -> 4 is a plain 2x2 average.
    EXPECT_FLOAT_EQ(half.at(1, 2),
                    0.25f * (image.at(2, 4) + image.at(3, 4) + image.at(2, 5) + image.at(3, 5)));

    Image unit(9, 9, 1);
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 9; ++x)
            unit.at(x, y) = static_cast<float>(std::fmod(0.37 * x + 0.61 * y * y, 1.0));
    const Image odd = resample(unit, 4, 4);  // 9 -> 4: footprints of 2.25 texels, non-integer
    EXPECT_NEAR(mean(odd), mean(unit), 1e-6);
    const Image oddWide = resample(unit, 4, 9);  // one axis only
    EXPECT_NEAR(mean(oddWide), mean(unit), 1e-6);
}

TEST(Resample, MinifyOfAConstantIsConstant) {
    const Image flat(9, 7, 3, 0.3f);
    const Image small = resample(flat, 4, 2);
    for (float v : small.pixels()) EXPECT_NEAR(v, 0.3f, 1e-6);
    const Image same = resample(flat, 9, 7);
    EXPECT_EQ(same, flat);
}

TEST(MipPyramid, LevelSizesAndMeans) {
    const Image image = ramp(8, 4);
    const std::vector<Image> levels = buildMipPyramid(image);
    ASSERT_EQ(levels.size(), 4u);
    const int sizes[4][2] = {{8, 4}, {4, 2}, {2, 1}, {1, 1}};
    for (std::size_t i = 0; i < levels.size(); ++i) {
        EXPECT_EQ(levels[i].width(), sizes[i][0]);
        EXPECT_EQ(levels[i].height(), sizes[i][1]);
        // Values are ~1..40; 1e-5 relative covers the float sums of three box levels.
        EXPECT_NEAR(mean(levels[i]), mean(levels[0]), 1e-5 * 40) << "level " << i;
    }
    EXPECT_EQ(levels[0], image);

    const std::vector<Image> odd = buildMipPyramid(Image(5, 3, 1, 0.5f));  // 5x3 -> 2x1 -> 1x1
    ASSERT_EQ(odd.size(), 3u);
    EXPECT_EQ(odd[1].width(), 2);
    EXPECT_EQ(odd[1].height(), 1);
    EXPECT_NEAR(odd[2].at(0, 0), 0.5f, 1e-6);
}

TEST(GaussianBlur, PreservesTheMeanAndWrapsAround) {
    Image oneHot(8, 8, 1);
    oneHot.at(0, 0) = 1.0f;
    const Image blurred = gaussianBlur(oneHot, 1.0);
    // The kernel is renormalised, so the total is kept (float sums: 1e-6).
    EXPECT_NEAR(mean(blurred), mean(oneHot), 1e-6);
    // The corner texel's neighbours across both seams get weight: the opposite corner (7, 7) is a
    // diagonal neighbour through the wrap, equal to the in-image diagonal (1, 1).
    EXPECT_GT(blurred.at(7, 7), 0.01f);
    EXPECT_FLOAT_EQ(blurred.at(7, 7), blurred.at(1, 1));
    EXPECT_FLOAT_EQ(blurred.at(7, 0), blurred.at(1, 0));
    EXPECT_FLOAT_EQ(blurred.at(0, 7), blurred.at(0, 1));
    EXPECT_LT(blurred.at(0, 0), 1.0f);
    // sigma <= 0 is a copy.
    EXPECT_EQ(gaussianBlur(oneHot, 0.0), oneHot);
}

TEST(ImageOps, LuminanceAndChannels) {
    Image rgb(1, 1, 3);
    rgb.at(0, 0, 0) = 1.0f;
    rgb.at(0, 0, 1) = 0.5f;
    rgb.at(0, 0, 2) = 0.25f;
    EXPECT_FLOAT_EQ(luminance(rgb).at(0, 0), 0.2126f + 0.7152f * 0.5f + 0.0722f * 0.25f);
    EXPECT_EQ(extractChannel(rgb, 2).at(0, 0), 0.25f);
    const ValueRange range = valueRange(ramp(3, 3));
    EXPECT_EQ(range.min, 1.0f);
    EXPECT_EQ(range.max, ramp(3, 3).at(2, 2));
    const Image unit = normalizeToUnit(ramp(3, 3));
    EXPECT_EQ(valueRange(unit).min, 0.0f);
    EXPECT_EQ(valueRange(unit).max, 1.0f);
    EXPECT_EQ(normalizeToUnit(Image(2, 2, 1, 3.0f), 0.25f).at(1, 1), 0.25f);
}

}  // namespace
}  // namespace strata
