// The sweep horizon search (AoMethod::Sweep); see the comment on AoMethod::Sweep in
// strata/occlusion/ambient_occlusion.h for what it computes and how exact it is.
//
// Per direction, parallel lines one texel apart sweep the map. Every line has the same sample times
// and interpolation weights, only its heights differ, so neighbouring lines run in lockstep, one per
// SIMD lane (4 with the baseline ISA, 8 with AVX2, 16 with AVX-512): the control flow that depends on
// t alone (which texel asks when, which samples it sees) is shared, and the hull loops that depend on
// the heights run until every lane is done, with masks. Opposite directions (i and i + M/2, M even) use the
// same lines, texels and samples, looking the other way along them, so they share the samples. Per line
// group, the near field, the point at R, then the far field raise each texel's tan h; then the sink
// reads them. The kernel is in sweep_kernel.h, included once per lane width below.
//
// The near field (up to kNear columns), walked exactly on each texel's own line: every crossing and the
// quadratic arc inside each cell, plus the t -> 0+ slope. Every texel's own line has the same offsets
// to the grid, so this is one stencil with constant weights; the relief is stored with the minor axis
// contiguous, so the group's texels at one column are contiguous and the stencil is plain vector loads.
//
// The far field (distances kNear columns .. R). A line's profile is sampled at every major texel centre
// and every minor grid crossing (the bilinear relief is linear along both), and texel P, the texel
// nearest to the line at a column, asks for the largest elevation (z - zP) / |tP - t| over the samples
// with |tP - t| in [kNear dt, R] on its side (its window), plus the point at exactly R. Per side, one
// upper convex hull on a stack (Timonen & Westerholm 2010: pushing a point pops the ones it hides)
// takes the line's samples in order, up to the window's near end, and the texel's tangent to it (a
// walk down from the hull's top) is the highest sample over its window and everything beyond.
// That is the window's answer unless the tangent lies beyond R and would raise tan h; only then does
// the lane read its window itself (farFieldOfSide). Each sample is pushed once per side and popped at
// most once; each texel makes one tangent query per side. A lane's stack is its own (slot d of lane l
// at d kLanes + l; reads are gathers), but every lane pushes the same samples at the same time. Where
// every window of a direction is short (kShortWindow), each texel reads its window instead.
//
// The line is at most half a texel beside P, and that offset only matters beyond kNear columns, where
// it changes the elevation by at most (offset x slope across) / distance.
#include "horizon_line.h"
#include "horizon_search.h"
#include "strata/core/error.h"

#include "strata/core/parallel.h"
#if defined(__x86_64__) || defined(__i386__)
#define STRATA_SWEEP_X86
#include <immintrin.h>  // the AVX2 and AVX-512 builtins and intrinsics
#endif
#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace strata::detail {
namespace {

// Columns walked exactly on each texel's own line before the far field takes over. 4 keeps the far
// field's lateral error below 0.003 AO RMSE against the exact walk on every built-in pattern
// (docs/occlusion.md); 2 doubles it, 8 doubles the near field's work for a further halving.
constexpr int kNear = 4;
constexpr int kPad = kNear + 2;
// The widest line group (AVX-512): the relief is padded for its last lane.
constexpr int kMaxLanes = 16;
// A lane that reads its window itself skips runs of this many samples at a time.
constexpr int kRun = 16;
// A direction whose windows all have at most this many samples reads them sample by sample instead of
// through hulls: up to this length, 16 lanes reading their windows cost no more than a hull's pushes and
// tangent per step, and shorter windows less (docs/dev/occlusion-notes.md has the measurements).
constexpr int kShortWindow = 192;

// GCC vector extensions, each lane width in a namespace of its own below. Every function that takes or
// returns them is always inlined into a kernel compiled for the ISA that holds them (also at -O0, where
// a call between code built for different ISAs would not agree on where a wide vector goes), so the ABI
// of wide vectors without that ISA, which GCC warns about, never applies.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

// std::bit_cast, always inlined (at -O0 std::bit_cast is a call).
template <typename To, typename From>
[[gnu::always_inline]] inline To bitCast(const From& from) {
    static_assert(sizeof(To) == sizeof(From));
    To to;
    std::memcpy(&to, &from, sizeof to);
    return to;
}

// z = -S d in (major a, minor b) order, the minor axis contiguous: column a holds every minor index b.
// The minor axis is stored twice over (b in [0, 2 sizeB)) so that line j's row j + b never wraps, and
// wrapped texels pad every side for the near field, plus kMaxLanes more at the end for the last lane of the
// widest group.
class PaddedRelief {
public:
    PaddedRelief(const Image& depth, bool xMajor, float scale)
        : mSizeA(xMajor ? depth.width() : depth.height()),
          mSizeB(xMajor ? depth.height() : depth.width()),
          mStride(2 * mSizeB + 2 * kPad + kMaxLanes),
          // Every entry is written below: no zero fill (the map is twice the depth map's size).
          mZ(std::make_unique_for_overwrite<float[]>(static_cast<std::size_t>(mStride) *
                                                     static_cast<std::size_t>(mSizeA + 2 * kPad))) {
        parallelForChunks(-kPad, mSizeA + kPad, [&](int first, int last) {
            for (int a = first; a != last; ++a) {
                const int aw = MajorMinorDepth::wrap(a, mSizeA);
                float* column = mZ.get() + index(a, -kPad);
                int bw = MajorMinorDepth::wrap(-kPad, mSizeB);
                for (int b = -kPad; b < 2 * mSizeB + kPad + kMaxLanes; ++b) {
                    *column++ = -scale * (xMajor ? depth.at(aw, bw) : depth.at(bw, aw));
                    if (++bw == mSizeB) bw = 0;
                }
            }
        });
    }
    // a in [-kPad, sizeA + kPad), b in [-kPad, 2 sizeB + kPad + kMaxLanes).
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
    int longestWindow = 1;     // the most samples in one texel's window
    bool readWindows = false;  // read each window sample by sample instead of through hulls
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
                longestWindow = std::max(longestWindow, w.last.back() - w.first.back() + 1);
            }
        }
    }
};

