// Conservative cone maps (strata/relief/cone_map.h).
//
// Notation: cells C in max_mip.h's frame, horizontal units texels, vertical units depth. Per cell, m_C and
// M_C are its smallest and largest corner depths: a bilinear patch takes its extremes at its corners, so
// m_C <= d(x) <= M_C on the whole closed cell. We need, for every x in C and every y of the periodic plane
// with d(y) < d(x),
//     |y - x| / (d(x) - d(y)) >= c_C.                                                              (*)
// The plane is split around C into N_R(C), the (2R + 1) x (2R + 1) square of cells centred on C, and the
// rest, and each part gets its own bound:
//
// Near (y in N_R(C)). The gradient of a bilinear patch is (a(t), b(s)) with a affine in t alone and b
// affine in s alone, so |grad|^2 is convex and separable: its maximum over the cell is
// max(a(0)^2, a(1)^2) + max(b(0)^2, b(1)^2), taken at a corner. N_R(C) is convex, so the segment from x to
// y stays in it, and d, continuous and piecewise smooth along the segment, changes by at most L_R |y - x|
// where L_R is the largest gradient norm over the cells of N_R(C). Hence (*) holds with c = 1 / L_R. And
// where no cell of N_R(C) has a corner above M_C, d(y) >= M_C >= d(x) there and the near part bounds
// nothing (the top of a plateau keeps an unbounded cone).
//
// Far (y outside N_R(C), in a cell C'). The two squares are at least dist(C, C') >= R apart (they are R
// cells apart along some axis), and d(x) - d(y) <= M_C - m_C'. The cells are sorted into K bands of equal
// width over the map's own range of m; with lo_k the smallest m among band k's cells, every C' of band k
// satisfies
//     |y - x| / (d(x) - d(y)) >= max(D_k(C), R) / (M_C - lo_k)      (where M_C > lo_k; else d(y) >= d(x))
// with D_k(C) the distance from C to the nearest cell of band k. The far bound is the minimum of that over
// the bands. (The plan this follows used levels h_k = k / K in place of lo_k, and the nearest cell of
// bands 0..k in place of band k alone. Both are looser at the same cost, and with h_k a flat map at a
// depth between two levels got a finite cone where the true one is unbounded.)
//
// Distances between squares by a distance transform: for cells whose centres are (a, b) apart (integers),
// dist = sqrt(max(|a| - 1, 0)^2 + max(|b| - 1, 0)^2), which is the distance from C's centre to the nearest
// centre of the 3 x 3 dilation of the site set. So D_k is the Euclidean distance transform (Felzenszwalb &
// Huttenlocher 2012, "Distance Transforms of Sampled Functions": exact, separable, linear) of band k's
// dilated cells, taken on the torus: the column pass sweeps each column round twice each way, the row pass
// runs the lower envelope of parabolas over the row extended by min(W / 2, cap) cells each side, which
// holds every copy that can be the nearest. Its intersections are kept as exact integer fractions.
//
// Each radius R gives a valid bound min(1 / L_R, far_R), so the best of them is valid too:
//     c_C = min(maxRatio, max over R of min(1 / L_R, far_R)).
// R = 1 suits rough maps (the near region is small, its slope bound local); on smooth slopes the far bound
// at distance R is about R / (R + 2) of the truth, so larger R wins there.
//
// Work bounds that change no result: U_C, the current c_C, only decreases, and a far term >= U_C cannot
// lower the final c_C (it is <= U_C already, and a min with something >= it changes no max or min below
// it). So band k needs distances only up to cap_k = max over C of U_C (M_C - lo_k), kept per row; a row
// whose cap is <= 1 is skipped, and the bands stop when every row's is. Distances beyond the cap are clamped
// to it (still a lower bound of the truth, and the term then is >= U_C anyway).
//
// Rounding: the terms are computed in float, squared (no square root per band and cell), with relative
// errors of a few ulps (about 1e-7 each); the result is scaled by 1 - 1e-6 at the end so that rounding
// never makes a cone wider than the bound proves.
#include "strata/relief/cone_map.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/parallel.h"
#include "strata/image/quantize.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace strata {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kMaxDepthLevels = 4096;
// The radii R of the near regions (see the top). Each costs two 3 x 3 filters per step and a float per
// cell. Measured on the tests' smooth map (sum of sines, 24x16), mean generated / brute-force cone: 0.42
// with R = 1 alone, 0.62 adding 2, 0.73 adding 4; 3 or 5 added nothing measurable; rough maps use R = 1.
constexpr std::array<int, 3> kRadii = {1, 2, 4};
constexpr std::size_t kRadiusCount = kRadii.size();
// See "Rounding" at the top.
constexpr float kRoundingMargin = 1.0f - 1e-6f;

