// The sweep horizon search (AoMethod::Sweep); see the comment on AoMethod::Sweep in
// strata/occlusion/ambient_occlusion.h for what it computes and how exact it is.
//
// Per direction, two passes (then the sink reads the rows).
//
// The far field (distances kNear columns .. R). Parallel lines one texel apart sweep the map against
// the direction. A line's profile is sampled at every major texel centre and every minor grid crossing
// (the bilinear relief is linear along both), and texel P, the texel nearest to the line at a column,
// asks for the largest elevation (z - zP) / (tP - t) over the samples with t in [tP - R, tP - kNear dt],
// plus the point at exactly R. That window slides, so the line is cut into blocks as long as the window
// (L = R - kNear dt): a window always lies in the end of one block and the start of the next. The start
// of the current block is an upper convex hull on a stack, pushed in order (Timonen & Westerholm 2010:
// pushing a point pops the ones it hides). The end of the previous block is a hull built backwards,
// from the block's last sample to its first, with an undo log: as the window's start moves on, the
// samples it leaves are undone in the reverse order of their pushes. Each sample is pushed twice and
// popped at most twice; each query is a tangent search on two hulls, from where the previous one ended.
//
// The near field (up to kNear columns), walked exactly on each texel's own line: every crossing and the
// quadratic arc inside each cell, plus the t -> 0+ slope. Every texel's own line has the same offsets
// to the grid, so this is one stencil with constant weights, run a row at a time over contiguous
// memory (vectorised). It runs first; the far field then raises each texel's tan h.
//
// The line is at most half a texel beside P, and that offset only matters beyond kNear columns, where
// it changes the elevation by at most (offset x slope across) / distance.
#include "horizon_line.h"
#include "horizon_search.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace strata::detail {
namespace {

// Columns walked exactly on each texel's own line before the far field takes over. 4 keeps the far
// field's lateral error below 0.003 AO RMSE against the exact walk on every built-in pattern
// (docs/occlusion.md); 2 doubles it, 8 costs twice the time for a further halving.
constexpr int kNear = 4;
constexpr int kPad = kNear + 2;

struct HullPoint {
    float t;
    float z;
};

// > 0 when c lies above the line through a and b (a.t < b.t).
inline float orient(const HullPoint& a, const HullPoint& b, const HullPoint& c) {
    return (b.t - a.t) * (c.z - a.z) - (b.z - a.z) * (c.t - a.t);
}

// z = -S d in (major a, minor b) order: row b holds minor index b, contiguous along the major axis.
// The minor axis is stored twice over (b in [0, 2 sizeB)) so that line j's row j + b never wraps, and
// kPad wrapped texels pad every side for the near field.
class PaddedRelief {
public:
    PaddedRelief(const Image& depth, bool xMajor, float scale)
        : mSizeA(xMajor ? depth.width() : depth.height()),
          mSizeB(xMajor ? depth.height() : depth.width()),
          mStride(mSizeA + 2 * kPad),
          mZ(static_cast<std::size_t>(mStride) * static_cast<std::size_t>(2 * mSizeB + 2 * kPad)) {
        for (int b = -kPad; b < 2 * mSizeB + kPad; ++b)
            for (int a = -kPad; a < mSizeA + kPad; ++a) {
                const int aw = MajorMinorDepth::wrap(a, mSizeA);
                const int bw = MajorMinorDepth::wrap(b, mSizeB);
                mZ[index(a, b)] = -scale * (xMajor ? depth.at(aw, bw) : depth.at(bw, aw));
            }
    }
    // a in [-kPad, sizeA + kPad), b in [-kPad, 2 sizeB + kPad).
    std::ptrdiff_t index(int a, int b) const {
        return static_cast<std::ptrdiff_t>(b + kPad) * mStride + static_cast<std::ptrdiff_t>(a + kPad);
    }
    const float* data() const { return mZ.data(); }
    const float* row(int b) const { return mZ.data() + index(0, b); }
    std::ptrdiff_t stride() const { return mStride; }
    int sizeA() const { return mSizeA; }
    int sizeB() const { return mSizeB; }

private:
    int mSizeA;
    int mSizeB;
    std::ptrdiff_t mStride;
    std::vector<float> mZ;
};

// One cell-segment of the near field, relative to texel P = (a, r): the segment runs inside the cell
// between major steps q - 1 and q (towards the direction) and minor rows r + minor, r + minor + 1,
// from (alpha0, beta0) to (alpha1, beta1) in the cell's unit square, from distance t0 to t1.
struct NearSegment {
    int q;
    int minor;
    float alpha0, beta0, alpha1, beta1;
    float t0, t1;
};

// What every line of one direction shares. Line j (j in [0, sizeB)) at processing step k crosses
// column a_k = start + order k (unwrapped; against the direction, so that samples already seen lie
// towards the direction) at minor coordinate j + a_k slope; t = k dt grows along the line.
struct DirectionPlan {
    LineDirection dir;
    int sizeA = 0;
    int sizeB = 0;
    double radius = 1.0;
    // Queries, k in [0, sizeA): the texel of line j at step k is (texelColumn[k], j + texelRow[k]).
    std::vector<int> texelColumn;
    std::vector<int> texelRow;
    // The far field, empty when R <= kNear dt.
    bool hasFar = false;
    float blockLength = 0.0f;  // L = R - kNear dt
    int firstStep = 0;         // k of the first sample
    // Samples in order of t: z = (1 - w) Z[index0 + j stride] + w Z[index1 + j stride].
    std::vector<float> sampleT;
    std::vector<std::ptrdiff_t> sampleIndex0;
    std::vector<std::ptrdiff_t> sampleIndex1;
    std::vector<float> sampleW;
    std::vector<int> sampleBlock;       // floor(t / L)
    std::vector<int> columnSample;      // k - firstStep -> the index of the column sample at step k
    std::vector<int> blockFirstSample;  // block - sampleBlock[0] -> its first sample (and one past the end)
    // The point at exactly R before texel k: bilinear between columns k1, k1 + 1 (weight alpha of the
    // second) and rows r, r + 1 (weight boundaryFrac[k]); index of (k1, r) for line 0, and of (k1 + 1, r).
    std::vector<std::ptrdiff_t> boundaryIndex0;
    std::vector<std::ptrdiff_t> boundaryIndex1;
    std::vector<float> boundaryFrac;
    std::vector<float> boundaryAlpha;
    // The near field.
    std::vector<NearSegment> near;
    float coefMajor = 0.0f;  // the t -> 0+ slope: coefMajor (z(a + step) - zP) + coefMinor (z(r + side) - zP)
    float coefMinor = 0.0f;
    int sideMinor = 1;

