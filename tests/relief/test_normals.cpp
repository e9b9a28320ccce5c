// Normals from depth (CONVENTIONS §3): against the analytic normal of a smooth field, exact cases,
// the sign convention, and the encode / decode / height paths.
#include "strata/image/image_ops.h"
#include "strata/relief/relief_texture.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

// The angle between two vectors, in radians.
double angleBetween(const double a[3], const double b[3]) {
    const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    // atan2 of |a x b| and a.b stays accurate for tiny angles, where acos(dot) loses half the digits.
    const double cx = a[1] * b[2] - a[2] * b[1];
    const double cy = a[2] * b[0] - a[0] * b[2];
    const double cz = a[0] * b[1] - a[1] * b[0];
    return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot);
}

double toDegrees(double radians) {
    return radians * 180.0 / kPi;
}

template <typename F>
Image depthFrom(int width, int height, F&& d) {
    Image depth(width, height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            depth.at(x, y) = static_cast<float>(d(depth.texelU(x), depth.texelV(y)));
    return depth;
}

TEST(NormalsFromDepth, MatchAnalyticNormalsOfASinusoid) {
    // d(u, v) = 0.5 + 0.5 sin(2 pi a u) cos(2 pi b v): integer a, b, so it tiles and central
    // differences with wrap-around see no seam.
    constexpr int kSize = 256;
    constexpr int kA = 3;
    constexpr int kB = 2;
    constexpr double kS = 0.1;
    const Image depth = depthFrom(kSize, kSize, [](double u, double v) {
        return 0.5 + 0.5 * std::sin(2.0 * kPi * kA * u) * std::cos(2.0 * kPi * kB * v);
    });
    const Image normals = normalsFromDepth(depth, kS);
    ASSERT_EQ(normals.channels(), 3);

    double sum = 0.0;
    double worst = 0.0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const double u = depth.texelU(x);
            const double v = depth.texelV(y);
            // CONVENTIONS §3: n = normalize(S dd/du, S dd/dv, 1), derivatives per tile.
            const double ddu =
                0.5 * 2.0 * kPi * kA * std::cos(2.0 * kPi * kA * u) * std::cos(2.0 * kPi * kB * v);
            const double ddv =
                -0.5 * 2.0 * kPi * kB * std::sin(2.0 * kPi * kA * u) * std::sin(2.0 * kPi * kB * v);
            const double expected[3] = {kS * ddu, kS * ddv, 1.0};
            const double actual[3] = {normals.at(x, y, 0), normals.at(x, y, 1), normals.at(x, y, 2)};
            const double angle = angleBetween(expected, actual);
            sum += angle;
            worst = std::max(worst, angle);
        }
    const double meanDegrees = toDegrees(sum / (kSize * kSize));
    const double maxDegrees = toDegrees(worst);
    RecordProperty("mean_angle_error_deg", std::to_string(meanDegrees));
    RecordProperty("max_angle_error_deg", std::to_string(maxDegrees));
    std::printf("normalsFromDepth vs analytic at %d^2, S = %.2f: mean %.5f deg, max %.5f deg\n", kSize, kS,
                meanDegrees, maxDegrees);

    // The requirement: a mean angle error below half a degree.
    EXPECT_LT(meanDegrees, 0.5);
    // The tighter bound that central differences guarantee. For a wave of angular frequency k and a
    // texel step h, the central difference is the derivative times sin(kh)/(kh): a relative error of at
    // most e = (kh)^2/6, i.e. O(h^2). Changing the slope vector p = S grad d by D tilts normalize(p, 1)
    // by at most |D| / sqrt(1 + |p|^2) (a change across p; along p it is |D| / (1 + |p|^2)), and
    // |D| <= e |p|, so no texel is off by more than e |p| / sqrt(1 + |p|^2) < e. With
    // k = 2 pi max(a, b) and h = 1/256, e = (2 pi 3 / 256)^2 / 6 = 9.0e-4 rad = 0.052 deg. Float
    // rounding of the depth (6e-8 relative, amplified by 1/(2h) = 128 and by S) adds under 1e-6 rad.
    const double kh = 2.0 * kPi * std::max(kA, kB) / kSize;
    const double maxBoundDegrees = toDegrees(kh * kh / 6.0 + 1e-6);
    EXPECT_LT(maxDegrees, maxBoundDegrees);
    // Here the error lies mostly along the slope (a and b are close), where it tilts by at most
    // e |p| / (1 + |p|^2) <= e / 2 = 0.026 deg: the worst texel measures 0.0259 deg. The mean over all
    // texels, most of them on gentler slopes, stays well below that (measured 0.016 deg).
    EXPECT_LT(meanDegrees, toDegrees(kh * kh / 12.0));
}