void validate(const Image& depth, const ConeMapOptions& options) {
    if (depth.empty()) throw Error(ErrorKind::InvalidInput, "cone map: the depth map is empty (0x0)");
    if (depth.channels() != 1)
        throw Error(ErrorKind::InvalidInput, "cone map: the depth map has " +
                                                 std::to_string(depth.channels()) + " channels, expected 1");
    if (options.depthLevels < 1 || options.depthLevels > kMaxDepthLevels)
        throw Error(ErrorKind::InvalidInput,
                    "cone map: depth levels = " + std::to_string(options.depthLevels) + " is outside [1, " +
                        std::to_string(kMaxDepthLevels) + "]");
    if (!(options.maxRatio >= 0.0f) || !std::isfinite(options.maxRatio))
        throw Error(ErrorKind::InvalidInput, "cone map: max ratio = " + formatNumber(options.maxRatio) +
                                                 " is not a finite number >= 0");
}

// Per-cell inputs of the bounds, in frame order (index y * W + x).
struct Cells {
    int width = 0;
    int height = 0;
    std::vector<float> highest;  // m_C, the smallest corner depth
    std::vector<float> deepest;  // M_C, the largest corner depth
    std::vector<float> slope2;   // the largest squared gradient norm over the cell, depth per texel

    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
};

Cells makeCells(const Image& depth) {
    Cells cells;
    const int width = cells.width = depth.width();
    const int height = cells.height = depth.height();
    const std::size_t count = depth.texelCount();
    cells.highest.resize(count);
    cells.deepest.resize(count);
    cells.slope2.resize(count);
    parallelForChunks(0, height, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            // Frame row y is image row H - 1 - y (max_mip.h), so frame row y + 1 is the image row above.
            const float* low = depth.row(height - 1 - y);
            const float* high = depth.row(height - 1 - (y + 1) % height);
            for (int x = 0; x < width; ++x) {
                const int x1 = x + 1 == width ? 0 : x + 1;
                const float d00 = low[x], d10 = low[x1], d01 = high[x], d11 = high[x1];
                const std::size_t i = cells.index(x, y);
                cells.highest[i] = std::min({d00, d10, d01, d11});
                cells.deepest[i] = std::max({d00, d10, d01, d11});
                const float a0 = d10 - d00, a1 = d11 - d01, b0 = d01 - d00, b1 = d11 - d10;
                cells.slope2[i] = std::max(a0 * a0, a1 * a1) + std::max(b0 * b0, b1 * b1);
            }
        }
    });
    return cells;
}

