// strata/image/quantize.h: the 8- and 16-bit unorm encodings of CONVENTIONS §5, correctly rounded.
#include "strata/image/quantize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace strata {
namespace {

TEST(Quantize, EndsAndClamps) {
    EXPECT_EQ(toUnorm16(0.0), 0);
    EXPECT_EQ(toUnorm16(1.0), 65535);
    EXPECT_EQ(toUnorm16(-0.5), 0);
    EXPECT_EQ(toUnorm16(7.0), 65535);
    EXPECT_EQ(toUnorm16(std::numeric_limits<double>::quiet_NaN()), 0);
    EXPECT_EQ(toUnorm8(0.5), 128);  // 127.5 rounds half up
    EXPECT_EQ(toUnorm8(1.0), 255);
    EXPECT_EQ(toUnorm8(-1.0), 0);
}

TEST(Quantize, EveryCodeRoundTrips) {
    for (int q = 0; q <= 65535; ++q) {
        const float v = static_cast<float>(q) / 65535.0f;
        ASSERT_EQ(toUnorm16(v), q) << q;
        ASSERT_EQ(quantizeUnorm16(v), v) << q;
    }
}

TEST(Quantize, RoundsTheExactProductNotAFloatOne) {
    // The float nearest 1.5 / 65535 lies just below it: its exact product with 65535 is below 1.5 (code 1),
    // but the float product rounds to 1.5 and would give code 2. Half of all codes have such a neighbour.
    const float v = 1.5f / 65535.0f;
    ASSERT_LT(static_cast<double>(v) * 65535.0, 1.5);
    ASSERT_EQ(v * 65535.0f, 1.5f);
    EXPECT_EQ(toUnorm16(v), 1);
}

}  // namespace
}  // namespace strata
