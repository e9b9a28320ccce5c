// Rotation of band-3 real spherical-harmonic coefficient vectors (spherical_harmonics.h's basis and index).
//
// Method: Ivanic & Ruedenberg, "Rotation Matrices for Real Spherical Harmonics. Direct Determination by
// Recursion", J. Phys. Chem. 100 (1996) 6342, with the corrections of J. Phys. Chem. A 102 (1998) 9099
// (Table 2: R^l = u U + v V + w W, built from band 1's matrix and band l - 1's). The basis has no
// Condon-Shortley phase, the form the recurrence is written for. Rotation never mixes bands, so the
// result is a block-diagonal 16 x 16 matrix (blocks 1, 3, 5, 7: 84 numbers), built once per rotation in
// O(l^4) and applied to any number of vectors; it is exact (to rounding): a rotated band-limited function
// is band-limited with the same bands.
//
// Meaning: for coefficients c of a function f, ShRotation(R).apply(c) holds the coefficients of the rotated
// function g(w) = f(R^T w): what f shows towards R^T w, g shows towards w (a light from direction d moves to
// R d). R is a glm::dmat3 (column-major: R[j] is column j) acting on column vectors as R * v. Later use:
// with R = transpose(TBN) (rows tangent, bitangent, normal) a world-space environment becomes one in a
// vertex's tangent frame.
//
// Failure behaviour: R must be a rotation: R^T R = I and det R = +1 within 1e-6 (STRATA_CHECK aborts
// otherwise: a reflection or a scale is a bug in the caller).
#pragma once

#include "strata/environment/spherical_harmonics.h"

#include <glm/mat3x3.hpp>

#include <array>

namespace strata {

class ShRotation {
public:
    explicit ShRotation(const glm::dmat3& rotation);

    ShVector apply(const ShVector& coefficients) const;
    ShColor apply(const ShColor& coefficients) const;

    // Entry (m, n) of band l's (2l + 1) x (2l + 1) block, l in [0, 3], m and n in [-l, l]:
    // apply(c)[shIndex(l, m)] = sum_n entry(l, m, n) c[shIndex(l, n)].
    double entry(int l, int m, int n) const {
        return mBlocks[blockOffset(l) + (m + l) * (2 * l + 1) + (n + l)];
    }

private:
    static constexpr int blockOffset(int l) { return l == 0 ? 0 : l == 1 ? 1 : l == 2 ? 10 : 35; }

    std::array<double, 84> mBlocks{};  // bands 0..3, each row-major, (2l + 1)^2 entries
};

// One-off forms of ShRotation(rotation).apply(coefficients).
ShVector shRotate(const ShVector& coefficients, const glm::dmat3& rotation);
ShColor shRotate(const ShColor& coefficients, const glm::dmat3& rotation);

}  // namespace strata
