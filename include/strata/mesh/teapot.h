// The Utah teapot's control points: Martin Newell's 1975 data set of 306 points and 32 bicubic Bezier
// patches (public domain; the version with the bottom patches, as distributed in the classic "teaset"
// files). Exposed so that tests can evaluate the patches independently of the tessellation.
#pragma once

#include <glm/vec3.hpp>

#include <array>

namespace strata {

constexpr int kTeapotPatchCount = 32;

// The 4 x 4 control points of patch `patch` (0..31) as the built-in "teapot" uses them, row-major:
// element [4 * j + i] is P_ij, i along the patch parameter s and j along t, so that
//   P(s, t) = sum_ij B_i(s) B_j(t) P_ij   (cubic Bernstein polynomials B).
// Already in the built-in's frame: the original data (z up, spout along +x) scaled by 1 / 3.15, so the
// teapot stands on z = 0 with height 1. In this data cross(dP/ds, dP/dt) points out of the teapot on all 32
// patches (tests/mesh verifies it), so no patch needs its parameters reversed. Patches 20-23 (knob top) and
// 28-31 (bottom centre) have their row j = 0 collapsed to one point, so dP/ds = 0 along t = 0 there.
// Checks (STRATA_CHECK) that patch is in range.
std::array<glm::vec3, 16> teapotPatchControlPoints(int patch);

}  // namespace strata
