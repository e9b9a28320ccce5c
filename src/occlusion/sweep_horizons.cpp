// The sweep horizon search (AoMethod::Sweep); see the comment on AoMethod::Sweep in
// strata/occlusion/ambient_occlusion.h for what it computes and how exact it is.
//
// Per direction, parallel lines one texel apart sweep the map. Every line has the same sample times
// and interpolation weights, only its heights differ, so kLanes neighbouring lines run in lockstep,
// one per SIMD lane: the control flow that depends on t alone (blocks, windows, which texel asks which
// hull) is shared, and the hull loops that depend on the heights run until every lane is done, with
// masks. Opposite directions (i and i + M/2, M even) use the same lines, texels and samples, looking
// the other way along them, so they share the samples and every hull. Per line group, the near field,
// the point at R, then the far field raise each texel's tan h; then the sink reads them.
//
// The near field (up to kNear columns), walked exactly on each texel's own line: every crossing and the
// quadratic arc inside each cell, plus the t -> 0+ slope. Every texel's own line has the same offsets
// to the grid, so this is one stencil with constant weights; the relief is stored with the minor axis
// contiguous, so the group's texels at one column are contiguous and the stencil is plain vector loads.
//
// The far field (distances kNear columns .. R). A line's profile is sampled at every major texel centre
// and every minor grid crossing (the bilinear relief is linear along both), and texel P, the texel
// nearest to the line at a column, asks for the largest elevation (z - zP) / |tP - t| over the samples
// with |tP - t| in [kNear dt, R] on its side, plus the point at exactly R. Those windows slide, so the
// line is cut into blocks as long as a window (L = R - kNear dt): a window lies in the end of one block
// and the start of the next (or, rarely, inside one block: then its samples are read one by one).
// Block by block, a forward pass pushes the block's samples from its first onto an upper convex hull
// on a stack (Timonen & Westerholm 2010: pushing a point pops the ones it hides) and answers the
// windows that end in the block; a backward pass pushes them from its last and answers the windows
// that start in it. Each sample is pushed at most twice and popped at most twice; each texel makes at
// most two tangent searches, each from where the previous one on that hull ended. A hull is only
// pushed up to where some lane needs it: a lane skips a hull when the highest sample in its part of
// the window, at that part's nearest distance, cannot beat the tan h it already has. A lane's stacks
// are its own (slot d of lane l at d kLanes + l; reads are gathers), but every lane pushes the same
// samples at the same time, so whether a stack is empty is shared.
//
// The line is at most half a texel beside P, and that offset only matters beyond kNear columns, where
// it changes the elevation by at most (offset x slope across) / distance.
#include "horizon_line.h"
#include "horizon_search.h"

#if defined(__x86_64__) || defined(__i386__)
#define STRATA_SWEEP_X86
#include <immintrin.h>  // declares the AVX2 builtins
#endif
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