// Per-thread storage for one line group at a time; lane l of entry e at e width + l, width the
// kernel's group width.
struct GroupWork {
    std::vector<float> tan[2];      // the result per side: step k
    std::vector<float> z;           // the samples
    std::vector<float> hull;        // (t, z) per slot [1, size]
    std::vector<float> runHighest;  // per run of kRun samples, its highest
};

namespace lanes8 {
// SSE2 (the baseline ISA) or AVX2: one AVX2 register of floats.
constexpr int kLanes = 8;
using Floats = float __attribute__((vector_size(kLanes * sizeof(float))));
using Ints = std::int32_t __attribute__((vector_size(kLanes * sizeof(std::int32_t))));
using Words = long long __attribute__((vector_size(kLanes * sizeof(std::int32_t))));
constexpr Ints kLaneIndex = {0, 1, 2, 3, 4, 5, 6, 7};
constexpr int kHeld = 4;  // hull slots in registers (sweep_kernel.h): 7 spill with 16 registers

// Whether any lane is set. kNative: one VPTEST, in code that only runs inside a function compiled for
// AVX2 (the builtin, unlike its intrinsic, may sit in a function inlined into one).
template <bool kNative>
[[gnu::always_inline]] inline bool any(Ints mask) {
    const auto w = bitCast<Words>(mask);
#ifdef STRATA_SWEEP_X86
    if constexpr (kNative) return !__builtin_ia32_ptestz256(w, w);
#endif
    return ((w[0] | w[1]) | (w[2] | w[3])) != 0;
}

// A point of each lane's profile.
struct Points {
    Floats t;
    Floats z;
};
// Stacks hold (t, z) pairs, so that reading a lane's point is one 8-byte load: entry e of lane l at
// 2 (e kLanes + l). Lanes 0, 1, 4, 5 are read into one register and 2, 3, 6, 7 into another, so that
// one shuffle within 128-bit halves (SHUFPS) splits them into t and z in lane order. (Hardware gathers
// were no faster: docs/dev/occlusion-notes.md.)
using Pairs = double __attribute__((vector_size(kLanes * sizeof(float))));
constexpr int kPairLane[2][kLanes / 2] = {{0, 1, 4, 5}, {2, 3, 6, 7}};
constexpr Ints kFirstOfPair = {0, 2, 8, 10, 4, 6, 12, 14};
constexpr Ints kPairOfLow = {0, 8, 1, 9, 4, 12, 5, 13};  // (t, z) of lanes 0, 1, 4, 5
constexpr Ints kPairOfHigh = {2, 10, 3, 11, 6, 14, 7, 15};
#include "sweep_pairs.h"

#include "sweep_kernel.h"
}  // namespace lanes8

