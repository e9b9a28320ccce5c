// strata/relief/max_mip.h: the maximum mipmap the maxmip technique traverses.
#include "strata/core/error.h"
#include "strata/relief/max_mip.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace strata {
namespace {

TEST(MaxMipPyramid, EachNodeIsTheHighestPointOfItsCells) {
    // 8 x 4: non-square, so the v side reaches 1 a level before the u side.
    Image depth(8, 4, 1);
    std::mt19937 random(3);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (float& d : depth.pixels()) d = uniform(random);
    const std::vector<Image> levels = maxMipPyramid(depth);
    ASSERT_EQ(levels.size(), 4u);  // 8x4, 4x2, 2x1, 1x1
    EXPECT_EQ(levels[1].width(), 4);
    EXPECT_EQ(levels[2].height(), 1);
    EXPECT_EQ(levels[3].width(), 1);
    // Frame row y is image row H - 1 - y; cell (i, j) spans texels i..i+1, j..j+1 (wrapping).
    const auto texel = [&](int x, int y) { return depth.at(x % 8, 3 - (y % 4)); };
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 8; ++i)
            EXPECT_EQ(levels[0].at(i, j),
                      std::min({texel(i, j), texel(i + 1, j), texel(i, j + 1), texel(i + 1, j + 1)}));
    for (std::size_t k = 1; k < levels.size(); ++k)
        for (int y = 0; y < levels[k].height(); ++y)
            for (int x = 0; x < levels[k].width(); ++x) {
                const Image& below = levels[k - 1];
                float m = 2.0f;
                for (int yy = 0; yy < below.height(); ++yy)
                    for (int xx = 0; xx < below.width(); ++xx)
                        if (xx / 2 == x && std::min(yy / 2, below.height() > 1 ? yy / 2 : 0) == y)
                            m = std::min(m, below.at(xx, yy));
                EXPECT_EQ(levels[k].at(x, y), m) << "level " << k << " node " << x << ", " << y;
            }
    EXPECT_EQ(levels.back().at(0, 0), *std::min_element(depth.pixels().begin(), depth.pixels().end()));
}

TEST(MaxMipPyramid, NeedsPowerOfTwoSides) {
    EXPECT_THROW(maxMipPyramid(Image(6, 4, 1)), Error);
    EXPECT_THROW(maxMipPyramid(Image(4, 4, 2)), Error);
}

}  // namespace
}  // namespace strata