    DirectionPlan(const LineDirection& direction, const PaddedRelief& relief, double radiusTiles)
        : dir(direction), sizeA(relief.sizeA()), sizeB(relief.sizeB()), radius(radiusTiles) {
        const int order = -dir.step;
        const int start = order < 0 ? sizeA - 1 : 0;
        const double slope = dir.g * dir.step;  // minor per +1 major
        const double dt = dir.dt;
        auto minorAt = [&](double k) { return (start + order * k) * slope; };
        auto column = [&](int k) { return MajorMinorDepth::wrap(start + order * k, sizeA); };
        auto wrapB = [&](double b) { return MajorMinorDepth::wrap(static_cast<int>(b), sizeB); };

        texelColumn.resize(static_cast<std::size_t>(sizeA));
        texelRow.resize(texelColumn.size());
        for (int k = 0; k < sizeA; ++k) {
            texelColumn[static_cast<std::size_t>(k)] = column(k);
            texelRow[static_cast<std::size_t>(k)] = wrapB(std::round(minorAt(k)));
        }

        const double farLength = radius - kNear * dt;
        hasFar = farLength > 0.0 && sizeA > kNear;
        if (hasFar) {
            blockLength = static_cast<float>(farLength);
            firstStep = static_cast<int>(std::floor(-radius / dt)) - 1;
            const int lastStep = sizeA - 1 - kNear;
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
            for (const float t : sampleT)
                sampleBlock.push_back(static_cast<int>(std::floor(t / blockLength)));
            for (std::size_t s = 0; s < sampleBlock.size(); ++s)
                while (static_cast<int>(blockFirstSample.size()) <= sampleBlock[s] - sampleBlock[0])
                    blockFirstSample.push_back(static_cast<int>(s));
            blockFirstSample.push_back(static_cast<int>(sampleBlock.size()));

            for (int k = 0; k < sizeA; ++k) {
                const double u = k - radius / dt;
                const double k1 = std::floor(u);
                const double b = minorAt(u);
                const double fb = std::floor(b);
                boundaryIndex0.push_back(relief.index(column(static_cast<int>(k1)), wrapB(fb)));
                boundaryIndex1.push_back(relief.index(column(static_cast<int>(k1) + 1), wrapB(fb)));
                boundaryFrac.push_back(static_cast<float>(b - fb));
                boundaryAlpha.push_back(static_cast<float>(u - k1));
            }
        }

        // The near field's cell segments along a texel's own line, minor offset q g at step q, up to
        // kNear steps or R, whichever is nearer.
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
                near.push_back({q, static_cast<int>(m), static_cast<float>(alpha0),
                                static_cast<float>(beta0 - m), static_cast<float>(alpha1),
                                static_cast<float>(beta1 - m), static_cast<float>(s0),
                                static_cast<float>(s1)});
            }
            b0 = b1;
        }
        const double cx = std::abs(dir.cosPhi) * (dir.xMajor ? sizeA : sizeB);
        const double cy = std::abs(dir.sinPhi) * (dir.xMajor ? sizeB : sizeA);
        coefMajor = static_cast<float>(dir.xMajor ? cx : cy);
        coefMinor = static_cast<float>(dir.xMajor ? cy : cx);
        sideMinor = dir.xMajor ? dir.sideY : dir.sideX;
    }
};

