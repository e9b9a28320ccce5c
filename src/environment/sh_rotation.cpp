#include "strata/environment/sh_rotation.h"

#include "strata/core/check.h"

#include <glm/matrix.hpp>

#include <cmath>
#include <cstdlib>

namespace strata {

namespace {

// A band's block during the recurrence, indexed by (m, n) in [-l, l].
struct Band {
    int l = 0;
    std::array<double, 49> values{};
    double& operator()(int m, int n) {
        return values[static_cast<std::size_t>((m + l) * (2 * l + 1) + (n + l))];
    }
    double operator()(int m, int n) const {
        return values[static_cast<std::size_t>((m + l) * (2 * l + 1) + (n + l))];
    }
};

// Ivanic & Ruedenberg's P (1998 corrections, Table 2), for band l from band 1 (r1) and band l - 1 (prev).
double functionP(int i, int a, int b, int l, const Band& r1, const Band& prev) {
    if (b == l) return r1(i, 1) * prev(a, l - 1) - r1(i, -1) * prev(a, -l + 1);
    if (b == -l) return r1(i, 1) * prev(a, -l + 1) + r1(i, -1) * prev(a, l - 1);
    return r1(i, 0) * prev(a, b);
}

double functionU(int m, int n, int l, const Band& r1, const Band& prev) {
    return functionP(0, m, n, l, r1, prev);
}

double functionV(int m, int n, int l, const Band& r1, const Band& prev) {
    if (m == 0) return functionP(1, 1, n, l, r1, prev) + functionP(-1, -1, n, l, r1, prev);
    if (m > 0) {
        const double d = m == 1 ? 1.0 : 0.0;
        return functionP(1, m - 1, n, l, r1, prev) * std::sqrt(1.0 + d) -
               functionP(-1, -m + 1, n, l, r1, prev) * (1.0 - d);
    }
    const double d = m == -1 ? 1.0 : 0.0;
    return functionP(1, m + 1, n, l, r1, prev) * (1.0 - d) +
           functionP(-1, -m - 1, n, l, r1, prev) * std::sqrt(1.0 + d);
}

double functionW(int m, int n, int l, const Band& r1, const Band& prev) {
    if (m > 0) return functionP(1, m + 1, n, l, r1, prev) + functionP(-1, -m - 1, n, l, r1, prev);
    return functionP(1, m - 1, n, l, r1, prev) - functionP(-1, -m + 1, n, l, r1, prev);
}

// Ivanic & Ruedenberg's u, v, w (1998 corrections, Table 2) for every (m, n) of band l: they depend on the
// indices only, so they are computed once.
struct Weights {
    std::array<double, 49> u{}, v{}, w{};
};

Weights makeWeights(int l) {
    Weights weights;
    for (int m = -l; m <= l; ++m)
        for (int n = -l; n <= l; ++n) {
            const double d = m == 0 ? 1.0 : 0.0;
            const int absM = std::abs(m);
            const double denominator =
                std::abs(n) == l ? (2.0 * l) * (2.0 * l - 1.0) : static_cast<double>((l + n) * (l - n));
            const auto at = static_cast<std::size_t>((m + l) * (2 * l + 1) + (n + l));
            weights.u[at] = std::sqrt(static_cast<double>((l + m) * (l - m)) / denominator);
            weights.v[at] =
                0.5 * std::sqrt((1.0 + d) * (l + absM - 1.0) * (l + absM) / denominator) * (1.0 - 2.0 * d);
            // (l - |m| - 1)(l - |m|) is 0 for |m| >= l - 1 (and W is then undefined): w = 0 there.
            weights.w[at] = absM >= l - 1
                                ? 0.0
                                : -0.5 * std::sqrt((l - absM - 1.0) * (l - absM) / denominator) * (1.0 - d);
        }
    return weights;
}

Band nextBand(int l, const Band& r1, const Band& prev) {
    static const Weights kWeights[2] = {makeWeights(2), makeWeights(3)};
    const Weights& weights = kWeights[l - 2];
    Band band;
    band.l = l;
    for (int m = -l; m <= l; ++m) {
        for (int n = -l; n <= l; ++n) {
            const auto at = static_cast<std::size_t>((m + l) * (2 * l + 1) + (n + l));
            double value = 0.0;
            if (weights.u[at] != 0.0) value += weights.u[at] * functionU(m, n, l, r1, prev);
            if (weights.v[at] != 0.0) value += weights.v[at] * functionV(m, n, l, r1, prev);
            if (weights.w[at] != 0.0) value += weights.w[at] * functionW(m, n, l, r1, prev);
            band.values[at] = value;
        }
    }
    return band;
}

}  // namespace

ShRotation::ShRotation(const glm::dmat3& rotation) {
    const glm::dmat3 product = glm::transpose(rotation) * rotation;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) STRATA_CHECK_LE(std::abs(product[i][j] - (i == j ? 1.0 : 0.0)), 1e-6);
    STRATA_CHECK_LE(std::abs(glm::determinant(rotation) - 1.0), 1e-6);

    // Band 1 is 0.488603 (y, z, x): its block is R itself with rows and columns in the order y, z, x
    // (m = -1, 0, 1). glm is column-major: element (row r, column c) of R is rotation[c][r].
    constexpr int kAxis[3] = {1, 2, 0};
    Band r1;
    r1.l = 1;
    for (int m = -1; m <= 1; ++m)
        for (int n = -1; n <= 1; ++n) r1(m, n) = rotation[kAxis[n + 1]][kAxis[m + 1]];

    mBlocks[0] = 1.0;
    const auto store = [this](const Band& band) {
        const int size = 2 * band.l + 1;
        for (int i = 0; i < size * size; ++i)
            mBlocks[static_cast<std::size_t>(blockOffset(band.l) + i)] =
                band.values[static_cast<std::size_t>(i)];
    };
    store(r1);
    const Band r2 = nextBand(2, r1, r1);
    store(r2);
    store(nextBand(3, r1, r2));
}

ShVector ShRotation::apply(const ShVector& coefficients) const {
    ShVector result{};
    for (int l = 0; l < kShBands; ++l)
        for (int m = -l; m <= l; ++m) {
            double sum = 0.0;
            for (int n = -l; n <= l; ++n) sum += entry(l, m, n) * coefficients[shIndex(l, n)];
            result[shIndex(l, m)] = sum;
        }
    return result;
}

ShColor ShRotation::apply(const ShColor& coefficients) const {
    ShColor result{};
    for (int l = 0; l < kShBands; ++l)
        for (int m = -l; m <= l; ++m) {
            glm::dvec3 sum(0.0);
            for (int n = -l; n <= l; ++n) sum += entry(l, m, n) * coefficients[shIndex(l, n)];
            result[shIndex(l, m)] = sum;
        }
    return result;
}

ShVector shRotate(const ShVector& coefficients, const glm::dmat3& rotation) {
    return ShRotation(rotation).apply(coefficients);
}

ShColor shRotate(const ShColor& coefficients, const glm::dmat3& rotation) {
    return ShRotation(rotation).apply(coefficients);
}

}  // namespace strata