// Replaces `values` (W x H, wrapping) by its 3 x 3 maximum (pick = max) or minimum (pick = min), separably,
// through `scratch` (same size).
template <typename Pick>
void filter3(std::vector<float>& values, std::vector<float>& scratch, int width, int height, Pick pick) {
    parallelForChunks(0, height, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            const float* in = values.data() + static_cast<std::size_t>(y) * width;
            float* o = scratch.data() + static_cast<std::size_t>(y) * width;
            for (int x = 0; x < width; ++x)
                o[x] = pick(pick(in[x == 0 ? width - 1 : x - 1], in[x]), in[x + 1 == width ? 0 : x + 1]);
        }
    });
    parallelForChunks(0, height, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            const float* below =
                scratch.data() + static_cast<std::size_t>(y == 0 ? height - 1 : y - 1) * width;
            const float* at = scratch.data() + static_cast<std::size_t>(y) * width;
            const float* above =
                scratch.data() + static_cast<std::size_t>(y + 1 == height ? 0 : y + 1) * width;
            float* o = values.data() + static_cast<std::size_t>(y) * width;
            for (int x = 0; x < width; ++x) o[x] = pick(pick(below[x], at[x]), above[x]);
        }
    });
}

float pickMax(float a, float b) {
    return a < b ? b : a;
}

float pickMin(float a, float b) {
    return b < a ? b : a;
}

// The bounds of every cell, and the pass over the depth bands that tightens them.
class ConeBounds {
public:
    ConeBounds(const Cells& cells, int levels, float maxRatio)
        : mCells(cells),
          mWidth(cells.width),
          mHeight(cells.height),
          mMaxRatio2(maxRatio * maxRatio),
          mRadii(cells.highest.size()) {
        const std::size_t count = cells.highest.size();
        // Near bounds, squared: 1 / L_R^2 with L_R^2 the (2R + 1)^2 maximum of the cells' squared slopes,
        // grown from R - 1 by one 3 x 3 maximum at a time. Where no cell of N_R(C) has a corner above C's
        // deepest one, nothing in N_R(C) rises above any apex of C (d(y) >= m_C' >= M_C >= d(x)) and the
        // near part bounds nothing: the top of a plateau keeps an unbounded cone.
        std::vector<float> slope2 = cells.slope2;
        std::vector<float> highest = cells.highest;
        std::vector<float> scratch(count);
        int radius = 0;
        for (std::size_t r = 0; r < kRadiusCount; ++r) {
            for (; radius < kRadii[r]; ++radius) {
                filter3(slope2, scratch, mWidth, mHeight, pickMax);
                filter3(highest, scratch, mWidth, mHeight, pickMin);
            }
            parallelForChunks(0, mHeight, [&](int y0, int y1) {
                for (std::size_t i = mCells.index(0, y0); i < mCells.index(0, y1); ++i) {
                    const bool bounded = slope2[i] > 0.0f && highest[i] < cells.deepest[i];
                    mRadii[i].near2[r] = bounded ? 1.0f / slope2[i] : kInf;
                    mRadii[i].far2[r] = kInf;
                }
            });
        }
        mBound2.resize(count);
        parallelForChunks(0, mHeight, [&](int y0, int y1) {
            for (std::size_t i = mCells.index(0, y0); i < mCells.index(0, y1); ++i)
                mBound2[i] = boundOf(mRadii[i]);
        });
        makeBands(levels);
        mColumnDistance.resize(count);
        mRowCap2.resize(static_cast<std::size_t>(mHeight));
    }

    // Runs every band that can still lower a bound.
    void run() {
        if (mBandLo.empty()) return;
        // The first band's caps, row by row; later bands get theirs from the band before (fold).
        parallelForChunks(0, mHeight, [&](int y0, int y1) {
            for (int y = y0; y < y1; ++y) {
                float cap2 = 0.0f;
                for (std::size_t i = mCells.index(0, y); i < mCells.index(0, y + 1); ++i) {
                    const float rise = mCells.deepest[i] - mBandLo[0];
                    if (rise > 0.0f) cap2 = std::max(cap2, mBound2[i] * rise * rise);
                }
                mRowCap2[static_cast<std::size_t>(y)] = cap2;
            }
        });
        for (std::size_t band = 0; band < mBandLo.size(); ++band) {
            const float cap2 = *std::max_element(mRowCap2.begin(), mRowCap2.end());
            // See "Work bounds" at the top: cap <= 1 means no term of this band or a later one matters.
            if (!(cap2 > 1.0f)) break;
            runBand(band, std::sqrt(cap2));
        }
    }

