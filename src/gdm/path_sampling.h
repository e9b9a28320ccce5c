// The path tracers' random numbers and direction sampling (gdm_path_trace.cpp, gdm_mesh_path_trace.cpp): one
// definition, so that on the quad both tracers draw the same paths.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "strata/core/error.h"
#include "strata/gdm/gdm_path_trace.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

namespace strata::detail {

// splitmix64 (Steele, Lea and Flood 2014): the finaliser as a hash, and the generator as a counter through
// it.
inline constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ull;
inline std::uint64_t splitmix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

class PathRandom {
public:
    // One stream per path: (seed, pixel, sample) hashed into the starting state.
    PathRandom(std::uint64_t seed, int i, int j, int sample) {
        std::uint64_t h = splitmix(seed + kGolden);
        h = splitmix(h ^ ((std::uint64_t(std::uint32_t(j)) << 32) | std::uint64_t(std::uint32_t(i))));
        mState = splitmix(h ^ std::uint64_t(std::uint32_t(sample)));
    }
    // Uniform in [0, 1): the top 53 bits.
    double next() {
        mState += kGolden;
        return double(splitmix(mState) >> 11) * 0x1.0p-53;
    }

private:
    std::uint64_t mState;
};

// An orthonormal basis (t, s) of the plane perpendicular to the unit n (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited").
inline void orthonormalBasis(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& s) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    t = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    s = glm::dvec3(b, sign + n.y * n.y * a, -n.y);
}

// A direction drawn with density cos(theta) / pi around the unit normal n (Malley's method).
inline glm::dvec3 cosineDirection(const glm::dvec3& n, double u1, double u2) {
    glm::dvec3 t, s;
    orthonormalBasis(n, t, s);
    const double r = std::sqrt(u1);
    const double phi = 2.0 * std::numbers::pi * u2;
    return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * s + std::sqrt(1.0 - u1) * n);
}

// A direction drawn with density (s + 1) / (2 pi) (w . r)^s around the unit r (the Phong lobe).
inline glm::dvec3 phongDirection(const glm::dvec3& r, double shininess, double u1, double u2) {
    glm::dvec3 t, s;
    orthonormalBasis(r, t, s);
    const double cosine = std::pow(u1, 1.0 / (shininess + 1.0));
    const double sine = std::sqrt(std::max(1.0 - cosine * cosine, 0.0));
    const double phi = 2.0 * std::numbers::pi * u2;
    return glm::normalize(sine * std::cos(phi) * t + sine * std::sin(phi) * s + cosine * r);
}

// The albedo's texture point of an unwrapped hit position (u, v, z): (u mod 1, v mod 1, z / H in [0, 1]).
inline glm::dvec3 pathTexturePoint(const glm::dvec3& point, double height) {
    return {point.x - std::floor(point.x), point.y - std::floor(point.y),
            std::clamp(point.z / height, 0.0, 1.0)};
}

// Throws Error(InvalidInput) naming `what` and the value for paths per pixel or bounces out of range
// (GdmPathTraceOptions' limits).
inline void checkPathCounts(int samplesPerPixel, int bounces, const std::string& what) {
    if (samplesPerPixel < 1 || samplesPerPixel > GdmPathTraceOptions::kMaxSamplesPerPixel)
        throw Error(ErrorKind::InvalidInput,
                    what + ": samplesPerPixel " + std::to_string(samplesPerPixel) + " is outside [1, " +
                        std::to_string(GdmPathTraceOptions::kMaxSamplesPerPixel) + "]");
    if (bounces < 0 || bounces > GdmPathTraceOptions::kMaxBounces)
        throw Error(ErrorKind::InvalidInput, what + ": bounces " + std::to_string(bounces) +
                                                 " is outside [0, " +
                                                 std::to_string(GdmPathTraceOptions::kMaxBounces) + "]");
}

}  // namespace strata::detail