// The vertex of an upper hull (points[first..last], in order along the hull, all before q in t) that
// q sees highest, i.e. the tangent from q. The elevation is unimodal along the hull, so a local search
// from the previous answer finds it.
inline int tangent(const HullPoint* points, int first, int last, int guess, HullPoint q) {
    int c = std::clamp(guess, first, last);
    while (c < last && orient(points[c], q, points[c + 1]) > 0.0f) ++c;
    while (c > first && orient(points[c], q, points[c - 1]) > 0.0f) --c;
    return c;
}

// Per-thread storage for one line at a time.
struct LineWork {
    std::vector<float> z;           // the line's samples
    std::vector<HullPoint> prefix;  // [1, prefixSize]: the current block's samples so far
    std::vector<HullPoint> suffix;  // [1, suffixSize]: the previous block's, last sample at 1
    struct Undo {
        int size;
        HullPoint overwritten;
    };
    std::vector<Undo> undo;
};

// Raises tan h of every texel of line j (in tan, row-major: sizeB rows of sizeA, holding the near
// field) to its far field over [tP - R, tP - kNear dt].
void farFieldOfLine(const PaddedRelief& relief, const DirectionPlan& plan, int j, LineWork& work,
                    float* tan) {
    const std::size_t count = plan.sampleT.size();
    const float* zmap = relief.data();
    const std::ptrdiff_t offset = static_cast<std::ptrdiff_t>(j) * relief.stride();
    work.z.resize(count);
    for (std::size_t s = 0; s < count; ++s) {
        const float w = plan.sampleW[s];
        work.z[s] =
            (1.0f - w) * zmap[plan.sampleIndex0[s] + offset] + w * zmap[plan.sampleIndex1[s] + offset];
    }
    work.prefix.resize(count + 2);
    work.suffix.resize(count + 2);
    work.undo.resize(count + 1);
    HullPoint* prefix = work.prefix.data();
    HullPoint* suffix = work.suffix.data();
    const float* t = plan.sampleT.data();
    const float* z = work.z.data();

    int prefixSize = 0;
    int suffixSize = 0;
    int undoSize = 0;
    int prefixGuess = 1;
    int suffixGuess = 1;
    int block = plan.sampleBlock[0] - 2;  // none yet
    int next = 0;                         // the next sample to push onto the prefix
    int suffixLowest = 0;                 // the suffix's earliest sample; the suffix ends before suffixEnd
    int suffixEnd = 0;
    const auto dt = static_cast<float>(plan.dir.dt);
    const auto radius = static_cast<float>(plan.radius);
    const int sizeA = plan.sizeA;
    const int sizeB = plan.sizeB;
    for (int k = 0; k < sizeA; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        const float tP = static_cast<float>(k) * dt;
        const int hiSample = plan.columnSample[static_cast<std::size_t>(k - kNear - plan.firstStep)];
        const float lo = tP - radius;
        const int hiBlock = plan.sampleBlock[static_cast<std::size_t>(hiSample)];
        if (hiBlock != block) {
            // A new block: its prefix starts empty, and the previous block becomes the suffix, built
            // from its last sample backwards.
            block = hiBlock;
            const int first = block - 1 - plan.sampleBlock[0];
            const int b0 = first >= 0 ? plan.blockFirstSample[static_cast<std::size_t>(first)] : 0;
            const int b1 = plan.blockFirstSample[static_cast<std::size_t>(first + 1)];
            prefixSize = 0;
            next = b1;
            suffixSize = 0;
            undoSize = 0;
            for (int s = b1 - 1; s >= b0; --s) {
                const HullPoint p{t[s], z[s]};
                const int size = suffixSize;
                while (suffixSize >= 2 && orient(p, suffix[suffixSize], suffix[suffixSize - 1]) >= 0.0f)
                    --suffixSize;
                ++suffixSize;
                work.undo[static_cast<std::size_t>(undoSize++)] = {size, suffix[suffixSize]};
                suffix[suffixSize] = p;
            }
            suffixLowest = b0;
            suffixEnd = b1;
            suffixGuess = 1;
        }
        for (; next <= hiSample; ++next) {
            const HullPoint p{t[next], z[next]};
            while (prefixSize >= 2 && orient(prefix[prefixSize - 1], prefix[prefixSize], p) >= 0.0f)
                --prefixSize;
            prefix[++prefixSize] = p;
        }
        // Samples before tP - R leave the suffix, last pushed first.
        for (; suffixLowest < suffixEnd && t[suffixLowest] < lo; ++suffixLowest) {
            const LineWork::Undo& u = work.undo[static_cast<std::size_t>(--undoSize)];
            suffix[suffixSize] = u.overwritten;
            suffixSize = u.size;
        }

        int row = j + plan.texelRow[kk];
        const float zP = zmap[relief.index(plan.texelColumn[kk], row)];
        if (row >= sizeB) row -= sizeB;
        float& out = tan[static_cast<std::size_t>(row) * static_cast<std::size_t>(sizeA) +
                         static_cast<std::size_t>(plan.texelColumn[kk])];
        const HullPoint q{tP, zP};
        float best = out;
        if (prefixSize > 0) {
            prefixGuess = tangent(prefix, 1, prefixSize, prefixGuess, q);
            const HullPoint& h = prefix[prefixGuess];
            best = std::max(best, (h.z - zP) / (tP - h.t));
        }
        if (suffixSize > 0) {
            suffixGuess = tangent(suffix, 1, suffixSize, suffixGuess, q);
            const HullPoint& h = suffix[suffixGuess];
            best = std::max(best, (h.z - zP) / (tP - h.t));
        }
        // The point at exactly R.
        const float fr = plan.boundaryFrac[kk];
        const float alpha = plan.boundaryAlpha[kk];
        const float* c0 = zmap + plan.boundaryIndex0[kk] + offset;
        const float* c1 = zmap + plan.boundaryIndex1[kk] + offset;
        const std::ptrdiff_t down = relief.stride();
        const float zR = (1.0f - alpha) * ((1.0f - fr) * c0[0] + fr * c0[down]) +
                         alpha * ((1.0f - fr) * c1[0] + fr * c1[down]);
        out = std::max(best, (zR - zP) / radius);
    }
}