    // c_C, in texels per unit of depth, with the rounding margin, capped (exactly maxRatio where the cap
    // binds).
    float ratio(std::size_t i, float maxRatio) const {
        return mBound2[i] >= mMaxRatio2 ? maxRatio
                                        : std::min(maxRatio, std::sqrt(mBound2[i]) * kRoundingMargin);
    }

private:
    // Per cell and radius R (kRadii), squared: the near bound 1 / L_R^2 and the far bound over the bands run
    // so far. Kept together so that the band pass touches one cache line per cell.
    struct Radii {
        std::array<float, kRadiusCount> near2;
        std::array<float, kRadiusCount> far2;
    };

    // A position on the row as an exact fraction (integer arithmetic: the envelope's loop would otherwise
    // wait on a division per parabola). The denominator is positive; 0 / 0 stands for minus infinity.
    struct Fraction {
        long long numerator = 0;
        long long denominator = 0;
        bool above(long long n, long long d) const {
            return denominator != 0 && n * denominator > numerator * d;
        }
        bool atOrBefore(int x) const { return numerator <= static_cast<long long>(x) * denominator; }
    };

    struct RowBuffers {
        explicit RowBuffers(std::size_t width, std::size_t span)
            : f(width), where(span), offset(span), start(span) {}
        std::vector<int> f;             // per cell of the row, the dilated squared column distance, or -1
        std::vector<int> where;         // the envelope's parabolas: vertex positions,
        std::vector<long long> offset;  // their f(q) + q^2,
        std::vector<Fraction> start;    // and where each starts to be the lowest
    };

    // min(maxRatio, max_R min(1 / L_R, far_R)), squared; the rounding margin comes last (ratio()), so that
    // the skips in fold() compare with the bound itself.
    float boundOf(const Radii& radii) const {
        float best = 0.0f;
        for (std::size_t r = 0; r < kRadiusCount; ++r)
            best = std::max(best, std::min(radii.near2[r], radii.far2[r]));
        return std::min(mMaxRatio2, best);
    }

    // Sorts the cells into bands of equal width over [min m, max m] (the map's own range, so that no band
    // is wasted on depths it lacks), and records each non-empty band's smallest m.
    void makeBands(int levels) {
        const auto [lowest, highest] = std::minmax_element(mCells.highest.begin(), mCells.highest.end());
        const float base = *lowest, range = *highest - *lowest;
        const auto scale = static_cast<float>(levels) / range;
        std::vector<float> lo(static_cast<std::size_t>(levels), kInf);
        mBand.resize(mCells.highest.size());
        for (std::size_t i = 0; i < mBand.size(); ++i) {
            const float m = mCells.highest[i];
            // The band boundaries need no care: the bound uses each band's true smallest m, whatever
            // cells it holds.
            const int b = range > 0.0f ? std::min(levels - 1, static_cast<int>((m - base) * scale)) : 0;
            mBand[i] = static_cast<std::uint16_t>(b);
            lo[static_cast<std::size_t>(b)] = std::min(lo[static_cast<std::size_t>(b)], m);
        }
        // Renumber the non-empty bands 0, 1, ... in increasing lo.
        std::vector<std::uint16_t> renumber(static_cast<std::size_t>(levels), 0);
        for (int b = 0; b < levels; ++b) {
            if (lo[static_cast<std::size_t>(b)] == kInf) continue;
            renumber[static_cast<std::size_t>(b)] = static_cast<std::uint16_t>(mBandLo.size());
            mBandLo.push_back(lo[static_cast<std::size_t>(b)]);
        }
        for (std::uint16_t& band : mBand) band = renumber[band];
    }