namespace lanes4 {
// The baseline ISA (SSE2 on x86-64, NEON on AArch64): one 128-bit register of floats. Wider generic
// vectors would be split into pairs of registers by GCC, and their masks and selects into scalar code.
constexpr int kLanes = 4;
using Floats = float __attribute__((vector_size(kLanes * sizeof(float))));
using Ints = std::int32_t __attribute__((vector_size(kLanes * sizeof(std::int32_t))));
using Words = long long __attribute__((vector_size(kLanes * sizeof(std::int32_t))));
constexpr Ints kLaneIndex = {0, 1, 2, 3};
constexpr int kHeld = 4;  // hull slots in registers (sweep_kernel.h): 7 spill with 16 registers

template <bool>
[[gnu::always_inline]] inline bool any(Ints mask) {
    const auto w = bitCast<Words>(mask);
    return (w[0] | w[1]) != 0;
}

struct Points {
    Floats t;
    Floats z;
};
// (t, z) pairs as in lanes8: lanes 0 and 1 in one register, 2 and 3 in another.
using Pairs = double __attribute__((vector_size(kLanes * sizeof(float))));
constexpr int kPairLane[2][kLanes / 2] = {{0, 1}, {2, 3}};
constexpr Ints kFirstOfPair = {0, 2, 4, 6};
constexpr Ints kPairOfLow = {0, 4, 1, 5};
constexpr Ints kPairOfHigh = {2, 6, 3, 7};
#include "sweep_pairs.h"

#include "sweep_kernel.h"
}  // namespace lanes4

void groupHorizonsPortable(const PaddedRelief& relief, const DirectionPlan& plan, int j, GroupWork& work,
                           bool cosineWeights) {
    lanes4::horizonsOfGroup<false>(relief, plan, j, work, cosineWeights);
}

#ifdef STRATA_SWEEP_X86
__attribute__((target("avx2"))) void groupHorizonsAvx2(const PaddedRelief& relief, const DirectionPlan& plan,
                                                       int j, GroupWork& work, bool cosineWeights) {
    lanes8::horizonsOfGroup<true>(relief, plan, j, work, cosineWeights);
}

// AVX-512: 16 lanes in one register, hardware gathers and scatters. Everything defined in this region
// is compiled for AVX-512, so that GCC keeps the 16-lane comparisons in mask registers (helpers compiled
// for the baseline and inlined later would be split into scalar code); the standard library, defined
// above it, is not, so no function that other code may share is built for AVX-512.
#pragma GCC push_options
#pragma GCC target("avx2,avx512f,avx512vl,avx512bw,avx512dq")
namespace lanes16 {
constexpr int kLanes = 16;
using Floats = float __attribute__((vector_size(kLanes * sizeof(float))));
using Ints = std::int32_t __attribute__((vector_size(kLanes * sizeof(std::int32_t))));
constexpr Ints kLaneIndex = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
constexpr int kHeld = 7;  // hull slots in registers (sweep_kernel.h)

template <bool>
[[gnu::always_inline]] inline bool any(Ints mask) {
    const auto m = bitCast<__m512i>(mask);
    return _mm512_test_epi32_mask(m, m) != 0;
}

struct Points {
    Floats t;
    Floats z;
};
// (t, z) pairs as in lanes8; lanes 0-7 are gathered as eight doubles, 8-15 as eight more, and one
// two-source permute per component puts t and z in lane order.
constexpr Ints kEven = {0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30};
constexpr Ints kPairOfLow = {0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23};
constexpr Ints kPairOfHigh = kPairOfLow + 8;
using Indices = std::int32_t __attribute__((vector_size(8 * sizeof(std::int32_t))));
using Doubles = double __attribute__((vector_size(8 * sizeof(double))));
constexpr auto kAllEight = static_cast<__mmask8>(0xff);  // every one of eight elements
// The builtins rather than _mm512_i32gather_pd, whose undefined source register GCC 12 reports as
// maybe uninitialised.
[[gnu::always_inline]] inline Doubles gather8(const float* pairs, Indices index) {
    return __builtin_ia32_gathersiv8df(Doubles{}, pairs, index, kAllEight, 8);
}
[[gnu::always_inline]] inline Points gather(const float* pairs, Ints index) {
    const auto a =
        bitCast<Floats>(gather8(pairs, __builtin_shufflevector(index, index, 0, 1, 2, 3, 4, 5, 6, 7)));
    const auto b =
        bitCast<Floats>(gather8(pairs, __builtin_shufflevector(index, index, 8, 9, 10, 11, 12, 13, 14, 15)));
    return {__builtin_shuffle(a, b, kEven), __builtin_shuffle(a, b, kEven + 1)};
}
[[gnu::always_inline]] inline void scatter(float* pairs, Ints index, const Points& p) {
    __builtin_ia32_scattersiv8df(pairs, kAllEight,
                                 __builtin_shufflevector(index, index, 0, 1, 2, 3, 4, 5, 6, 7),
                                 bitCast<Doubles>(__builtin_shuffle(p.t, p.z, kPairOfLow)), 8);
    __builtin_ia32_scattersiv8df(pairs, kAllEight,
                                 __builtin_shufflevector(index, index, 8, 9, 10, 11, 12, 13, 14, 15),
                                 bitCast<Doubles>(__builtin_shuffle(p.t, p.z, kPairOfHigh)), 8);
}

#include "sweep_kernel.h"
}  // namespace lanes16

