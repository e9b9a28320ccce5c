// Private to the relief module: the building blocks of the procedural patterns (patterns.h).
//
// Every pattern is a function of continuous texture coordinates (u, v) in [0, 1)^2 that is periodic on
// the torus: the noise here has integer lattice periods per tile, distances wrap around, and repeated
// shapes come in integer counts per tile. Randomness comes from a splitmix64 hash of (seed, stream,
// indices) only, so a pattern is the same on every platform and standard library (std::rand and the
// <random> distributions are not).
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace strata::pattern {

using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;

// What a pattern gives at one point: a depth (0 = top; any range, makePattern normalises it to [0, 1])
// and an sRGB colour (clamped to [0, 1] afterwards).
struct Sample {
    double depth;
    Vec3 color;
};

class Generator {
public:
    virtual ~Generator() = default;
    // (u, v) in [0, 1)^2, v up (CONVENTIONS §1). Must be periodic in both with period 1, and thread-safe.
    virtual Sample evaluate(Vec2 uv) const = 0;
};

// --- Hashing -----------------------------------------------------------------------------------------

// splitmix64's output function (Steele, Lea and Flood 2014): a cheap bijective 64-bit mixer.
constexpr std::uint64_t mix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// A key for one random stream of one pattern: patterns draw their noise, layout and colours from
// different streams so that changing how many numbers one of them uses does not shift the others.
constexpr std::uint64_t streamKey(std::uint32_t seed, std::uint64_t stream) {
    return mix64(mix64(seed) ^ (stream * 0xd1b54a32d192ed03ull));
}

constexpr std::uint64_t hashIndices(std::uint64_t key, std::int64_t a, std::int64_t b = 0,
                                    std::int64_t c = 0) {
    std::uint64_t h = mix64(key ^ static_cast<std::uint64_t>(a));
    h = mix64(h ^ static_cast<std::uint64_t>(b));
    return mix64(h ^ static_cast<std::uint64_t>(c));
}

// A uniform double in [0, 1) from the top 53 bits of a hash.
constexpr double toUnit(std::uint64_t h) {
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

inline double hashUnit(std::uint64_t key, std::int64_t a, std::int64_t b = 0, std::int64_t c = 0) {
    return toUnit(hashIndices(key, a, b, c));
}

// A sequential generator (splitmix64) for a pattern's global choices.
class Rng {
public:
    explicit Rng(std::uint64_t key) : mState(key) {}
    double uniform() {
        mState += 0x9e3779b97f4a7c15ull;
        return toUnit(mix64(mState));
    }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

private:
    std::uint64_t mState;
};

// --- Scalar helpers ----------------------------------------------------------------------------------

// floor() without a libm call (GCC calls out for std::floor and std::round on baseline x86-64, and
// patterns evaluate millions of points). Valid for |x| < 2^31, far beyond any tile coordinate here.
inline int floorInt(double x) {
    const int i = static_cast<int>(x);
    return x < i ? i - 1 : i;
}
inline double floorFast(double x) {
    return static_cast<double>(floorInt(x));
}
inline double fract(double x) {
    return x - floorFast(x);
}
inline double clamp01(double x) {
    return std::clamp(x, 0.0, 1.0);
}
inline double smoothstep(double e0, double e1, double x) {
    const double t = clamp01((x - e0) / (e1 - e0));
    return t * t * (3.0 - 2.0 * t);
}
// The shortest signed difference between two coordinates on the unit circle, in [-0.5, 0.5].
inline double wrapDelta(double d) {
    return d - floorFast(d + 0.5);
}
// The smaller of i mod n (n > 0), for any integer i.
inline std::int64_t wrapIndex(std::int64_t i, std::int64_t n) {
    const std::int64_t r = i % n;
    return r < 0 ? r + n : r;
}

// A rounded (quarter-circle) edge: 0 at t = 0, rising with infinite slope, 1 with zero slope at t >= 1.
// Used for bevels where a flat top meets a groove: it reads as a rounded edge in the normal map.
inline double roundedEdge(double t) {
    const double s = 1.0 - clamp01(t);
    return std::sqrt(1.0 - s * s);
}

// Polynomial smooth maximum (Quilez): max(a, b) with the corner rounded over a width k.
inline double smoothMax(double a, double b, double k) {
    const double h = clamp01(0.5 + 0.5 * (a - b) / k);
    return b + (a - b) * h + k * h * (1.0 - h);
}

inline Vec3 rgb(double r, double g, double b) {
    return {r, g, b};
}

// --- Periodic noise ----------------------------------------------------------------------------------

// Gradient (Perlin) noise on the lattice Z^2 with integer periods (px, py): noise(x + px, y) ==
// noise(x, y) == noise(x, y + py). Roughly in [-1, 1], zero at lattice points.
double periodicNoise(double x, double y, int px, int py, std::uint64_t key);

// Fractal sum over `octaves` of periodicNoise in tile coordinates: octave k has (px, py) * 2^k cells
// across the tile and amplitude gain^k; the sum is divided by the total amplitude (so roughly [-1, 1]).
double periodicFbm(Vec2 uv, int px, int py, int octaves, std::uint64_t key, double gain = 0.5);

// --- Cells on the torus ------------------------------------------------------------------------------

// The nearest site of a CellLattice to a point, with the distance to the cell's border.
struct CellHit {
    int column;  // the site's cell, wrapped to [0, columns) x [0, rows): an id for per-cell choices
    int row;
    Vec2 offset;          // point - site, tile units
    double edgeDistance;  // distance from the point to the Voronoi border of its cell, tile units
};

// One site per cell of a columns x rows grid over the tile, each moved by a random jitter of up to
// `jitter` cell widths in each axis; odd rows shifted by `rowShift` cells (rows must then be even, so
// that the shift repeats). nearest() is the Voronoi cell of the periodic site set (exact borders, as
// distances to the bisectors). With jitter 0 and rowShift 0.5 the cells are hexagons.
class CellLattice {
public:
    CellLattice(int columns, int rows, double jitter, double rowShift, std::uint64_t key);
    CellHit nearest(Vec2 uv) const;
    int columns() const { return mColumns; }
    int rows() const { return mRows; }

private:
    int mColumns;
    int mRows;
    double mRowShift;
    std::vector<Vec2> mJitter;  // per wrapped cell, in cell units
};

// --- The patterns ------------------------------------------------------------------------------------

std::unique_ptr<Generator> makeBase(std::uint32_t seed);
std::unique_ptr<Generator> makeFabric(std::uint32_t seed);
std::unique_ptr<Generator> makeJeans(std::uint32_t seed);
std::unique_ptr<Generator> makeMetal(std::uint32_t seed);
std::unique_ptr<Generator> makeCushion(std::uint32_t seed);
std::unique_ptr<Generator> makeMiniBricks(std::uint32_t seed);
std::unique_ptr<Generator> makeStoneBricks(std::uint32_t seed);
std::unique_ptr<Generator> makeScales(std::uint32_t seed);
std::unique_ptr<Generator> makeHexTiles(std::uint32_t seed);
std::unique_ptr<Generator> makeWoodPlanks(std::uint32_t seed);

}  // namespace strata::pattern