    // Distance in y from each cell to the nearest cell of `band` in its column (periodic), saturated at
    // `saturate`: a forward and a backward sweep, each once round to warm up and once to store.
    void columnPass(std::uint16_t band, int saturate) {
        constexpr int kBlock = 256;
        const int blocks = (mWidth + kBlock - 1) / kBlock;
        const auto limit = static_cast<std::uint16_t>(saturate);
        // A count saturates after `saturate` rows, so the warm-up needs no more of them.
        const int warm = std::min(mHeight, saturate);
        parallelForChunks(0, blocks, [&](int b0, int b1) {
            std::array<std::uint16_t, kBlock> count;
            for (int b = b0; b < b1; ++b) {
                const int x0 = b * kBlock, n = std::min(mWidth, x0 + kBlock) - x0;
                const auto sweep = [&](int y, auto store) {
                    const std::uint16_t* bands = mBand.data() + mCells.index(x0, y);
                    std::uint16_t* out = mColumnDistance.data() + mCells.index(x0, y);
                    for (int x = 0; x < n; ++x) {
                        const auto next = static_cast<std::uint16_t>(std::min<int>(count[x] + 1, limit));
                        count[x] = bands[x] == band ? std::uint16_t{0} : next;
                        store(out[x], count[x]);
                    }
                };
                const auto none = [](std::uint16_t&, std::uint16_t) {};
                std::fill(count.begin(), count.end(), limit);
                for (int y = mHeight - warm; y < mHeight; ++y) sweep(y, none);
                for (int y = 0; y < mHeight; ++y) sweep(y, [](std::uint16_t& o, std::uint16_t c) { o = c; });
                std::fill(count.begin(), count.end(), limit);
                for (int y = warm - 1; y >= 0; --y) sweep(y, none);
                for (int y = mHeight - 1; y >= 0; --y)
                    sweep(y, [](std::uint16_t& o, std::uint16_t c) { o = std::min(o, c); });
            }
        });
    }

    // One band: its distance transform up to `cap`, folded into the bounds; leaves the next band's caps in
    // mRowCap2.
    void runBand(std::size_t band, float cap) {
        const float lo = mBandLo[band];
        const float nextLo = band + 1 < mBandLo.size() ? mBandLo[band + 1] : kInf;
        // The column distance of a dilated site is one less than the raw one; anything past cap + 1 is as
        // good as infinite.
        const int saturate = static_cast<int>(std::min(65535.0f, std::floor(cap) + 2.0f));
        columnPass(static_cast<std::uint16_t>(band), saturate);
        // Copies further than half a period or than the cap are never the nearest that matters.
        const int extend = std::min(mWidth / 2, static_cast<int>(std::floor(cap)));
        parallelForChunks(0, mHeight, [&](int y0, int y1) {
            RowBuffers buffers(static_cast<std::size_t>(mWidth),
                               static_cast<std::size_t>(mWidth + 2 * extend));
            for (int y = y0; y < y1; ++y) {
                float& rowCap2 = mRowCap2[static_cast<std::size_t>(y)];
                // A row whose cap is <= 1 has no cell this band (or a later one) can lower; its cap stays an
                // upper bound for the next band, whose lo is larger.
                if (!(rowCap2 > 1.0f)) continue;
                const int parabolas = envelope(y, cap, extend, buffers);
                rowCap2 = fold(y, lo, nextLo, cap * cap, parabolas, buffers);
            }
        });
    }