void groupHorizonsAvx512(const PaddedRelief& relief, const DirectionPlan& plan, int j, GroupWork& work,
                         bool cosineWeights) {
    lanes16::horizonsOfGroup<true>(relief, plan, j, work, cosineWeights);
}
#pragma GCC pop_options
#endif

// A kernel and its group width.
struct GroupKernel {
    void (*horizons)(const PaddedRelief&, const DirectionPlan&, int, GroupWork&, bool);
    int lanes;
};
GroupKernel groupKernel(SweepKernel kernel) {
    if (kernel == SweepKernel::Auto)
        kernel = sweepKernelRuns(SweepKernel::Avx512) ? SweepKernel::Avx512
                 : sweepKernelRuns(SweepKernel::Avx2) ? SweepKernel::Avx2
                                                      : SweepKernel::Portable;
    if (!sweepKernelRuns(kernel))
        throw Error(ErrorKind::InvalidInput,
                    std::string("the sweep's ") + toString(kernel) + " kernel does not run on this CPU");
    switch (kernel) {
#ifdef STRATA_SWEEP_X86
        case SweepKernel::Avx512:
            return {groupHorizonsAvx512, lanes16::kLanes};
        case SweepKernel::Avx2:
            return {groupHorizonsAvx2, lanes8::kLanes};
#endif
        default:
            return {groupHorizonsPortable, lanes4::kLanes};
    }
}

