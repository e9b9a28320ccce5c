// The sRGB transfer function (strata/image/srgb.h).
#include "strata/image/srgb.h"

#include <gtest/gtest.h>

#include <cmath>

namespace strata {
namespace {

TEST(Srgb, EndsAndLinearSegmentAreExact) {
    EXPECT_EQ(srgbToLinear(0.0), 0.0);
    EXPECT_EQ(srgbToLinear(1.0), 1.0);
    EXPECT_EQ(linearToSrgb(0.0), 0.0);
    // 1.055 * 1 - 0.055 is 1 to within the rounding of the two constants in double (a few ulp).
    EXPECT_DOUBLE_EQ(linearToSrgb(1.0), 1.0);
    EXPECT_EQ(srgbToLinear(0.04), 0.04 / 12.92);
    EXPECT_EQ(linearToSrgb(0.003), 12.92 * 0.003);
}

TEST(Srgb, ClampsToTheUnitInterval) {
    EXPECT_EQ(srgbToLinear(-0.5), 0.0);
    EXPECT_EQ(srgbToLinear(2.0), 1.0);
    EXPECT_EQ(linearToSrgb(-0.5), 0.0);
    EXPECT_DOUBLE_EQ(linearToSrgb(2.0), 1.0);  // as linearToSrgb(1.0), a few ulp
}

TEST(Srgb, MidGreyAndRoundTrip) {
    // IEC 61966-2-1: code 128 / 255 is 0.21586 linear (to the 5 digits the tables give).
    EXPECT_NEAR(srgbToLinear(128.0 / 255.0), 0.21586, 5e-6);
    // The two halves invert each other; a few pow() calls in double: 1e-12.
    for (int i = 0; i <= 100; ++i) {
        const double c = i / 100.0;
        EXPECT_NEAR(linearToSrgb(srgbToLinear(c)), c, 1e-12) << c;
    }
    // The segments meet: continuous at the breakpoints to the precision of the standard's constants.
    EXPECT_NEAR(srgbToLinear(0.04045), std::pow((0.04045 + 0.055) / 1.055, 2.4), 1e-7);
    EXPECT_NEAR(linearToSrgb(0.0031308), 1.055 * std::pow(0.0031308, 1.0 / 2.4) - 0.055, 1e-7);
}

}  // namespace
}  // namespace strata