    // Row y's lower envelope of the parabolas (x - q)^2 + f(q) over the row extended by `extend` cells each
    // side (Felzenszwalb & Huttenlocher, Algorithm 1), f the squared y-distance to the 3 x 3 dilation of the
    // band's cells: the raw column distance less one, dilated along x by a 3-wide minimum, or -1 (no
    // parabola) past the cap. Returns the parabola count.
    int envelope(int y, float cap, int extend, RowBuffers& buffers) const {
        const std::uint16_t* column = mColumnDistance.data() + mCells.index(0, y);
        const int limit = static_cast<int>(cap);
        int* f = buffers.f.data();
        const auto squared = [limit](int raw) {
            const int g = std::max(0, raw - 1);
            return g <= limit ? g * g : -1;
        };
        if (mWidth == 1) {
            f[0] = squared(column[0]);
        } else {
            f[0] = squared(std::min({column[mWidth - 1], column[0], column[1]}));
            for (int x = 1; x < mWidth - 1; ++x)
                f[x] = squared(std::min({column[x - 1], column[x], column[x + 1]}));
            f[mWidth - 1] = squared(std::min({column[mWidth - 2], column[mWidth - 1], column[0]}));
        }
        int parabolas = 0;
        int* where = buffers.where.data();
        long long* offset = buffers.offset.data();
        Fraction* start = buffers.start.data();
        // Magnitudes: |h| < 2^31 and |2 (q - where)| < 2^16 for sides up to 16384, so the cross products in
        // Fraction stay far inside 64 bits.
        const auto push = [&](int q, int fq) {
            const long long h = static_cast<long long>(fq) + static_cast<long long>(q) * q;
            Fraction s;  // where the new parabola goes below the top one (minus infinity if none is left)
            while (parabolas > 0) {
                const int top = parabolas - 1;
                const long long n = h - offset[top], d = 2 * static_cast<long long>(q - where[top]);
                // The first parabola starts at minus infinity and is never removed.
                if (top == 0 || start[top].above(n, d)) {
                    s = {n, d};
                    break;
                }
                --parabolas;
            }
            where[parabolas] = q;
            offset[parabolas] = h;
            start[parabolas] = s;
            ++parabolas;
        };
        // extend <= W / 2: the copies of the row's end, the row, the copies of its start.
        for (int q = -extend; q < 0; ++q)
            if (f[q + mWidth] >= 0) push(q, f[q + mWidth]);
        for (int q = 0; q < mWidth; ++q)
            if (f[q] >= 0) push(q, f[q]);
        for (int q = mWidth; q < mWidth + extend; ++q)
            if (f[q - mWidth] >= 0) push(q, f[q - mWidth]);
        return parabolas;
    }

    // Folds the band's squared distances of row y (from its envelope, clamped to cap2) into the bounds;
    // returns the row's squared cap for the next band (lo = nextLo).
    float fold(int y, float lo, float nextLo, float cap2, int parabolas, const RowBuffers& buffers) {
        const std::size_t row = mCells.index(0, y);
        const float* deepest = mCells.deepest.data() + row;
        float* bound2 = mBound2.data() + row;
        float nextCap2 = 0.0f;
        int j = 0;
        for (int x = 0; x < mWidth; ++x) {
            const float rise = deepest[x] - lo;
            if (!(rise > 0.0f)) continue;
            const float rise2 = rise * rise;
            // The smallest term of this band (R = 1) needs a distance below bound * rise to lower the bound.
            if (bound2[x] * rise2 > 1.0f) {
                float distance2 = cap2;
                if (parabolas > 0) {
                    while (j + 1 < parabolas && buffers.start[static_cast<std::size_t>(j + 1)].atOrBefore(x))
                        ++j;
                    const long long q = buffers.where[static_cast<std::size_t>(j)];
                    const long long d2 =
                        buffers.offset[static_cast<std::size_t>(j)] - q * q + (x - q) * (x - q);
                    distance2 = std::min(cap2, static_cast<float>(d2));
                }
                if (distance2 < bound2[x] * rise2) {
                    const float inverse2 = 1.0f / rise2;
                    Radii& radii = mRadii[row + static_cast<std::size_t>(x)];
                    for (std::size_t r = 0; r < kRadiusCount; ++r) {
                        const auto radius2 = static_cast<float>(kRadii[r] * kRadii[r]);
                        radii.far2[r] = std::min(radii.far2[r], std::max(distance2, radius2) * inverse2);
                    }
                    bound2[x] = boundOf(radii);
                }
            }
            const float nextRise = deepest[x] - nextLo;
            if (nextRise > 0.0f) nextCap2 = std::max(nextCap2, bound2[x] * nextRise * nextRise);
        }
        return nextCap2;
    }

