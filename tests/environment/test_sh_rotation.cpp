// Rotation of SH coefficient vectors (Ivanic & Ruedenberg 1996/1998): against direct evaluation, norms per
// band, composition, and the analytic quarter turn.
#include "strata/environment/sh_rotation.h"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <numbers>
#include <random>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

glm::dmat3 rotation(double angle, glm::dvec3 axis) {
    return glm::mat3_cast(glm::angleAxis(angle, glm::normalize(axis)));
}

// Rotations about general axes, and about each coordinate axis (the recurrence's special cases |n| = l).
std::vector<glm::dmat3> testRotations() {
    std::vector<glm::dmat3> rotations = {
        rotation(0.0, {0, 0, 1}),         rotation(kPi / 2.0, {0, 0, 1}),  rotation(kPi / 2.0, {1, 0, 0}),
        rotation(kPi / 2.0, {0, 1, 0}),   rotation(kPi, {1, 1, 0}),        rotation(2.1, {0.3, -0.7, 0.2}),
        rotation(-0.4, {-1.0, 0.2, 0.9}), rotation(1e-7, {0.5, 0.5, 0.5}),
    };
    std::mt19937 random(19);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int i = 0; i < 12; ++i)
        rotations.push_back(
            rotation(kPi * uniform(random), {uniform(random), uniform(random), uniform(random) + 0.01}));
    return rotations;
}

ShVector randomCoefficients(std::mt19937& random) {
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    ShVector c;
    for (double& v : c) v = uniform(random);
    return c;
}

std::vector<glm::dvec3> testDirections() {
    std::vector<glm::dvec3> directions;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            const double polar = (i + 0.5) * kPi / 8.0;
            const double azimuth = (j + 0.3) * 2.0 * kPi / 8.0;
            directions.emplace_back(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                                    std::cos(polar));
        }
    return directions;
}

// The rotated function g(w) = f(R^T w). Coefficients in [-1, 1], basis values below 3: the reconstruction
// is a 16-term sum of O(1) terms, and the recurrence a few dozen operations per entry; 1e-12 is rounding with
// room (the measured worst, over 200 random rotations, is 2.7e-15) and far inside the 1e-5 the environment
// needs.
TEST(ShRotation, RotatedCoefficientsEvaluateLikeTheInverseRotatedDirection) {
    std::mt19937 random(7);
    double worst = 0.0;
    for (const glm::dmat3& r : testRotations()) {
        const ShVector c = randomCoefficients(random);
        const ShVector rotated = ShRotation(r).apply(c);
        for (const glm::dvec3& w : testDirections())
            worst = std::max(worst,
                             std::abs(shReconstruct(rotated, w) - shReconstruct(c, glm::transpose(r) * w)));
    }
    EXPECT_LT(worst, 1e-12);
}

TEST(ShRotation, PreservesEachBandsNorm) {
    std::mt19937 random(11);
    for (const glm::dmat3& r : testRotations()) {
        const ShVector c = randomCoefficients(random);
        const ShVector rotated = shRotate(c, r);
        for (int l = 0; l < kShBands; ++l) {
            double before = 0.0, after = 0.0;
            for (int m = -l; m <= l; ++m) {
                before += c[shIndex(l, m)] * c[shIndex(l, m)];
                after += rotated[shIndex(l, m)] * rotated[shIndex(l, m)];
            }
            EXPECT_NEAR(after, before, 1e-12) << "band " << l;  // an orthogonal block: rounding only
        }
    }
}

TEST(ShRotation, ComposesLikeTheRotations) {
    std::mt19937 random(13);
    const std::vector<glm::dmat3> rotations = testRotations();
    for (std::size_t i = 0; i + 1 < rotations.size(); ++i) {
        const glm::dmat3& a = rotations[i];
        const glm::dmat3& b = rotations[i + 1];
        const ShVector c = randomCoefficients(random);
        const ShVector twice = shRotate(shRotate(c, a), b);
        const ShVector once = shRotate(c, b * a);
        for (int k = 0; k < kShCount; ++k) EXPECT_NEAR(twice[k], once[k], 1e-12) << k;  // rounding only
    }
}

TEST(ShRotation, QuarterTurnAboutZCarriesALightFromXToY) {
    // The projection of a delta light from d is Y(d); rotated by R it must be Y(R d).
    const glm::dmat3 quarter = rotation(kPi / 2.0, {0, 0, 1});
    const glm::dvec3 moved = quarter * glm::dvec3(1.0, 0.0, 0.0);
    EXPECT_NEAR(moved.y, 1.0, 1e-15);  // glm's quaternion to matrix: rounding only
    const glm::dvec3 from = glm::normalize(glm::dvec3(1.0, 0.0, 0.4));
    const ShVector rotated = shRotate(shEvaluate(from), quarter);
    const ShVector expected = shEvaluate(glm::normalize(glm::dvec3(0.0, 1.0, 0.4)));
    for (int k = 0; k < kShCount; ++k) EXPECT_NEAR(rotated[k], expected[k], 1e-12) << k;  // rounding only

    // The identity is the identity, entry by entry.
    const ShRotation identity(glm::dmat3(1.0));
    for (int l = 0; l < kShBands; ++l)
        for (int m = -l; m <= l; ++m)
            for (int n = -l; n <= l; ++n) EXPECT_NEAR(identity.entry(l, m, n), m == n ? 1.0 : 0.0, 1e-15);
}

TEST(ShRotation, RgbRotatesEachChannel) {
    std::mt19937 random(17);
    const glm::dmat3 r = rotation(0.8, {1.0, -2.0, 0.5});
    const ShVector red = randomCoefficients(random), green = randomCoefficients(random),
                   blue = randomCoefficients(random);
    ShColor color;
    for (int k = 0; k < kShCount; ++k) color[k] = {red[k], green[k], blue[k]};
    const ShColor rotated = ShRotation(r).apply(color);
    const ShVector redRotated = shRotate(red, r), blueRotated = shRotate(blue, r);
    for (int k = 0; k < kShCount; ++k) {
        EXPECT_EQ(rotated[k].x, redRotated[k]);  // the same operations in the same order
        EXPECT_EQ(rotated[k].z, blueRotated[k]);
    }
}

}  // namespace
}  // namespace strata
