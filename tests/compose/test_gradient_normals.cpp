// A depth map's gradient stored as normals at a scale of its own (strata/compose/gradient_normals.h).
#include "strata/compose/gradient_normals.h"
#include "strata/core/error.h"
#include "strata/relief/relief_texture.h"

#include <gtest/gtest.h>

#include <cmath>

namespace strata {
namespace {

// d(u) over 4 texels of one row: 0, 0.25, 0.5, 0.25. Central differences per tile with wrap-around,
// (d[x+1] - d[x-1]) / (2 / 4), give g.x = 0, 1, 0, -1 and g.y = 0: the steepest |g| is 1.
Image ramp() {
    Image depth(4, 1, 1);
    const float values[] = {0.0f, 0.25f, 0.5f, 0.25f};
    for (int x = 0; x < 4; ++x) depth.at(x, 0) = values[x];
    return depth;
}

TEST(GradientNormals, ScaleMakesTheSteepestGradientAQuarter) {
    const Image gradient = depthGradient(ramp());
    ASSERT_NEAR(gradient.at(1, 0, 0), 1.0f, 1e-6f);  // the ramp's analytic slope, in float
    EXPECT_NEAR(gradientNormalScale(gradient), 0.25, 1e-6);
    EXPECT_EQ(gradientNormalScale(depthGradient(Image(3, 3, 1))), 1.0);  // flat: no scale to pick
}

TEST(GradientNormals, NormalsGiveTheGradientBack) {
    const GradientNormals result = gradientNormals(ramp());
    ASSERT_EQ(result.normals.channels(), 3);
    ASSERT_EQ(result.normals.width(), 4);
    const Image gradient = depthGradient(ramp());
    for (int x = 0; x < 4; ++x) {
        const double nx = result.normals.at(x, 0, 0), ny = result.normals.at(x, 0, 1);
        const double nz = result.normals.at(x, 0, 2);
        EXPECT_NEAR(std::sqrt(nx * nx + ny * ny + nz * nz), 1.0, 1e-6);  // unit, in float
        // The shader's recovery g = n.xy / (n.z S_L); float normals: 1e-6 relative to |g| <= 1.
        EXPECT_NEAR(nx / (nz * result.scale), gradient.at(x, 0, 0), 1e-6) << x;
        EXPECT_NEAR(ny / (nz * result.scale), gradient.at(x, 0, 1), 1e-6) << x;
    }
    // The steepest texel: normalize(0.25, 0, 1).
    EXPECT_NEAR(result.normals.at(1, 0, 0), 0.25 / std::sqrt(1.0625), 1e-6);
}

TEST(GradientNormals, RefuseAMapThatIsNotDepth) {
    EXPECT_THROW(gradientNormals(Image()), Error);
    EXPECT_THROW(gradientNormals(Image(2, 2, 3)), Error);
}

}  // namespace
}  // namespace strata