    const Cells& mCells;
    int mWidth;
    int mHeight;
    float mMaxRatio2;
    std::vector<Radii> mRadii;
    std::vector<float> mBound2;                  // U_C^2, the current c_C^2
    std::vector<float> mBandLo;                  // per non-empty band, its smallest m, increasing
    std::vector<std::uint16_t> mBand;            // per cell, its band
    std::vector<std::uint16_t> mColumnDistance;  // per cell, the column pass's result
    std::vector<float> mRowCap2;                 // per row, its cap for the band being run
};

}  // namespace

float coneMapMaxRatio(const Image& depth, const ConeMapOptions& options) {
    validate(depth, options);
    return options.maxRatio > 0.0f ? options.maxRatio
                                   : static_cast<float>(std::max(depth.width(), depth.height()));
}

Image coneMap(const Image& depth, const ConeMapOptions& options) {
    const float maxRatio = coneMapMaxRatio(depth, options);
    for (int y = 0; y < depth.height(); ++y)
        for (int x = 0; x < depth.width(); ++x)
            if (!std::isfinite(depth.at(x, y)))
                throw Error(ErrorKind::InvalidInput, "cone map: depth " + formatNumber(depth.at(x, y)) +
                                                         " at texel (" + std::to_string(x) + ", " +
                                                         std::to_string(y) + ") is not finite");
    const Cells cells = makeCells(depth);
    ConeBounds bounds(cells, options.depthLevels, maxRatio);
    bounds.run();
    Image out = Image::uninitialized(depth.width(), depth.height(), 1);
    parallelForChunks(0, depth.height(), [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < depth.width(); ++x) out.at(x, y) = bounds.ratio(cells.index(x, y), maxRatio);
    });
    return out;
}

PackedConeMap packConeMap(const Image& depth, const ConeMapOptions& options) {
    const Image ratios = coneMap(depth, options);
    PackedConeMap packed;
    packed.maxRatio = coneMapMaxRatio(depth, options);
    packed.depthLevels = options.depthLevels;
    packed.texels = Image(depth.width(), depth.height(), 2);
    const int width = depth.width(), height = depth.height();
    // Frame row y is image row height - 1 - y (see the top of cone_map.h).
    const auto texel = [&](int x, int y) { return depth.at(x % width, height - 1 - (y % height)); };
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float highest =
                std::min({texel(x, y), texel(x + 1, y), texel(x, y + 1), texel(x + 1, y + 1)});
            // To 16 bits, never deeper than the cell's highest point (a depth that is already a 16-bit
            // value keeps it exactly).
            long q = toUnorm16(highest);
            if (q > 0 && static_cast<float>(q) / 65535.0f > highest) --q;
            packed.texels.at(x, y, 0) = static_cast<float>(q) / 65535.0f;
            packed.texels.at(x, y, 1) =
                static_cast<float>(encodeConeRatio(ratios.at(x, y), packed.maxRatio)) / 65535.0f;
        }
    }
    return packed;
}

std::uint16_t encodeConeRatio(float ratio, float maxRatio) {
    STRATA_CHECK(maxRatio > 0.0f && std::isfinite(maxRatio));
    if (!(ratio > 0.0f)) return 0;
    if (ratio >= maxRatio) return 65535;
    const double scaled = std::sqrt(static_cast<double>(ratio) / static_cast<double>(maxRatio)) * 65535.0;
    auto q = static_cast<int>(std::floor(scaled));
    // The float decode can round above the exact (q / 65535)^2 * maxRatio; step down until it does not, so
    // that decode(encode(r)) <= r holds as the decoder computes it.
    while (q > 0 && decodeConeRatio(static_cast<std::uint16_t>(q), maxRatio) > ratio) --q;
    return static_cast<std::uint16_t>(q);
}

float decodeConeRatio(std::uint16_t q, float maxRatio) {
    const float s = static_cast<float>(q) / 65535.0f;
    return s * s * maxRatio;
}

}  // namespace strata