// Runs the sweep for every direction and hands each line group's horizons to
// sink(i, plan, j, lanes, width, tan, opposite): tan[k width + l] is the horizon of line j + l
// (l < lanes) at step k in direction i (or with cosineWeights its cos^2 h), texel (plan.texelColumn[k],
// j + l + plan.texelRow[k], minor wrapped) in (major, minor) coordinates. Every texel lies on exactly one
// line per direction, so sinks of one direction never share a texel. With M even, directions i and
// i + M/2 are opposite: the same lines, samples and texels serve both, and opposite holds direction
// i + M/2's results as tan holds i's (nullptr with M odd). width is the kernel's group width
// (lanes <= width).
template <typename Sink>
void sweep(const Image& depth, const AoParams& params, const SweepOptions& options, bool cosineWeights,
           const Sink& sink) {
    const auto scale = static_cast<float>(params.depthScale);
    const PaddedRelief byColumns(depth, true, scale);
    const PaddedRelief byRows(depth, false, scale);
    tbb::enumerable_thread_specific<GroupWork> works;
    const GroupKernel kernel = groupKernel(options.kernel);
    const int m = params.directions;
    const bool paired = m % 2 == 0;
    const int sweeps = paired ? m / 2 : m;
    const auto planOf = [&](int i) {
        const LineDirection dir(2.0 * std::numbers::pi * i / m, depth.width(), depth.height());
        DirectionPlan plan(dir, paired, dir.xMajor ? byColumns : byRows, params.radius);
        plan.readWindows = !options.hullsOnly && plan.longestWindow <= kShortWindow;
        return plan;
    };
    // Each direction's plan is made while the one before runs, so that planning is not a serial step.
    std::optional<DirectionPlan> next(planOf(0));
    for (int i = 0; i < sweeps; ++i) {
        const DirectionPlan plan = std::move(*next);
        tbb::task_group planning;
        if (i + 1 < sweeps) planning.run([&] { next.emplace(planOf(i + 1)); });
        const PaddedRelief& relief = plan.dir.xMajor ? byColumns : byRows;
        const int sizeB = relief.sizeB();
        const int groups = (sizeB + kernel.lanes - 1) / kernel.lanes;
        parallelForChunks(0, groups, [&](int first, int last) {
            GroupWork& work = works.local();
            for (int g = first; g != last; ++g) {
                const int j = g * kernel.lanes;
                const int lanes = std::min(kernel.lanes, sizeB - j);
                kernel.horizons(relief, plan, j, work, cosineWeights);
                sink(i, plan, j, lanes, kernel.lanes, work.tan[0].data(),
                     paired ? work.tan[1].data() : nullptr);
            }
        });
        planning.wait();
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

bool sweepKernelRuns(SweepKernel kernel) {
    switch (kernel) {
        case SweepKernel::Auto:
        case SweepKernel::Portable:
            return true;
#ifdef STRATA_SWEEP_X86
        case SweepKernel::Avx2:
            return __builtin_cpu_supports("avx2");
        case SweepKernel::Avx512:
            return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                   __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
#endif
        default:
            return false;
    }
}

const char* toString(SweepKernel kernel) {
    switch (kernel) {
        case SweepKernel::Auto:
            return "auto";
        case SweepKernel::Portable:
            return "portable";
        case SweepKernel::Avx2:
            return "avx2";
        case SweepKernel::Avx512:
            return "avx512";
    }
    return "unknown";
}

HorizonMap sweepHorizons(const Image& depth, const AoParams& params, const SweepOptions& options) {
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
    sweep(depth, params, options, false,
          [&](int i, const DirectionPlan& plan, int j, int lanes, int width, const float* tan,
              const float* opposite) {
              for (int k = 0; k < plan.sizeA; ++k) {
                  const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(k) * width;
                  forEachTexel(plan, j, lanes, k, [&](std::size_t index, int l) {
                      // index = a sizeB + b; the map is row-major in (x, y).
                      const std::size_t a = index / static_cast<std::size_t>(plan.sizeB);
                      const std::size_t b = index % static_cast<std::size_t>(plan.sizeB);
                      const std::size_t x = plan.dir.xMajor ? a : b;
                      const std::size_t y = plan.dir.xMajor ? b : a;
                      float* texel = result.tanHorizon.data() + (y * static_cast<std::size_t>(w) + x) * dirs;
                      texel[i] = tan[at + l];
                      if (opposite != nullptr) texel[i + m / 2] = opposite[at + l];
                  });
              }
          });
    return result;
}

Image sweepAo(const Image& depth, const AoParams& params, const SweepOptions& options) {
    const int w = depth.width();
    const int h = depth.height();
    // Directions with x major add into byColumns (column x, along y); the others into byRows (row y,
    // along x): the (major, minor) layout of each.
    std::vector<float> byColumns(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0f);
    std::vector<float> byRows(byColumns.size(), 0.0f);
    sweep(depth, params, options, true,
          [&](int, const DirectionPlan& plan, int j, int lanes, int width, const float* weight,
              const float* opposite) {
              float* sum = plan.dir.xMajor ? byColumns.data() : byRows.data();
              std::array<float, kMaxLanes> both{};
              for (int k = 0; k < plan.sizeA; ++k) {
                  const float* wk = weight + static_cast<std::ptrdiff_t>(k) * width;
                  if (opposite != nullptr) {
                      // The opposite direction's texels are the same: one pass over them adds both.
                      const float* ok = opposite + static_cast<std::ptrdiff_t>(k) * width;
                      for (int l = 0; l < width; ++l) both[static_cast<std::size_t>(l)] = wk[l] + ok[l];
                      wk = both.data();
                  }
                  const auto kk = static_cast<std::size_t>(k);
                  int row = j + plan.texelRow[kk];
                  if (row >= plan.sizeB) row -= plan.sizeB;
                  if (lanes == width && row + width <= plan.sizeB) {
                      float* out = sum +
                                   static_cast<std::size_t>(plan.texelColumn[kk]) *
                                       static_cast<std::size_t>(plan.sizeB) +
                                   static_cast<std::size_t>(row);
                      for (int l = 0; l < width; ++l) out[l] += wk[l];
                  } else {
                      forEachTexel(plan, j, lanes, k, [&](std::size_t index, int l) { sum[index] += wk[l]; });
                  }
              }
          });
    // The mean, divided once at the end: a fully open texel sums to exactly M and gives exactly 1.
    Image ao(w, h, 1, 0.0f);
    const auto directions = static_cast<float>(params.directions);
    parallelForChunks(0, h, [&](int rowBegin, int rowEnd) {
        for (int y = rowBegin; y != rowEnd; ++y)
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
