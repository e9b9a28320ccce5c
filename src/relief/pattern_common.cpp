#include "pattern_common.h"

#include "strata/core/check.h"

#include <array>
#include <limits>
#include <numbers>

namespace strata::pattern {

namespace {

// Sixteen unit gradients spread evenly on the circle: enough directions that the noise shows no grid
// bias, and a table lookup instead of a cos/sin per lattice corner.
struct GradientTable {
    std::array<double, 16> x{};
    std::array<double, 16> y{};
    GradientTable() {
        for (int k = 0; k < 16; ++k) {
            const double angle = (k + 0.5) * std::numbers::pi / 8.0;
            x[k] = std::cos(angle);
            y[k] = std::sin(angle);
        }
    }
};

const GradientTable& gradients() {
    static const GradientTable table;
    return table;
}

double fade(double t) {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

}  // namespace

double periodicNoise(double x, double y, int px, int py, std::uint64_t key) {
    const GradientTable& g = gradients();
    const double x0 = floorFast(x);
    const double y0 = floorFast(y);
    const double tx = x - x0;
    const double ty = y - y0;
    // Wrapping the lattice indices (not the coordinates) is what makes the noise periodic.
    const std::int64_t i0 = wrapIndex(static_cast<std::int64_t>(x0), px);
    const std::int64_t j0 = wrapIndex(static_cast<std::int64_t>(y0), py);
    const std::int64_t i1 = i0 + 1 == px ? 0 : i0 + 1;
    const std::int64_t j1 = j0 + 1 == py ? 0 : j0 + 1;
    const auto corner = [&](std::int64_t i, std::int64_t j, double dx, double dy) {
        // One mixing round per corner (not hashIndices' three): noise is most of a pattern's cost, and
        // splitmix64's finaliser alone decorrelates neighbouring lattice points well enough.
        const auto k =
            static_cast<std::size_t>(mix64(key ^ (static_cast<std::uint64_t>(i) * 0x9e3779b97f4a7c15ull +
                                                  static_cast<std::uint64_t>(j) * 0xc2b2ae3d27d4eb4full)) >>
                                     60);
        return g.x[k] * dx + g.y[k] * dy;
    };
    const double n00 = corner(i0, j0, tx, ty);
    const double n10 = corner(i1, j0, tx - 1.0, ty);
    const double n01 = corner(i0, j1, tx, ty - 1.0);
    const double n11 = corner(i1, j1, tx - 1.0, ty - 1.0);
    const double sx = fade(tx);
    const double sy = fade(ty);
    const double bottom = n00 + (n10 - n00) * sx;
    const double top = n01 + (n11 - n01) * sx;
    // 2D gradient noise peaks at sqrt(1/2); scale it to about [-1, 1].
    return std::numbers::sqrt2 * (bottom + (top - bottom) * sy);
}

double periodicFbm(Vec2 uv, int px, int py, int octaves, std::uint64_t key, double gain) {
    double sum = 0.0;
    double amplitude = 1.0;
    double total = 0.0;
    for (int k = 0; k < octaves; ++k) {
        const int fx = px << k;
        const int fy = py << k;
        sum += amplitude *
               periodicNoise(uv.x * fx, uv.y * fy, fx, fy, mix64(key + static_cast<std::uint64_t>(k)));
        total += amplitude;
        amplitude *= gain;
    }
    return sum / total;
}

CellLattice::CellLattice(int columns, int rows, double jitter, double rowShift, std::uint64_t key)
    : mColumns(columns), mRows(rows), mRowShift(rowShift) {
    STRATA_CHECK_GT(columns, 0);
    STRATA_CHECK_GT(rows, 0);
    // A shift of odd rows repeats across the tile only with an even number of rows.
    STRATA_CHECK(rowShift == 0.0 || rows % 2 == 0);
    // The search window of nearest() (two cells each way) is exact only for sites that stay in their cell.
    STRATA_CHECK(jitter >= 0.0 && jitter <= 0.5);
    mJitter.resize(static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows));
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < columns; ++i)
            mJitter[static_cast<std::size_t>(j * columns + i)] = Vec2(
                jitter * (2.0 * hashUnit(key, i, j, 0) - 1.0), jitter * (2.0 * hashUnit(key, i, j, 1) - 1.0));
}

CellHit CellLattice::nearest(Vec2 uv) const {
    const int j0 = floorInt(uv.y * mRows);
    const double shift = (wrapIndex(j0, mRows) & 1) != 0 ? mRowShift : 0.0;
    const int i0 = floorInt(uv.x * mColumns - shift);
    constexpr int kReach = 2;
    constexpr int kSpan = 2 * kReach + 1;
    constexpr int kCount = kSpan * kSpan;
    // Wrap the window's column and row indices once, not once per site.
    std::array<int, kSpan> wrappedColumns{};
    std::array<int, kSpan> wrappedRows{};
    for (int k = 0; k < kSpan; ++k) {
        wrappedColumns[k] = static_cast<int>(wrapIndex(i0 - kReach + k, mColumns));
        wrappedRows[k] = static_cast<int>(wrapIndex(j0 - kReach + k, mRows));
    }
    std::array<Vec2, kCount> sites{};
    int best = 0;
    double bestDistance2 = std::numeric_limits<double>::max();
    for (int n = 0; n < kCount; ++n) {
        const int dj = n / kSpan;
        const int di = n % kSpan;
        const int wj = wrappedRows[dj];
        const Vec2 jitter = mJitter[static_cast<std::size_t>(wj * mColumns + wrappedColumns[di])];
        const double rowShift = (wj & 1) != 0 ? mRowShift : 0.0;
        // Unwrapped indices place the site where it lies next to uv, in this tile or a neighbouring one.
        sites[n] = Vec2((i0 - kReach + di + 0.5 + rowShift + jitter.x) / mColumns,
                        (j0 - kReach + dj + 0.5 + jitter.y) / mRows);
        const Vec2 d = uv - sites[n];
        const double d2 = glm::dot(d, d);
        if (d2 < bestDistance2) {
            bestDistance2 = d2;
            best = n;
        }
    }
    const Vec2 a = sites[best];
    double edge = std::numeric_limits<double>::max();
    for (int k = 0; k < kCount; ++k) {
        if (k == best) continue;
        // Distance from the point to the bisector of a and b, positive on a's side.
        const Vec2 ab = sites[k] - a;
        const double length = std::sqrt(glm::dot(ab, ab));
        edge = std::min(edge, glm::dot(0.5 * (a + sites[k]) - uv, ab) / length);
    }
    return {wrappedColumns[best % kSpan], wrappedRows[best / kSpan], uv - a, edge};
}

}  // namespace strata::pattern
