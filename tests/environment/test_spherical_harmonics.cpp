// Real spherical harmonics, bands 0-3: the basis against its closed form, orthonormality, projection of
// band-limited functions and of the clamped cosine (Ramamoorthi & Hanrahan 2001), irradiance.
#include "strata/environment/spherical_harmonics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

// Directions spread over the sphere, none on an axis (so that every basis function is non-zero there).
std::vector<glm::dvec3> testDirections() {
    std::vector<glm::dvec3> directions;
    for (int i = 0; i < 7; ++i)
        for (int j = 0; j < 9; ++j) {
            const double polar = (i + 0.37) * kPi / 7.0;
            const double azimuth = (j + 0.21) * 2.0 * kPi / 9.0;
            directions.emplace_back(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                                    std::cos(polar));
        }
    return directions;
}

double factorial(int n) {
    double result = 1.0;
    for (int i = 2; i <= n; ++i) result *= i;
    return result;
}

// The closed form the header states, through libstdc++'s std::assoc_legendre (C++17 special functions,
// defined without the Condon-Shortley phase, the same choice as the basis).
double closedFormY(int l, int m, const glm::dvec3& d) {
    const int absM = std::abs(m);
    const double k = std::sqrt((2 * l + 1) / (4.0 * kPi) * factorial(l - absM) / factorial(l + absM));
    const double legendre = std::assoc_legendre(static_cast<unsigned>(l), static_cast<unsigned>(absM), d.z);
    const double azimuth = std::atan2(d.y, d.x);
    if (m == 0) return k * legendre;
    const double trig = m > 0 ? std::cos(m * azimuth) : std::sin(absM * azimuth);
    return std::sqrt(2.0) * k * trig * legendre;
}

TEST(SphericalHarmonics, IndexIsLSquaredPlusLPlusM) {
    EXPECT_EQ(shIndex(0, 0), 0);
    EXPECT_EQ(shIndex(1, -1), 1);
    EXPECT_EQ(shIndex(1, 1), 3);
    EXPECT_EQ(shIndex(2, 0), 6);
    EXPECT_EQ(shIndex(3, -3), 9);
    EXPECT_EQ(shIndex(3, 3), 15);
    for (int k = 0; k < kShCount; ++k) EXPECT_EQ(shBand(k), static_cast<int>(std::sqrt(k)));
}

TEST(SphericalHarmonics, BasisMatchesTheClosedFormWithoutCondonShortleyPhase) {
    for (const glm::dvec3& d : testDirections()) {
        const ShVector basis = shEvaluate(d);
        for (int l = 0; l < kShBands; ++l)
            for (int m = -l; m <= l; ++m)
                // Both sides are a few double operations on values below 3: 1e-12 is rounding with room.
                EXPECT_NEAR(basis[shIndex(l, m)], closedFormY(l, m, d), 1e-12) << "l " << l << " m " << m;
    }
    // The sign choice, in words: band 1 is +0.488603 (y, z, x).
    const ShVector atX = shEvaluate({1.0, 0.0, 0.0});
    EXPECT_NEAR(atX[shIndex(1, 1)], std::sqrt(3.0 / (4.0 * kPi)), 1e-15);  // one multiply's rounding
    EXPECT_EQ(atX[shIndex(1, -1)], 0.0);
    // Directions need not be unit length.
    const ShVector scaled = shEvaluate({0.0, 0.0, 5.0});
    EXPECT_NEAR(scaled[shIndex(1, 0)], std::sqrt(3.0 / (4.0 * kPi)), 1e-15);  // one division's rounding
}

// The quadrature (20-point Gauss-Legendre in z per hemisphere x 64 azimuths) integrates every Y_i Y_j
// (degree 6) exactly, so the Gram matrix is the identity up to rounding: 2560 terms of magnitude < 1
// accumulate at most ~2560 * 1e-16 = 3e-13.
TEST(SphericalHarmonics, BasisIsOrthonormalOverTheSphere) {
    const SphereQuadrature& rule = shQuadrature();
    ASSERT_EQ(rule.directions.size(), 2560u);
    double weightSum = 0.0;
    for (const double w : rule.weights) weightSum += w;
    EXPECT_NEAR(weightSum, 4.0 * kPi, 1e-12);  // rounding of a 2560-term sum of 5e-3 each
    double worst = 0.0;
    for (int i = 0; i < kShCount; ++i)
        for (int j = 0; j < kShCount; ++j) {
            double integral = 0.0;
            for (std::size_t q = 0; q < rule.directions.size(); ++q) {
                const ShVector basis = shEvaluate(rule.directions[q]);
                integral += rule.weights[q] * basis[i] * basis[j];
            }
            worst = std::max(worst, std::abs(integral - (i == j ? 1.0 : 0.0)));
        }
    EXPECT_LT(worst, 1e-12);  // exact rule; see above
}