// The near field of every texel of row b into tanRow: tanRow[a] = tan h >= 0 of texel (a, b) over
// distances up to kNear steps (or R). Every texel's own line crosses the grid at the same offsets, so
// each term is the same stencil across the row; the loops over a vectorise.
__attribute__((target_clones("avx2", "default"))) void nearFieldOfRow(const PaddedRelief& relief,
                                                                      const DirectionPlan& plan, int b,
                                                                      float* tanRow) {
    const int n = relief.sizeA();
    const int step = plan.dir.step;
    const float* zP = relief.row(b);
    {
        const float* ahead = zP + step;
        const float* side = relief.row(b + plan.sideMinor);
        const float cMajor = plan.coefMajor;
        const float cMinor = plan.coefMinor;
        for (int a = 0; a < n; ++a) {
            const float slope = cMajor * (ahead[a] - zP[a]) + cMinor * (side[a] - zP[a]);
            tanRow[a] = std::max(slope, 0.0f);
        }
    }
    for (const NearSegment& s : plan.near) {
        const int shift = step * (s.q - 1);
        const float* p00 = relief.row(b + s.minor) + shift;
        const float* p10 = p00 + step;
        const float* p01 = relief.row(b + s.minor + 1) + shift;
        const float* p11 = p01 + step;
        const float alpha0 = s.alpha0;
        const float beta0 = s.beta0;
        const float alpha1 = s.alpha1;
        const float beta1 = s.beta1;
        const float inv1 = 1.0f / s.t1;
        if (s.t0 <= 0.0f) {  // the segment from P itself: only its end (the start is the t -> 0+ slope)
            for (int a = 0; a < n; ++a) {
                const float c00 = p00[a];
                const float e = c00 - p10[a] - p01[a] + p11[a];
                const float z1 = c00 + (p10[a] - c00) * alpha1 + (p01[a] - c00) * beta1 + e * alpha1 * beta1;
                tanRow[a] = std::max(tanRow[a], (z1 - zP[a]) * inv1);
            }
            continue;
        }
        // Inside the cell the relief along the line is z(t) = qa + qb t + qc t^2 with
        // qc = e dA dB / (t1 - t0)^2; its elevation (z - zP) / t peaks where qc t^2 = qa - zP, when that
        // t lies inside the segment and the arc is concave: raiseByArcInterior's formula (horizon_line.h),
        // written out branch-free here so that the loop vectorises (calling a shared branch-free
        // version of it measured 60 % slower at 512^2: GCC 12 no longer vectorised the loop).
        const float t0 = s.t0;
        const float t1 = s.t1;
        const float invLength = 1.0f / (t1 - t0);
        const float twist = (alpha1 - alpha0) * (beta1 - beta0) * invLength * invLength;
        const float t0Squared = t0 * t0;
        const float t1Squared = t1 * t1;
        for (int a = 0; a < n; ++a) {
            const float c00 = p00[a];
            const float du = p10[a] - c00;
            const float dv = p01[a] - c00;
            const float e = c00 - p10[a] - p01[a] + p11[a];
            const float z0 = c00 + du * alpha0 + dv * beta0 + e * alpha0 * beta0;
            const float z1 = c00 + du * alpha1 + dv * beta1 + e * alpha1 * beta1;
            const float h = zP[a];
            float best = std::max(tanRow[a], (z1 - h) * inv1);
            const float qc = e * twist;
            const bool concave = qc < 0.0f;
            const float qb = (z1 - z0) * invLength - qc * (t0 + t1);
            const float qa = z0 - qb * t0 - qc * t0Squared;
            // Branch-free, so that the loop vectorises: the divisor and the root are kept finite where
            // the peak is not used.
            const float ratio = (qa - h) / std::min(qc, -1e-30f);
            const bool inside = concave & (ratio > t0Squared) & (ratio < t1Squared);
            const float tm = std::sqrt(std::min(std::max(ratio, t0Squared), t1Squared));
            const float peak = (qa + qb * tm + qc * tm * tm - h) / tm;
            tanRow[a] = std::max(best, inside ? peak : 0.0f);
        }
    }
}

