// Real spherical harmonics of bands 0 to 3 (16 coefficients): evaluation, projection, reconstruction and
// the clamped-cosine convolution (irradiance), after Ramamoorthi & Hanrahan, "An Efficient Representation
// for Irradiance Environment Maps" (SIGGRAPH 2001, Eq. 3 and 8-9) and Sloan, "Stupid Spherical Harmonics
// (SH) Tricks" (GDC 2008, Appendix A2, where the same polynomials appear with the other sign choice).
//
// Conventions (CONVENTIONS §9: world space, +z up; directions are unit vectors (x, y, z) =
// (sin t cos p, sin t sin p, cos t) with polar angle t from +z and azimuth p from +x towards +y):
//  - Coefficient index: k = l^2 + l + m for band l in [0, 3] and m in [-l, l] (shIndex).
//  - Real basis WITHOUT the Condon-Shortley phase (the choice of Ramamoorthi & Hanrahan, and of Ivanic &
//    Ruedenberg's rotation recurrence, sh_rotation.h): for m > 0 Y_lm = sqrt(2) K_lm cos(m p) P_l^m(cos t),
//    for m < 0 Y_lm = sqrt(2) K_l|m| sin(|m| p) P_l^|m|(cos t), Y_l0 = K_l0 P_l(cos t), with P_l^m >= 0 near
//    the pole (no (-1)^m). So band 1 is +0.488603 (y, z, x): a positive m = 1 coefficient means light from
//    +x. (Sloan's table multiplies the odd-m functions by -1.) The basis is orthonormal over the sphere:
//    the integral of Y_i Y_j over solid angle is delta_ij.
//  - Projection: c_k = integral over the sphere of f(w) Y_k(w) dw; reconstruction f~(w) = sum_k c_k Y_k(w)
//    is the least-squares best band-3 approximation of f.
//  - Colours are linear RGB triples (glm::dvec3), one coefficient per channel.
//
// Failure behaviour: a direction of zero or non-finite length breaks the callers' contract
// (STRATA_CHECK aborts); directions need not be normalised, every function normalises them.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <functional>
#include <numbers>
#include <vector>

namespace strata {

inline constexpr int kShBands = 4;                    // bands l = 0, 1, 2, 3
inline constexpr int kShCount = kShBands * kShBands;  // 16 coefficients

// One coefficient per basis function, index shIndex(l, m).
using ShVector = std::array<double, kShCount>;
// One linear-RGB coefficient per basis function, index shIndex(l, m).
using ShColor = std::array<glm::dvec3, kShCount>;

// The coefficient index of band l in [0, 3], order m in [-l, l]: l^2 + l + m.
constexpr int shIndex(int l, int m) {
    return l * l + l + m;
}

// The 16 basis functions at `direction` (normalised here), as polynomials in (x, y, z):
//   l = 0: 0.282095
//   l = 1: 0.488603 y, 0.488603 z, 0.488603 x
//   l = 2: 1.092548 xy, 1.092548 yz, 0.315392 (3z^2 - 1), 1.092548 xz, 0.546274 (x^2 - y^2)
//   l = 3: 0.590044 y(3x^2 - y^2), 2.890611 xyz, 0.457046 y(5z^2 - 1), 0.373176 z(5z^2 - 3),
//          0.457046 x(5z^2 - 1), 1.445306 z(x^2 - y^2), 0.590044 x(x^2 - 3y^2)
// (the exact constants are the K_lm above, computed in double).
ShVector shEvaluate(const glm::dvec3& direction);

// f~(direction) = sum_k c_k Y_k(direction).
double shReconstruct(const ShVector& coefficients, const glm::dvec3& direction);
glm::dvec3 shReconstruct(const ShColor& coefficients, const glm::dvec3& direction);

// A quadrature rule on the unit sphere: sum_i weights[i] f(directions[i]) approximates the integral of f
// over solid angle (steradians).
struct SphereQuadrature {
    std::vector<glm::dvec3> directions;  // unit vectors
    std::vector<double> weights;         // steradians; they add up to 4 pi
};

// The rule shProject uses: 20-point Gauss-Legendre in z = cos t on each hemisphere separately (z in [0, 1]
// and [-1, 0], nodes from Boost.Math) times 64 uniformly spaced azimuths p = (i + 0.5) 2 pi / 64; 2560
// directions. It is exact (to rounding) for every function that is, on each hemisphere, a polynomial of
// degree <= 39 in z times a trigonometric polynomial of degree <= 63 in p. That covers every product
// Y_i Y_j of bands <= 3 (degree 6) and the clamped cosine max(z, 0) times any Y_k (a polynomial on each
// hemisphere, with its kink on the split): their projections are exact, not approximations.
const SphereQuadrature& shQuadrature();

// The projection of f (any function of a unit direction) with shQuadrature(). Exact for the functions
// named there; for others it is a quadrature whose error falls with f's smoothness on each hemisphere.
ShVector shProject(const std::function<double(const glm::dvec3&)>& function);
ShColor shProject(const std::function<glm::dvec3(const glm::dvec3&)>& function);

// Ramamoorthi & Hanrahan's A_l (Eq. 8-9): the clamped cosine max(cos t, 0) projects to
// c_l0 = A_l sqrt((2l + 1) / (4 pi)), every other coefficient 0: A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4,
// A_3 = 0 (zero for every odd l >= 3).
inline constexpr std::array<double, kShBands> kClampedCosineBands = {
    std::numbers::pi, 2.0 * std::numbers::pi / 3.0, std::numbers::pi / 4.0, 0.0};

// The band of a coefficient index k in [0, 16): floor(sqrt(k)).
constexpr int shBand(int k) {
    return k < 1 ? 0 : k < 4 ? 1 : k < 9 ? 2 : 3;
}

// Irradiance from radiance (Ramamoorthi & Hanrahan, Eq. 7): E_lm = A_l L_lm, so that
// shReconstruct(result, n) is the irradiance (W m^-2 for radiance in W m^-2 sr^-1) at a surface of normal n
// lit by the band-limited radiance the coefficients describe (exact for it: the clamped cosine's bands >= 4
// meet no radiance, and A_3 = 0).
ShColor shIrradiance(const ShColor& radiance);

// Rec. 709 luminance (0.2126 R + 0.7152 G + 0.0722 B) of each coefficient.
ShVector shLuminance(const ShColor& coefficients);

// The direction band 1 points to: normalize(c[3], c[1], c[2]) (the x, y, z terms). For a single narrow
// light it is the light's direction. Returns (0, 0, 0) when band 1 is all zero.
glm::dvec3 shDominantDirection(const ShVector& coefficients);

}  // namespace strata