TEST(NormalsFromDepth, FlatDepthGivesStraightUpExactly) {
    for (const float d : {0.0f, 0.37f, 1.0f}) {
        const Image normals = normalsFromDepth(Image(16, 8, 1, d), 0.5);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 16; ++x) {
                // Exact: the differences of equal values are exactly 0, and normalize(0, 0, 1) is exact.
                EXPECT_EQ(normals.at(x, y, 0), 0.0f);
                EXPECT_EQ(normals.at(x, y, 1), 0.0f);
                EXPECT_EQ(normals.at(x, y, 2), 1.0f);
            }
    }
}

TEST(NormalsFromDepth, RampGivesItsExactSlopeAwayFromTheSeam) {
    // d = u on a non-square map: the slope is 1 per tile whatever the texel counts. A ramp does not
    // tile, so the two columns next to the seam see the wrap-around jump; every other texel's central
    // difference of a linear function is exact.
    constexpr double kS = 0.2;
    const Image depth = depthFrom(64, 16, [](double u, double) { return u; });
    const Image normals = normalsFromDepth(depth, kS);
    const double length = std::sqrt(kS * kS + 1.0);
    for (int y = 0; y < depth.height(); ++y)
        for (int x = 1; x + 1 < depth.width(); ++x) {
            // 1e-5: the depth values are floats (6e-8 relative), and their difference over two texels is
            // multiplied by W / 2 = 32: 1e-5 leaves a factor of 4 over that.
            EXPECT_NEAR(normals.at(x, y, 0), kS / length, 1e-5) << "x " << x << " y " << y;
            EXPECT_NEAR(normals.at(x, y, 1), 0.0, 1e-5);
            EXPECT_NEAR(normals.at(x, y, 2), 1.0 / length, 1e-5);
        }
}

TEST(NormalsFromDepth, SignConvention) {
    // The relief point is (u, v, -S d): the surface z = -S d(u, v) has the upward normal
    // (-dz/du, -dz/dv, 1) = (S dd/du, S dd/dv, 1). Where depth grows towards +u the surface falls
    // away towards +u, so its normal leans towards +u: nx > 0.
    const Image alongU =
        depthFrom(32, 32, [](double u, double) { return 0.5 + 0.25 * std::sin(2.0 * kPi * u); });
    const Image nu = normalsFromDepth(alongU, 0.1);
    // Column 0 is u = 1/64, where sin(2 pi u) rises: depth increases with u.
    EXPECT_GT(nu.at(0, 5, 0), 0.0f);
    EXPECT_EQ(nu.at(0, 5, 1), 0.0f);
    // At u = 1/2 + 1/64 (column 16) depth decreases with u: nx < 0.
    EXPECT_LT(nu.at(16, 5, 0), 0.0f);

    // Depth growing towards v = 1, i.e. towards row 0 (CONVENTIONS §1), gives ny > 0 (OpenGL, green up).
    const Image alongV =
        depthFrom(32, 32, [](double, double v) { return 0.5 + 0.25 * std::sin(2.0 * kPi * v); });
    const Image nv = normalsFromDepth(alongV, 0.1);
    // Row 31 is v = 1/64, where depth rises with v.
    EXPECT_GT(nv.at(7, 31, 1), 0.0f);
    EXPECT_EQ(nv.at(7, 31, 0), 0.0f);
    EXPECT_LT(nv.at(7, 15, 1), 0.0f);  // row 15: v = 1/2 + 1/64, depth falls with v

    // And the per-tile gradient itself: d = v away from the seam rows has dd/dv = 1.
    const Image ramp = depthFrom(8, 32, [](double, double v) { return v; });
    const Image gradient = depthGradient(ramp);
    // 1e-5: float depth differences multiplied by H / 2 = 16, as in the ramp test above.
    EXPECT_NEAR(gradient.at(3, 10, 0), 0.0, 1e-5);
    EXPECT_NEAR(gradient.at(3, 10, 1), 1.0, 1e-5);
}