TEST(SphericalHarmonics, ProjectionOfABandLimitedFunctionGivesItsCoefficients) {
    ShVector expected;
    for (int k = 0; k < kShCount; ++k) expected[k] = 0.1 * (k + 1) * (k % 2 == 0 ? 1.0 : -1.0);
    const ShVector projected = shProject([&](const glm::dvec3& d) { return shReconstruct(expected, d); });
    for (int k = 0; k < kShCount; ++k)
        EXPECT_NEAR(projected[k], expected[k], 1e-12) << k;  // exact rule (degree 6), rounding only

    // x^2 = 1/3 - (3z^2 - 1) / 6 + (x^2 - y^2) / 2 on the unit sphere, so its coefficients are those
    // numbers divided by the basis constants.
    const ShVector xSquared = shProject([](const glm::dvec3& d) { return d.x * d.x; });
    for (int k = 0; k < kShCount; ++k) {
        double value = 0.0;
        if (k == shIndex(0, 0)) value = (1.0 / 3.0) / (0.5 * std::sqrt(1.0 / kPi));
        if (k == shIndex(2, 0)) value = (-1.0 / 6.0) / (0.25 * std::sqrt(5.0 / kPi));
        if (k == shIndex(2, 2)) value = 0.5 / (0.25 * std::sqrt(15.0 / kPi));
        EXPECT_NEAR(xSquared[k], value, 1e-12) << k;  // exact rule, rounding only
    }
}

// Ramamoorthi & Hanrahan (2001), Eq. 8-9: max(cos t, 0) = sum_l A_l sqrt((2l + 1) / (4 pi)) Y_l0 with
// A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4, A_3 = 0. The rule splits the sphere at the equator, where the
// kink is, so max(z, 0) Y_k is a polynomial on each part and the projection is exact up to rounding.
TEST(SphericalHarmonics, ClampedCosineProjectsToRamamoorthiHanrahanCoefficients) {
    EXPECT_DOUBLE_EQ(kClampedCosineBands[0], kPi);
    EXPECT_DOUBLE_EQ(kClampedCosineBands[1], 2.0 * kPi / 3.0);
    EXPECT_DOUBLE_EQ(kClampedCosineBands[2], kPi / 4.0);
    EXPECT_EQ(kClampedCosineBands[3], 0.0);
    const ShVector projected = shProject([](const glm::dvec3& d) { return std::max(d.z, 0.0); });
    for (int l = 0; l < kShBands; ++l)
        for (int m = -l; m <= l; ++m) {
            const double expected =
                m == 0 ? kClampedCosineBands[l] * std::sqrt((2 * l + 1) / (4.0 * kPi)) : 0.0;
            EXPECT_NEAR(projected[shIndex(l, m)], expected, 1e-12) << "l " << l << " m " << m;  // exact rule
        }
    // The classic numbers: 0.886227, 1.023327, 0.495416.
    EXPECT_NEAR(projected[0], std::sqrt(kPi) / 2.0, 1e-12);
    EXPECT_NEAR(projected[2], std::sqrt(kPi / 3.0), 1e-12);
    EXPECT_NEAR(projected[6], std::sqrt(5.0 * kPi) / 8.0, 1e-12);
}

TEST(SphericalHarmonics, IrradianceOfUniformUnitRadianceIsPi) {
    // Constant radiance 1 has c_00 = sqrt(4 pi); the irradiance at any normal is the integral of cos over the
    // hemisphere, pi.
    ShColor radiance{};
    radiance[0] = glm::dvec3(std::sqrt(4.0 * kPi));
    const ShColor irradiance = shIrradiance(radiance);
    for (const glm::dvec3& n : testDirections())
        EXPECT_NEAR(shReconstruct(irradiance, n).y, kPi, 1e-12);  // a few roundings of O(1) numbers

    // A band-1 radiance L(w) = z (the coefficient of 0.488603 z is 1 / 0.488603): its irradiance at the
    // normal n is the integral of z max(n.w, 0) = (2 pi / 3) n.z.
    ShColor linear{};
    linear[shIndex(1, 0)] = glm::dvec3(1.0 / std::sqrt(3.0 / (4.0 * kPi)));
    for (const glm::dvec3& n : testDirections())
        EXPECT_NEAR(shReconstruct(shIrradiance(linear), n).x, 2.0 * kPi / 3.0 * n.z, 1e-12);  // rounding
}

TEST(SphericalHarmonics, DominantDirectionOfADeltaIsItsDirection) {
    const glm::dvec3 d = glm::dvec3(0.3, -0.5, 0.8) / std::sqrt(0.98);
    const glm::dvec3 found = shDominantDirection(shEvaluate(d));
    EXPECT_NEAR(found.x, d.x, 1e-15);  // normalising an exact multiple of d: rounding only
    EXPECT_NEAR(found.y, d.y, 1e-15);
    EXPECT_NEAR(found.z, d.z, 1e-15);
    EXPECT_EQ(shDominantDirection(ShVector{1.0}), glm::dvec3(0.0));

    ShColor color{};
    color[3] = glm::dvec3(1.0, 2.0, 3.0);
    const ShVector luminance = shLuminance(color);
    EXPECT_NEAR(luminance[3], 0.2126 + 2.0 * 0.7152 + 3.0 * 0.0722, 1e-15);  // rounding
}

}  // namespace
}  // namespace strata