// Runs the sweep for every direction and hands each row of tan h to sink(i, xMajor, b, tanRow): tanRow[a]
// is the horizon of texel (a, b) in (major, minor) coordinates.
template <typename Sink>
void sweep(const Image& depth, const AoParams& params, const Sink& sink) {
    const auto scale = static_cast<float>(params.depthScale);
    const PaddedRelief byColumns(depth, true, scale);
    const PaddedRelief byRows(depth, false, scale);
    std::vector<float> tan(static_cast<std::size_t>(depth.width()) *
                           static_cast<std::size_t>(depth.height()));
    for (int i = 0; i < params.directions; ++i) {
        const LineDirection dir(2.0 * std::numbers::pi * i / params.directions, depth.width(),
                                depth.height());
        const PaddedRelief& relief = dir.xMajor ? byColumns : byRows;
        const DirectionPlan plan(dir, relief, params.radius);
        const int sizeA = relief.sizeA();
        const int sizeB = relief.sizeB();
        const auto rowOf = [&](int b) {
            return tan.data() + static_cast<std::size_t>(b) * static_cast<std::size_t>(sizeA);
        };
        tbb::parallel_for(tbb::blocked_range<int>(0, sizeB), [&](const tbb::blocked_range<int>& rows) {
            for (int b = rows.begin(); b != rows.end(); ++b) nearFieldOfRow(relief, plan, b, rowOf(b));
        });
        if (plan.hasFar)
            tbb::parallel_for(tbb::blocked_range<int>(0, sizeB), [&](const tbb::blocked_range<int>& lines) {
                LineWork work;
                for (int j = lines.begin(); j != lines.end(); ++j)
                    farFieldOfLine(relief, plan, j, work, tan.data());
            });
        tbb::parallel_for(tbb::blocked_range<int>(0, sizeB), [&](const tbb::blocked_range<int>& rows) {
            for (int b = rows.begin(); b != rows.end(); ++b) sink(i, dir.xMajor, b, rowOf(b), sizeA);
        });
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
    sweep(depth, params, [&](int i, bool xMajor, int b, const float* tanRow, int count) {
        for (int a = 0; a < count; ++a) {
            const int x = xMajor ? a : b;
            const int y = xMajor ? b : a;
            result.tanHorizon[(static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                               static_cast<std::size_t>(x)) *
                                  dirs +
                              static_cast<std::size_t>(i)] = tanRow[a];
        }
    });
    return result;
}

Image sweepAo(const Image& depth, const AoParams& params) {
    const int w = depth.width();
    const int h = depth.height();
    // Directions with x major add into byRows (row y, along x); the others into byColumns (row x, along y).
    std::vector<float> byRows(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0f);
    std::vector<float> byColumns(byRows.size(), 0.0f);
    sweep(depth, params, [&](int, bool xMajor, int b, const float* tanRow, int count) {
        float* out = (xMajor ? byRows.data() : byColumns.data()) +
                     static_cast<std::size_t>(b) * static_cast<std::size_t>(count);
        for (int a = 0; a < count; ++a) out[a] += 1.0f / (1.0f + tanRow[a] * tanRow[a]);
    });
    // The mean, divided once at the end: a fully open texel sums to exactly M and gives exactly 1.
    Image ao(w, h, 1, 0.0f);
    const auto directions = static_cast<float>(params.directions);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            ao.at(x, y) = (byRows[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(x)] +
                           byColumns[static_cast<std::size_t>(x) * static_cast<std::size_t>(h) +
                                     static_cast<std::size_t>(y)]) /
                          directions;
    return ao;
}

}  // namespace strata::detail