TEST(NormalsFromDepth, ScaleOnlyChangesTheTilt) {
    // normalize(S g, 1): doubling S doubles the tangent of the tilt, and the direction in the plane
    // stays the same.
    const Image depth = depthFrom(32, 32, [](double u, double v) {
        return 0.5 + 0.3 * std::sin(2.0 * kPi * u) * std::sin(4.0 * kPi * v);
    });
    const Image a = normalsFromDepth(depth, 0.05);
    const Image b = normalsFromDepth(depth, 0.1);
    for (int y = 0; y < 32; y += 3)
        for (int x = 0; x < 32; x += 3) {
            const double ta = std::hypot(a.at(x, y, 0), a.at(x, y, 1)) / a.at(x, y, 2);
            const double tb = std::hypot(b.at(x, y, 0), b.at(x, y, 1)) / b.at(x, y, 2);
            // 1e-5: float rounding of normalised components (1e-7) divided by nz >= 0.5.
            EXPECT_NEAR(tb, 2.0 * ta, 1e-5);
        }
}

TEST(NormalMapFiles, EncodeDecodeRoundTrip) {
    const Image depth = depthFrom(24, 16, [](double u, double v) {
        return 0.5 + 0.5 * std::sin(2.0 * kPi * 2.0 * u) * std::cos(2.0 * kPi * v);
    });
    const Image normals = normalsFromDepth(depth, 0.15);
    const Image encoded = encodeNormals(normals);
    for (int c = 0; c < 3; ++c) {
        const ValueRange range = valueRange(encoded, c);
        EXPECT_GE(range.min, 0.0f);
        EXPECT_LE(range.max, 1.0f);
    }
    // Stored form n * 0.5 + 0.5 (CONVENTIONS §3).
    EXPECT_FLOAT_EQ(encoded.at(5, 7, 1), normals.at(5, 7, 1) * 0.5f + 0.5f);
    // 1e-6: two float multiply-adds and a renormalisation of an already unit vector.
    EXPECT_LT(test::maxAbsDiff(decodeNormals(encoded), normals), 1e-6);
}

TEST(NormalMapFiles, DecodeWithFlipYNegatesY) {
    const Image depth = depthFrom(16, 16, [](double u, double v) {
        return 0.5 + 0.4 * std::sin(2.0 * kPi * u) * std::sin(2.0 * kPi * v);
    });
    const Image encoded = encodeNormals(normalsFromDepth(depth, 0.1));
    const Image plain = decodeNormals(encoded);
    const Image flipped = decodeNormals(encoded, true);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            EXPECT_EQ(flipped.at(x, y, 0), plain.at(x, y, 0));
            EXPECT_EQ(flipped.at(x, y, 1), -plain.at(x, y, 1));
            EXPECT_EQ(flipped.at(x, y, 2), plain.at(x, y, 2));
        }
}

TEST(NormalMapFiles, DecodeRenormalisesQuantisedValues) {
    // An 8-bit file cannot store a unit vector exactly; decoding must hand back unit normals.
    Image encoded(1, 1, 3);
    encoded.at(0, 0, 0) = 200.0f / 255.0f;
    encoded.at(0, 0, 1) = 90.0f / 255.0f;
    encoded.at(0, 0, 2) = 230.0f / 255.0f;
    const Image n = decodeNormals(encoded);
    const double length = std::sqrt(n.at(0, 0, 0) * n.at(0, 0, 0) + n.at(0, 0, 1) * n.at(0, 0, 1) +
                                    n.at(0, 0, 2) * n.at(0, 0, 2));
    EXPECT_NEAR(length, 1.0, 1e-6);  // float rounding of three products and a square root
    EXPECT_GT(n.at(0, 0, 0), 0.0f);
    EXPECT_LT(n.at(0, 0, 1), 0.0f);
}

TEST(NormalsHeightToDepth, IsOneMinusAndItsOwnInverse) {
    Image height(3, 2, 1);
    const float values[] = {0.0f, 0.25f, 0.5f, 0.75f, 1.0f, 0.125f};
    for (int i = 0; i < 6; ++i) height.at(i % 3, i / 3) = values[i];
    const Image depth = heightToDepth(height);
    for (int i = 0; i < 6; ++i) EXPECT_FLOAT_EQ(depth.at(i % 3, i / 3), 1.0f - values[i]);
    // White (h = 1) is the top, d = 0 (CONVENTIONS §2).
    EXPECT_EQ(depth.at(1, 1), 0.0f);
    EXPECT_EQ(heightToDepth(depth), height);  // 1 - (1 - h) is exact for these binary fractions
}

}  // namespace
}  // namespace strata