namespace strata::detail {
namespace {

// Columns walked exactly on each texel's own line before the far field takes over. 4 keeps the far
// field's lateral error below 0.003 AO RMSE against the exact walk on every built-in pattern
// (docs/occlusion.md); 2 doubles it, 8 costs twice the time for a further halving.
constexpr int kNear = 4;
constexpr int kPad = kNear + 2;
// Unpaired, the window ends past one block that its texels may read sample by sample rather than start
// another block.
constexpr int kTailSteps = 16;

// Lines per group: one AVX2 register of floats. The lanes' hull loops run as long as their slowest
// lane, so wider groups gain less than their width.
constexpr int kLanes = 8;

// GCC vector extensions: plain SSE2 in groupHorizonsPortable, AVX2 in groupHorizonsAvx2 (below). Every
// function that takes or returns them is always inlined into those two, so the ABI of 32-byte vectors
// without AVX, which GCC warns about, never applies.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
using Floats = float __attribute__((vector_size(kLanes * sizeof(float))));
using Ints = std::int32_t __attribute__((vector_size(kLanes * sizeof(std::int32_t))));
using Words = long long __attribute__((vector_size(kLanes * sizeof(std::int32_t))));

constexpr Ints kLaneIndex = {0, 1, 2, 3, 4, 5, 6, 7};
static_assert(kLanes == 8, "kLaneIndex lists the lanes");

[[gnu::always_inline]] inline Floats load(const float* p) {
    Floats v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store(float* p, Floats v) {
    std::memcpy(p, &v, sizeof v);
}
[[gnu::always_inline]] inline Floats splat(float x) {
    return Floats{} + x;
}
[[gnu::always_inline]] inline Floats max(Floats a, Floats b) {
    return a > b ? a : b;
}
[[gnu::always_inline]] inline Floats min(Floats a, Floats b) {
    return a < b ? a : b;
}
[[gnu::always_inline]] inline Ints max(Ints a, Ints b) {
    return a > b ? a : b;
}
[[gnu::always_inline]] inline Ints min(Ints a, Ints b) {
    return a < b ? a : b;
}
// Whether any lane is set. kAvx2: one VPTEST, in code that only runs inside a function compiled for
// AVX2 (the builtin, unlike its intrinsic, may sit in a function inlined into one).
template <bool kAvx2>
[[gnu::always_inline]] inline bool any(Ints mask) {
    const auto w = std::bit_cast<Words>(mask);
#ifdef STRATA_SWEEP_X86
    if constexpr (kAvx2) return !__builtin_ia32_ptestz256(w, w);
#endif
    return ((w[0] | w[1]) | (w[2] | w[3])) != 0;
}
// The stack slot d of every lane.
[[gnu::always_inline]] inline Ints slot(Ints d) {
    return d * kLanes + kLaneIndex;
}

// A point of each lane's profile.
struct Points {
    Floats t;
    Floats z;
};
[[gnu::always_inline]] inline Points select(Ints mask, const Points& a, const Points& b) {
    return {mask ? a.t : b.t, mask ? a.z : b.z};
}
// Stacks hold (t, z) pairs, so that reading a lane's point is one 8-byte load: entry e of lane l at
// 2 (e kLanes + l). Lanes 0, 1, 4, 5 are read into one register and 2, 3, 6, 7 into another, so that
// one shuffle within 128-bit halves (SHUFPS) splits them into t and z in lane order.
using Pairs = double __attribute__((vector_size(kLanes * sizeof(float))));
constexpr int kPairLane[2][kLanes / 2] = {{0, 1, 4, 5}, {2, 3, 6, 7}};
constexpr Ints kFirstOfPair = {0, 2, 8, 10, 4, 6, 12, 14};
constexpr Ints kPairOfLow = {0, 8, 1, 9, 4, 12, 5, 13};  // (t, z) of lanes 0, 1, 4, 5
constexpr Ints kPairOfHigh = {2, 10, 3, 11, 6, 14, 7, 15};
[[gnu::always_inline]] inline Points gather(const float* pairs, Ints index) {
    Pairs low;
    Pairs high;
    for (int l = 0; l < kLanes / 2; ++l) {
        std::memcpy(&low[l], pairs + 2 * index[kPairLane[0][l]], sizeof(double));
        std::memcpy(&high[l], pairs + 2 * index[kPairLane[1][l]], sizeof(double));
    }
    const auto a = std::bit_cast<Floats>(low);
    const auto b = std::bit_cast<Floats>(high);
    return {__builtin_shuffle(a, b, kFirstOfPair), __builtin_shuffle(a, b, kFirstOfPair + 1)};
}
[[gnu::always_inline]] inline void scatter(float* pairs, Ints index, const Points& p) {
    const auto low = std::bit_cast<Pairs>(__builtin_shuffle(p.t, p.z, kPairOfLow));
    const auto high = std::bit_cast<Pairs>(__builtin_shuffle(p.t, p.z, kPairOfHigh));
    for (int l = 0; l < kLanes / 2; ++l) {
        std::memcpy(pairs + 2 * index[kPairLane[0][l]], &low[l], sizeof(double));
        std::memcpy(pairs + 2 * index[kPairLane[1][l]], &high[l], sizeof(double));
    }
}

// > 0 where c lies above the line through a and b (a.t < b.t).
[[gnu::always_inline]] inline Floats orient(const Points& a, const Points& b, const Points& c) {
    return (b.t - a.t) * (c.z - a.z) - (b.z - a.z) * (c.t - a.t);
}

// z = -S d in (major a, minor b) order, the minor axis contiguous: column a holds every minor index b.
// The minor axis is stored twice over (b in [0, 2 sizeB)) so that line j's row j + b never wraps, and
// wrapped texels pad every side for the near field, plus kLanes more at the end for the last lane.
class PaddedRelief {
public:
    PaddedRelief(const Image& depth, bool xMajor, float scale)
        : mSizeA(xMajor ? depth.width() : depth.height()),
          mSizeB(xMajor ? depth.height() : depth.width()),
          mStride(2 * mSizeB + 2 * kPad + kLanes),
          // Every entry is written below: no zero fill (the map is twice the depth map's size).
          mZ(std::make_unique_for_overwrite<float[]>(static_cast<std::size_t>(mStride) *
                                                     static_cast<std::size_t>(mSizeA + 2 * kPad))) {
        tbb::parallel_for(tbb::blocked_range<int>(-kPad, mSizeA + kPad),
                          [&](const tbb::blocked_range<int>& as) {
                              for (int a = as.begin(); a != as.end(); ++a) {
                                  const int aw = MajorMinorDepth::wrap(a, mSizeA);
                                  float* column = mZ.get() + index(a, -kPad);
                                  int bw = MajorMinorDepth::wrap(-kPad, mSizeB);
                                  for (int b = -kPad; b < 2 * mSizeB + kPad + kLanes; ++b) {
                                      *column++ = -scale * (xMajor ? depth.at(aw, bw) : depth.at(bw, aw));
                                      if (++bw == mSizeB) bw = 0;
                                  }
                              }
                          });
    }
    // a in [-kPad, sizeA + kPad), b in [-kPad, 2 sizeB + kPad + kLanes).
    std::ptrdiff_t index(int a, int b) const {
        return static_cast<std::ptrdiff_t>(a + kPad) * mStride + static_cast<std::ptrdiff_t>(b + kPad);
    }
    const float* data() const { return mZ.get(); }
    // The index step of one major column; one minor row is 1.
    std::ptrdiff_t majorStride() const { return mStride; }
    int sizeA() const { return mSizeA; }
    int sizeB() const { return mSizeB; }

private:
    int mSizeA;
    int mSizeB;
    std::ptrdiff_t mStride;
    std::unique_ptr<float[]> mZ;
};

// One cell-segment of the near field, relative to texel P = (a, r): the segment runs inside the cell
// between major steps q - 1 and q (towards the direction) and minor rows r + minor, r + minor + 1,
// from (alpha0, beta0) to (alpha1, beta1) in the cell's unit square, from distance t0 to t1. The
// cell's corner (q - 1, minor) is at index offset from P's.
struct NearSegment {
    std::ptrdiff_t offset;
    float alpha0, beta0, alpha1, beta1;
    float t0, t1;
    // Derived, so that the stencil does no scalar division per texel: 1 / t1, 1 / (t1 - t0), and the
    // arc's z''/2 per unit twist, (alpha1 - alpha0) (beta1 - beta0) / (t1 - t0)^2.
    float invT1 = 0.0f;
    float invLength = 0.0f;
    float twist = 0.0f;
};

// The near field of one direction: the cell segments along a texel's own line, minor offset q g at
// step q, up to kNear steps or R, whichever is nearer, and the t -> 0+ slope.
struct NearStencil {
    std::vector<NearSegment> segments;
    float coefMajor = 0.0f;  // the t -> 0+ slope: coefMajor (z(a + step) - zP) + coefMinor (z(r + side) - zP)
    float coefMinor = 0.0f;
    std::ptrdiff_t aheadOffset = 0;  // index offsets of (a + step, r) and (a, r + side) from P
    std::ptrdiff_t sideOffset = 0;
    std::ptrdiff_t majorOffset = 0;  // of one step towards the direction

    NearStencil(const LineDirection& dir, const PaddedRelief& relief, double radius) {
        const double dt = dir.dt;
        majorOffset = dir.step * relief.majorStride();
        double b0 = 0.0;
        for (int q = 1; q <= kNear; ++q) {
            const double b1 = q * dir.g;
            const double t0 = (q - 1) * dt;
            const double t1 = q * dt;
            const double n = std::ceil(std::min(b0, b1));
            std::vector<std::pair<double, double>> cuts{{0.0, b0}};  // (alpha, b)
            if (n > std::min(b0, b1) && n < std::max(b0, b1)) cuts.emplace_back((n - b0) / (b1 - b0), n);
            cuts.emplace_back(1.0, b1);
            for (std::size_t s = 0; s + 1 < cuts.size(); ++s) {
                double alpha0 = cuts[s].first;
                double alpha1 = cuts[s + 1].first;
                double beta0 = cuts[s].second;
                double beta1 = cuts[s + 1].second;
                const double s0 = t0 + alpha0 * (t1 - t0);
                double s1 = t0 + alpha1 * (t1 - t0);
                if (s0 >= radius) break;
                if (s1 > radius) {  // the segment ends at R
                    const double f = (radius - s0) / (s1 - s0);
                    alpha1 = alpha0 + f * (alpha1 - alpha0);
                    beta1 = beta0 + f * (beta1 - beta0);
                    s1 = radius;
                }
                const double m = std::floor(0.5 * (cuts[s].second + cuts[s + 1].second));
                NearSegment segment{(q - 1) * majorOffset + static_cast<std::ptrdiff_t>(m),
                                    static_cast<float>(alpha0),
                                    static_cast<float>(beta0 - m),
                                    static_cast<float>(alpha1),
                                    static_cast<float>(beta1 - m),
                                    static_cast<float>(s0),
                                    static_cast<float>(s1)};
                segment.invT1 = 1.0f / segment.t1;
                segment.invLength = 1.0f / (segment.t1 - segment.t0);
                segment.twist = (segment.alpha1 - segment.alpha0) * (segment.beta1 - segment.beta0) *
                                segment.invLength * segment.invLength;
                segments.push_back(segment);
            }
            b0 = b1;
        }
        const int sizeA = relief.sizeA();
        const int sizeB = relief.sizeB();
        const double cx = std::abs(dir.cosPhi) * (dir.xMajor ? sizeA : sizeB);
        const double cy = std::abs(dir.sinPhi) * (dir.xMajor ? sizeB : sizeA);
        coefMajor = static_cast<float>(dir.xMajor ? cx : cy);
        coefMinor = static_cast<float>(dir.xMajor ? cy : cx);
        aheadOffset = majorOffset;
        sideOffset = dir.xMajor ? dir.sideY : dir.sideX;
    }
};

// The direction opposite dir, on the same lines: its texels and samples are dir's, in reverse.
LineDirection opposite(LineDirection dir) {
    dir.cosPhi = -dir.cosPhi;
    dir.sinPhi = -dir.sinPhi;
    dir.step = -dir.step;
    dir.g = -dir.g;
    dir.sideX = -dir.sideX;
    dir.sideY = -dir.sideY;
    return dir;
}

// What every line of one direction shares, and of its opposite when `paired` (side 1; side 0 is the
// direction). Line j (j in [0, sizeB)) at processing step k crosses column a_k = start + order k
// (unwrapped; against the direction, so that side 0's samples lie towards smaller t) at minor
// coordinate j + a_k slope; t = k dt grows along the line. Both sides see the same lines, texels and
// samples: side 0 looks towards smaller t, side 1 towards larger. Indices are those of line 0; line j
// adds j.
struct DirectionPlan {
    LineDirection dir;
    bool paired = false;
    int sizeA = 0;
    int sizeB = 0;
    double radius = 1.0;
    // Queries, k in [0, sizeA): the texel of line j at step k is (texelColumn[k], j + texelRow[k]).
    std::vector<int> texelColumn;
    std::vector<int> texelRow;
    std::vector<std::ptrdiff_t> texelIndex;
    std::vector<NearStencil> near;  // per side
    // The far field, empty when R <= kNear dt.
    bool hasFar = false;
    // Samples in order of t: z = (1 - w) Z[index0 + j] + w Z[index1 + j].
    std::vector<float> sampleT;
    std::vector<std::ptrdiff_t> sampleIndex0;
    std::vector<std::ptrdiff_t> sampleIndex1;
    std::vector<float> sampleW;
    std::vector<int> sampleBlock;       // floor((t - t0) / B) from 0, t0 the first texel's window end
    std::vector<int> blockFirstSample;  // block -> its first sample (and one past the end)
    // Per side and step k: the samples in texel k's window [first, last], those between kNear steps and
    // R away, and the point at exactly R: bilinear between columns k1, k1 + 1 (weight alpha of the
    // second) and rows r, r + 1 (weight frac); index of (k1, r) for line 0, and of (k1 + 1, r).
    struct Side {
        std::vector<int> first;
        std::vector<int> last;
        std::vector<std::ptrdiff_t> boundaryIndex0;
        std::vector<std::ptrdiff_t> boundaryIndex1;
        std::vector<float> boundaryFrac;
        std::vector<float> boundaryAlpha;
    };
    Side sides[2];

    DirectionPlan(const LineDirection& direction, bool withOpposite, const PaddedRelief& relief,
                  double radiusTiles)
        : dir(direction),
          paired(withOpposite),
          sizeA(relief.sizeA()),
          sizeB(relief.sizeB()),
          radius(radiusTiles) {
        const int order = -dir.step;
        const int start = order < 0 ? sizeA - 1 : 0;
        const double slope = dir.g * dir.step;  // minor per +1 major
        const double dt = dir.dt;
        auto minorAt = [&](double k) { return (start + order * k) * slope; };
        auto column = [&](int k) { return MajorMinorDepth::wrap(start + order * k, sizeA); };
        auto wrapB = [&](double b) { return MajorMinorDepth::wrap(static_cast<int>(b), sizeB); };

        texelColumn.resize(static_cast<std::size_t>(sizeA));
        texelRow.resize(texelColumn.size());
        texelIndex.resize(texelColumn.size());
        for (int k = 0; k < sizeA; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            texelColumn[kk] = column(k);
            texelRow[kk] = wrapB(std::round(minorAt(k)));
            texelIndex[kk] = relief.index(texelColumn[kk], texelRow[kk]);
        }
        near.emplace_back(dir, relief, radius);
        if (paired) near.emplace_back(opposite(dir), relief, radius);

        const double farLength = radius - kNear * dt;
        hasFar = farLength > 0.0 && sizeA > kNear;
        if (!hasFar) return;
        const int reach = static_cast<int>(std::ceil(radius / dt)) + 1;
        const int firstStep = -reach;
        const int lastStep = paired ? sizeA - 1 + reach : sizeA - 1 - kNear;
        std::vector<int> columnSample;  // k - firstStep -> the index of the column sample at step k
        for (int k = firstStep; k <= lastStep; ++k) {
            if (k > firstStep) {
                const double b0 = minorAt(k - 1);
                const double b1 = minorAt(k);
                const double n = std::ceil(std::min(b0, b1));
                if (n > std::min(b0, b1) && n < std::max(b0, b1)) {
                    const double f = (n - b0) / (b1 - b0);
                    const int row = wrapB(n);
                    sampleT.push_back(static_cast<float>((k - 1 + f) * dt));
                    sampleIndex0.push_back(relief.index(column(k - 1), row));
                    sampleIndex1.push_back(relief.index(column(k), row));
                    sampleW.push_back(static_cast<float>(f));
                }
            }
            const double b = minorAt(k);
            const double fb = std::floor(b);
            columnSample.push_back(static_cast<int>(sampleT.size()));
            sampleT.push_back(static_cast<float>(k * dt));
            sampleIndex0.push_back(relief.index(column(k), wrapB(fb)));
            sampleIndex1.push_back(relief.index(column(k), wrapB(fb) + 1));
            sampleW.push_back(static_cast<float>(b - fb));
        }
        // Blocks of B >= L from the first texel's window end: a window then ends in the block where it
        // starts or in the next. Each block's start costs a backward hull of the block before, so
        // unpaired, when one block of B > L holds every window end of the line but the last few (R about
        // a tile: the ends span (sizeA - 1) dt), it does; those few windows lie inside one block and read
        // their samples one by one. Paired, the other side's windows start where this side's end, so
        // B = L.
        const double anchor = -kNear * dt;
        const double span = (sizeA - 1) * dt;
        // Float t: a window is L to within a few 1e-7 of the largest |t|.
        const double minimum = farLength * (1.0 + 1e-5) + 1e-6 * (1.0 + span + radius);
        const double blockLength =
            !paired && span > minimum && span - minimum < kTailSteps * dt ? span * (1.0 + 1e-6) : minimum;
        for (const float t : sampleT)
            sampleBlock.push_back(
                static_cast<int>(std::floor((static_cast<double>(t) - anchor) / blockLength)));
        const int base = sampleBlock[0];
        for (int& b : sampleBlock) b -= base;
        for (std::size_t s = 0; s < sampleBlock.size(); ++s)
            while (static_cast<int>(blockFirstSample.size()) <= sampleBlock[s])
                blockFirstSample.push_back(static_cast<int>(s));
        blockFirstSample.push_back(static_cast<int>(sampleBlock.size()));

        const auto dtf = static_cast<float>(dt);
        const auto radiusf = static_cast<float>(radius);
        const int count = static_cast<int>(sampleT.size());
        for (int side = 0; side < (paired ? 2 : 1); ++side) {
            Side& w = sides[side];
            int edge =
                0;  // side 0: the first sample with t >= tP - R; side 1: one past the last with t <= tP + R
            for (int k = 0; k < sizeA; ++k) {
                const float tP = static_cast<float>(k) * dtf;
                if (side == 0) {
                    while (sampleT[static_cast<std::size_t>(edge)] < tP - radiusf) ++edge;
                    w.first.push_back(edge);
                    w.last.push_back(columnSample[static_cast<std::size_t>(k - kNear - firstStep)]);
                } else {
                    while (edge < count && sampleT[static_cast<std::size_t>(edge)] <= tP + radiusf) ++edge;
                    w.first.push_back(columnSample[static_cast<std::size_t>(k + kNear - firstStep)]);
                    w.last.push_back(edge - 1);
                }
                const double u = side == 0 ? k - radius / dt : k + radius / dt;
                const double k1 = std::floor(u);
                const double b = minorAt(u);
                const double fb = std::floor(b);
                w.boundaryIndex0.push_back(relief.index(column(static_cast<int>(k1)), wrapB(fb)));
                w.boundaryIndex1.push_back(relief.index(column(static_cast<int>(k1) + 1), wrapB(fb)));
                w.boundaryFrac.push_back(static_cast<float>(b - fb));
                w.boundaryAlpha.push_back(static_cast<float>(u - k1));
            }
        }
    }
};

// Per-thread storage for one line group at a time; lane l of entry e at e kLanes + l.
struct GroupWork {
    std::vector<float> tan[2];  // the result per side: step k
    std::vector<float> z;       // the samples
    std::vector<float> prefix;  // (t, z) per slot [1, size]: a block's samples from its first
    std::vector<float> suffix;  // (t, z) per slot [1, size]: a block's samples from its last, backwards
};

// The near field of the group's texels at every step k into tan: tan h >= 0 over distances up to
// kNear steps (or R).
template <bool kAvx2>
[[gnu::always_inline]] inline void nearFieldOfGroup(const float* zmap, const DirectionPlan& plan,
                                                    const NearStencil& stencil, float* tan) {
    const float cMajor = stencil.coefMajor;
    const float cMinor = stencil.coefMinor;
    for (int k = 0; k < plan.sizeA; ++k) {
        const float* p = zmap + plan.texelIndex[static_cast<std::size_t>(k)];
        const Floats zP = load(p);
        Floats best =
            max(cMajor * (load(p + stencil.aheadOffset) - zP) + cMinor * (load(p + stencil.sideOffset) - zP),
                Floats{});
        for (const NearSegment& s : stencil.segments) {
            const float* c = p + s.offset;
            const Floats c00 = load(c);
            const Floats c10 = load(c + stencil.majorOffset);
            const Floats c01 = load(c + 1);
            const Floats c11 = load(c + stencil.majorOffset + 1);
            const Floats du = c10 - c00;
            const Floats dv = c01 - c00;
            const Floats e = c00 - c10 - c01 + c11;
            const Floats z1 = c00 + du * s.alpha1 + dv * s.beta1 + e * s.alpha1 * s.beta1;
            best = max(best, (z1 - zP) * s.invT1);
            if (s.t0 <= 0.0f) continue;  // the segment from P itself: only its end (the start is the slope)
            // Inside the cell the relief along the line is z(t) = qa + qb t + qc t^2 with
            // qc = e dA dB / (t1 - t0)^2; its elevation (z - zP) / t peaks where qc t^2 = qa - zP, when
            // that t lies inside the segment and the arc is concave: raiseByArcInterior's formula
            // (horizon_line.h), branch-free across the lanes.
            const float t0 = s.t0;
            const float t1 = s.t1;
            const float invLength = s.invLength;
            const Floats z0 = c00 + du * s.alpha0 + dv * s.beta0 + e * s.alpha0 * s.beta0;
            const Floats qc = e * s.twist;
            const Floats qb = (z1 - z0) * invLength - qc * (t0 + t1);
            const Floats qa = z0 - qb * t0 - qc * (t0 * t0);
            // t0^2 < (qa - zP) / qc < t1^2 with qc < 0, multiplied out: no division in the usual case, where
            // no lane's peak is inside. The divisor and the root are kept finite where it is not used.
            const Floats rise = qa - zP;
            const Ints inside = (qc < 0.0f) & (rise < qc * (t0 * t0)) & (rise > qc * (t1 * t1));
            if (!any<kAvx2>(inside)) continue;
            const Floats ratio = rise / min(qc, splat(-1e-30f));
            Floats tm = min(max(ratio, splat(t0 * t0)), splat(t1 * t1));
            for (int l = 0; l < kLanes; ++l) tm[l] = std::sqrt(tm[l]);
            const Floats peak = (qa + qb * tm + qc * tm * tm - zP) / tm;
            best = inside ? max(best, peak) : best;
        }
        store(tan + static_cast<std::ptrdiff_t>(k) * kLanes, best);
    }
}

// Whether b lies higher than a as seen from q: above the line from a to q when q lies after both in
// t (side 0), or before both (side 1).
template <int kSide>
[[gnu::always_inline]] inline Ints seesHigher(const Points& q, const Points& a, const Points& b) {
    return (kSide == 0 ? orient(a, q, b) : orient(b, q, a)) > 0.0f;
}

// The vertex of each lane's upper hull (slots [1, size], in order along the hull, all on one side of
// q in t) that q sees highest, i.e. the tangent from q; guess is the previous answer. The elevation is
// unimodal along the hull, so a local search from there finds it. Both neighbours of the guess are
// read at once: most searches end there.
template <bool kAvx2, int kSide>
[[gnu::always_inline]] inline Points tangent(const float* hull, Ints size, Ints& guess, const Points& q) {
    Ints c = min(max(guess, Ints{} + 1), size);
    const Ints s = slot(c);
    Points at = gather(hull, s);
    const Points next = gather(hull, s + kLanes);
    const Points previous = gather(hull, s - kLanes);
    const Ints up = (c < size) & seesHigher<kSide>(q, at, next);
    const Ints down = (c > 1) & seesHigher<kSide>(q, at, previous);
    if (any<kAvx2>(up | down)) {
        c += down - up;
        at = select(up, next, select(down, previous, at));
        for (Ints moving = up; any<kAvx2>(moving);) {
            const Points candidate = gather(hull, slot(c + 1));
            moving &= (c < size) & seesHigher<kSide>(q, at, candidate);
            c -= moving;
            at = select(moving, candidate, at);
        }
        for (Ints moving = down; any<kAvx2>(moving);) {
            const Points candidate = gather(hull, slot(c - 1));
            moving &= (c > 1) & seesHigher<kSide>(q, at, candidate);
            c += moving;
            at = select(moving, candidate, at);
        }
    }
    guess = c;
    return at;
}

// Each lane's upper hull on a stack, slot d at d kLanes + lane, with its top three slots also in
// registers: the slot under them is read one pop ahead, so that the read is not on the path that
// decides whether to pop again.
struct HullStack {
    float* points;
    Ints size{};
    Points top{};  // slots size, size - 1, size - 2
    Points below{};
    Points under{};
};

// Pushes p (after every point of the stack in t when forward, before when not), popping what it hides.
template <bool kAvx2, bool kForward>
[[gnu::always_inline]] inline void push(HullStack& h, const Points& p) {
    for (;;) {
        const Floats o = kForward ? orient(h.below, h.top, p) : orient(p, h.top, h.below);
        const Ints pop = (h.size >= 2) & (o >= 0.0f);
        if (!any<kAvx2>(pop)) break;
        h.size += pop;
        h.top = select(pop, h.below, h.top);
        h.below = select(pop, h.under, h.below);
        const Ints s = slot(max(h.size - 2, Ints{}));
        h.under = select(pop, gather(h.points, s), h.under);
    }
    h.size += 1;
    const Ints at = slot(h.size);
    scatter(h.points, at, p);
    h.under = h.below;
    h.below = h.top;
    h.top = p;
}

// The texels of one side that query one hull: k, then on to end (forwards: k < end; backwards: k >= end).
struct QueryRange {
    int k = 0;
    int end = 0;
};

// Raises each lane's tan (per side and step k: near field and the point at R) to its far field: the
// samples of its window, between kNear steps and R away.
template <bool kAvx2>
[[gnu::always_inline]] inline void farFieldOfGroup(const float* zmap, const DirectionPlan& plan,
                                                   GroupWork& work) {
    const std::size_t count = plan.sampleT.size();
    const std::size_t entries = (count + 2) * kLanes;
    work.z.resize(count * kLanes);
    work.prefix.resize(2 * entries);
    work.suffix.resize(2 * entries);
    float* z = work.z.data();
    for (std::size_t s = 0; s < count; ++s) {
        const float w = plan.sampleW[s];
        store(z + s * kLanes,
              (1.0f - w) * load(zmap + plan.sampleIndex0[s]) + w * load(zmap + plan.sampleIndex1[s]));
    }
    const auto zAt = [&](int s) { return load(z + static_cast<std::ptrdiff_t>(s) * kLanes); };
    const auto sample = [&](int s) -> Points {
        return {splat(plan.sampleT[static_cast<std::size_t>(s)]), zAt(s)};
    };
    const float* t = plan.sampleT.data();
    const int* block = plan.sampleBlock.data();
    const auto dt = static_cast<float>(plan.dir.dt);
    const int sides = plan.paired ? 2 : 1;

    // Every query's window ends in the block where it starts or the next. Block by block: forwards, the
    // queries ending in it (its samples from its first up to their end, a prefix hull), then backwards
    // those starting in it and ending in the next (its samples down to their start, a suffix hull).
    // Each hull is only needed where some lane's bound (the part's highest sample at its nearest
    // distance) beats what that lane has, so samples are pushed only when such a query comes.
    QueryRange forward[2];
    QueryRange backward[2];
    int backwardStart[2] = {0, 0};  // per side, the first texel whose window starts in this block or later
    const int blocks = static_cast<int>(plan.blockFirstSample.size()) - 1;
    for (int b = 0; b < blocks; ++b) {
        const int f0 = plan.blockFirstSample[static_cast<std::size_t>(b)];
        const int f1 = plan.blockFirstSample[static_cast<std::size_t>(b + 1)];
        {
            HullStack prefix{work.prefix.data()};
            Ints guess[2] = {Ints{} + 1, Ints{} + 1};
            Floats highest = splat(-std::numeric_limits<float>::infinity());
            int next = f0;  // the next sample to push
            int scanned = f0;
            for (int side = 0; side < sides; ++side) {
                QueryRange& r = forward[side];
                r.end = r.k;
                while (r.end < plan.sizeA &&
                       block[plan.sides[side].last[static_cast<std::size_t>(r.end)]] == b)
                    ++r.end;
            }
            for (;;) {
                // The side whose next window ends first.
                int side = -1;
                for (int s = 0; s < sides; ++s)
                    if (forward[s].k < forward[s].end &&
                        (side < 0 || plan.sides[s].last[static_cast<std::size_t>(forward[s].k)] <
                                         plan.sides[side].last[static_cast<std::size_t>(forward[side].k)]))
                        side = s;
                if (side < 0) break;
                const int k = forward[side].k++;
                const auto kk = static_cast<std::size_t>(k);
                const int first = plan.sides[side].first[kk];
                const int last = plan.sides[side].last[kk];
                for (; scanned <= last; ++scanned) highest = max(highest, zAt(scanned));
                const float tP = static_cast<float>(k) * dt;
                const Floats zP = load(zmap + plan.texelIndex[kk]);
                float* out = work.tan[side].data() + static_cast<std::ptrdiff_t>(k) * kLanes;
                Floats best = load(out);
                if (block[first] == b) {
                    // The whole window lies in this block: its samples one by one.
                    for (int s = first; s <= last; ++s)
                        best = max(best, (zAt(s) - zP) / (side == 0 ? tP - t[s] : t[s] - tP));
                } else if (any<kAvx2>((highest - zP) > best * (side == 0 ? tP - t[last] : t[f0] - tP))) {
                    for (; next <= last; ++next) push<kAvx2, true>(prefix, sample(next));
                    const Points q{splat(tP), zP};
                    const Points h = side == 0 ? tangent<kAvx2, 0>(prefix.points, prefix.size, guess[0], q)
                                               : tangent<kAvx2, 1>(prefix.points, prefix.size, guess[1], q);
                    best = max(best, (h.z - zP) / (side == 0 ? tP - h.t : h.t - tP));
                }
                store(out, best);
            }
        }
        {
            HullStack suffix{work.suffix.data()};
            Ints guess[2] = {Ints{} + 1, Ints{} + 1};
            Floats highest = splat(-std::numeric_limits<float>::infinity());
            int pushed = f1;  // the hull holds [pushed, f1)
            int scanned = f1;
            for (int side = 0; side < sides; ++side) {
                // Windows starting in this block and ending in the next, last first.
                const DirectionPlan::Side& w = plan.sides[side];
                const auto blockOf = [&](const std::vector<int>& samples, int k) {
                    return block[samples[static_cast<std::size_t>(k)]];
                };
                int& k = backwardStart[side];
                while (k < plan.sizeA && blockOf(w.first, k) < b) ++k;
                int lowest = k;
                while (lowest < plan.sizeA && blockOf(w.first, lowest) == b && blockOf(w.last, lowest) == b)
                    ++lowest;
                int beyond = lowest;
                while (beyond < plan.sizeA && blockOf(w.first, beyond) == b) ++beyond;
                backward[side] = {beyond - 1, lowest};
            }
            for (;;) {
                // The side whose next window starts last.
                int side = -1;
                for (int s = 0; s < sides; ++s)
                    if (backward[s].k >= backward[s].end &&
                        (side < 0 || plan.sides[s].first[static_cast<std::size_t>(backward[s].k)] >
                                         plan.sides[side].first[static_cast<std::size_t>(backward[side].k)]))
                        side = s;
                if (side < 0) break;
                const int k = backward[side].k--;
                const auto kk = static_cast<std::size_t>(k);
                const int first = plan.sides[side].first[kk];
                for (; scanned > first; --scanned) highest = max(highest, zAt(scanned - 1));
                const float tP = static_cast<float>(k) * dt;
                const Floats zP = load(zmap + plan.texelIndex[kk]);
                float* out = work.tan[side].data() + static_cast<std::ptrdiff_t>(k) * kLanes;
                const Floats best = load(out);
                if (!any<kAvx2>((highest - zP) > best * (side == 0 ? tP - t[f1 - 1] : t[first] - tP)))
                    continue;
                for (; pushed > first; --pushed) push<kAvx2, false>(suffix, sample(pushed - 1));
                const Points q{splat(tP), zP};
                const Points h = side == 0 ? tangent<kAvx2, 0>(suffix.points, suffix.size, guess[0], q)
                                           : tangent<kAvx2, 1>(suffix.points, suffix.size, guess[1], q);
                store(out, max(best, (h.z - zP) / (side == 0 ? tP - h.t : h.t - tP)));
            }
        }
    }
}

// tan h of the texels of lines [j, j + kLanes) at every step k into work.tan[side] (lane l is line
// j + l; lines past sizeB repeat the first ones and are computed, not used). With cosineWeights, each
// result becomes the direction's term of the cosine-weighted AO instead, cos^2 h = 1 / (1 + tan^2 h),
// computed here with the kernel's vector width.
template <bool kAvx2>
[[gnu::always_inline]] inline void horizonsOfGroup(const PaddedRelief& relief, const DirectionPlan& plan,
                                                   int j, GroupWork& work, bool cosineWeights) {
    const float* zmap = relief.data() + j;
    const std::ptrdiff_t entries = static_cast<std::ptrdiff_t>(plan.sizeA) * kLanes;
    for (int side = 0; side < (plan.paired ? 2 : 1); ++side) {
        work.tan[side].resize(static_cast<std::size_t>(entries));
        float* tan = work.tan[side].data();
        nearFieldOfGroup<kAvx2>(zmap, plan, plan.near[static_cast<std::size_t>(side)], tan);
        if (!plan.hasFar) continue;
        // The point at exactly R.
        const DirectionPlan::Side& w = plan.sides[side];
        const auto radius = static_cast<float>(plan.radius);
        for (int k = 0; k < plan.sizeA; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const float fr = w.boundaryFrac[kk];
            const float alpha = w.boundaryAlpha[kk];
            const float* c0 = zmap + w.boundaryIndex0[kk];
            const float* c1 = zmap + w.boundaryIndex1[kk];
            const Floats zR = (1.0f - alpha) * ((1.0f - fr) * load(c0) + fr * load(c0 + 1)) +
                              alpha * ((1.0f - fr) * load(c1) + fr * load(c1 + 1));
            float* out = tan + static_cast<std::ptrdiff_t>(k) * kLanes;
            store(out, max(load(out), (zR - load(zmap + plan.texelIndex[kk])) / radius));
        }
    }
    if (plan.hasFar) farFieldOfGroup<kAvx2>(zmap, plan, work);
    if (cosineWeights)
        for (int side = 0; side < (plan.paired ? 2 : 1); ++side)
            for (std::ptrdiff_t e = 0; e < entries; e += kLanes) {
                const Floats h = load(work.tan[side].data() + e);
                store(work.tan[side].data() + e, 1.0f / (1.0f + h * h));
            }
}

using GroupHorizons = void (*)(const PaddedRelief&, const DirectionPlan&, int, GroupWork&, bool);

void groupHorizonsPortable(const PaddedRelief& relief, const DirectionPlan& plan, int j, GroupWork& work,
                           bool cosineWeights) {
    horizonsOfGroup<false>(relief, plan, j, work, cosineWeights);
}

#ifdef STRATA_SWEEP_X86
__attribute__((target("avx2"))) void groupHorizonsAvx2(const PaddedRelief& relief, const DirectionPlan& plan,
                                                       int j, GroupWork& work, bool cosineWeights) {
    horizonsOfGroup<true>(relief, plan, j, work, cosineWeights);
}
#endif

// AVX2 where the CPU has it, chosen at run time (the build targets the baseline ISA).
GroupHorizons groupHorizons() {
#ifdef STRATA_SWEEP_X86
    if (__builtin_cpu_supports("avx2")) return groupHorizonsAvx2;
#endif
    return groupHorizonsPortable;
}

// Runs the sweep for every direction and hands each line group's horizons to
// sink(i, plan, j, lanes, tan): tan[k kLanes + l] is the horizon of line j + l (l < lanes) at step k in
// direction i (or with cosineWeights its cos^2 h), texel (plan.texelColumn[k], j + l + plan.texelRow[k],
// minor wrapped) in (major, minor) coordinates. Every texel lies on exactly one line per direction, so
// sinks of one direction never share a texel. With M even, directions i and i + M/2 are opposite:
// the same lines, samples and hulls serve both.
template <typename Sink>
void sweep(const Image& depth, const AoParams& params, bool cosineWeights, const Sink& sink) {
    const auto scale = static_cast<float>(params.depthScale);
    const PaddedRelief byColumns(depth, true, scale);
    const PaddedRelief byRows(depth, false, scale);
    tbb::enumerable_thread_specific<GroupWork> works;
    const GroupHorizons horizonsOfGroup = groupHorizons();
    const int m = params.directions;
    const bool paired = m % 2 == 0;
    for (int i = 0; i < (paired ? m / 2 : m); ++i) {
        const LineDirection dir(2.0 * std::numbers::pi * i / m, depth.width(), depth.height());
        const PaddedRelief& relief = dir.xMajor ? byColumns : byRows;
        const DirectionPlan plan(dir, paired, relief, params.radius);
        const int sizeB = relief.sizeB();
        const int groups = (sizeB + kLanes - 1) / kLanes;
        tbb::parallel_for(tbb::blocked_range<int>(0, groups), [&](const tbb::blocked_range<int>& range) {
            GroupWork& work = works.local();
            for (int g = range.begin(); g != range.end(); ++g) {
                const int j = g * kLanes;
                const int lanes = std::min(kLanes, sizeB - j);
                horizonsOfGroup(relief, plan, j, work, cosineWeights);
                sink(i, plan, j, lanes, work.tan[0].data());
                if (paired) sink(i + m / 2, plan, j, lanes, work.tan[1].data());
            }
        });
    }
}

// Calls store(texel index in the sizeA x sizeB (major, minor) map, lane) for each texel of a line group
// at step k.
template <typename Store>
inline void forEachTexel(const DirectionPlan& plan, int j, int lanes, int k, const Store& store) {
    const auto kk = static_cast<std::size_t>(k);
    const std::size_t column =
        static_cast<std::size_t>(plan.texelColumn[kk]) * static_cast<std::size_t>(plan.sizeB);
    int row = (j + plan.texelRow[kk]) % plan.sizeB;
    for (int l = 0; l < lanes; ++l) {
        store(column + static_cast<std::size_t>(row), l);
        if (++row == plan.sizeB) row = 0;
    }
}

}  // namespace

HorizonMap sweepHorizons(const Image& depth, const AoParams& params) {
    const int w = depth.width();
    const int m = params.directions;
    HorizonMap result;
    result.width = w;
    result.height = depth.height();
    result.directions = m;
    result.depthScale = params.depthScale;
    result.radius = params.radius;
    result.tanHorizon.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(depth.height()) *
                             static_cast<std::size_t>(m));
    const auto dirs = static_cast<std::size_t>(m);
    sweep(depth, params, false, [&](int i, const DirectionPlan& plan, int j, int lanes, const float* tan) {
        for (int k = 0; k < plan.sizeA; ++k) {
            const float* tk = tan + static_cast<std::ptrdiff_t>(k) * kLanes;
            forEachTexel(plan, j, lanes, k, [&](std::size_t index, int l) {
                // index = a sizeB + b; the map is row-major in (x, y).
                const std::size_t a = index / static_cast<std::size_t>(plan.sizeB);
                const std::size_t b = index % static_cast<std::size_t>(plan.sizeB);
                const std::size_t x = plan.dir.xMajor ? a : b;
                const std::size_t y = plan.dir.xMajor ? b : a;
                result
                    .tanHorizon[(y * static_cast<std::size_t>(w) + x) * dirs + static_cast<std::size_t>(i)] =
                    tk[l];
            });
        }
    });
    return result;
}

Image sweepAo(const Image& depth, const AoParams& params) {
    const int w = depth.width();
    const int h = depth.height();
    // Directions with x major add into byColumns (column x, along y); the others into byRows (row y,
    // along x): the (major, minor) layout of each.
    std::vector<float> byColumns(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0f);
    std::vector<float> byRows(byColumns.size(), 0.0f);
    sweep(depth, params, true, [&](int, const DirectionPlan& plan, int j, int lanes, const float* weight) {
        float* sum = plan.dir.xMajor ? byColumns.data() : byRows.data();
        for (int k = 0; k < plan.sizeA; ++k) {
            const float* wk = weight + static_cast<std::ptrdiff_t>(k) * kLanes;
            const auto kk = static_cast<std::size_t>(k);
            int row = j + plan.texelRow[kk];
            if (row >= plan.sizeB) row -= plan.sizeB;
            if (lanes == kLanes && row + kLanes <= plan.sizeB) {
                float* out =
                    sum +
                    static_cast<std::size_t>(plan.texelColumn[kk]) * static_cast<std::size_t>(plan.sizeB) +
                    static_cast<std::size_t>(row);
                for (int l = 0; l < kLanes; ++l) out[l] += wk[l];
            } else {
                forEachTexel(plan, j, lanes, k, [&](std::size_t index, int l) { sum[index] += wk[l]; });
            }
        }
    });
    // The mean, divided once at the end: a fully open texel sums to exactly M and gives exactly 1.
    Image ao(w, h, 1, 0.0f);
    const auto directions = static_cast<float>(params.directions);
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& ys) {
        for (int y = ys.begin(); y != ys.end(); ++y)
            for (int x = 0; x < w; ++x)
                ao.at(x, y) = (byRows[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                      static_cast<std::size_t>(x)] +
                               byColumns[static_cast<std::size_t>(x) * static_cast<std::size_t>(h) +
                                         static_cast<std::size_t>(y)]) /
                              directions;
    });
    return ao;
}

}  // namespace strata::detail
