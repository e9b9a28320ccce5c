// Exact ray / bilinear height field intersection (include/strata/trace/heightfield_tracer.h,
// docs/trace.md).
#include "strata/trace/heightfield_tracer.h"

#include "strata/core/check.h"
#include "strata/core/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace strata {

// The ray in the walk's frame: texel coordinates (X, Y) and tile-unit Z as functions of s = t - tBase,
// with the base point moved into tile 0 (an integer shift of whole tiles, which the relief ignores).
struct HeightFieldTracer::Ray {
    double x0, y0, z0;  // position at s = 0: X in texels (columns), Y in texels (rows, down), Z in tiles
    double qx, qy, dz;  // d/ds of X, Y, Z
    int sx, sy;         // step direction of the cell walk in X and Y (+1, -1, 0)
};

namespace {

int floorDiv(int a, int n) {
    return a >= 0 ? a / n : -((-a + n - 1) / n);
}

// The cell index containing coordinate p for a ray moving with sign `step`: on a boundary (p integer) the
// cell the ray moves into.
int cellIndex(double p, int step) {
    const double f = std::floor(p);
    if (step < 0 && f == p) return static_cast<int>(f) - 1;
    return static_cast<int>(f);
}

int signOf(double value) {
    return value > 0.0 ? 1 : (value < 0.0 ? -1 : 0);
}

// Parameter at which the coordinate p0 + q s reaches `boundary`; +inf when q = 0.
double crossing(double boundary, double p0, double q) {
    return q != 0.0 ? (boundary - p0) / q : HeightFieldTracer::kInfinity;
}

// Smallest root in [0, length] of g(s) = g0 + g1 s + g2 s^2, given g0 > 0; +inf when there is none.
// Numerically stable form (q = -(g1 + sign(g1) sqrt(disc)) / 2, roots q / g2 and g0 / q), which also covers
// the linear case g2 = 0 (the root g0 / q = -g0 / g1).
double firstRoot(double g0, double g1, double g2, double length) {
    const double disc = g1 * g1 - 4.0 * g2 * g0;
    if (disc < 0.0) return HeightFieldTracer::kInfinity;
    const double q = -0.5 * (g1 + std::copysign(std::sqrt(disc), g1));
    double best = HeightFieldTracer::kInfinity;
    if (q != 0.0) {
        const double r = g0 / q;
        if (r >= 0.0 && r <= length) best = r;
    }
    if (g2 != 0.0) {
        const double r = q / g2;
        if (r >= 0.0 && r <= length) best = std::min(best, r);
    }
    return best;
}

bool finite(const glm::dvec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

}  // namespace

HeightFieldTracer::HeightFieldTracer(const Image& depth, double depthScale) {
    if (depth.empty()) throw Error(ErrorKind::InvalidInput, "height field tracer: the depth map is empty");
    if (depth.channels() != 1)
        throw Error(ErrorKind::InvalidInput, "height field tracer: the depth map has " +
                                                 std::to_string(depth.channels()) + " channels, expected 1");
    if (!std::isfinite(depthScale) || depthScale <= 0.0)
        throw Error(ErrorKind::InvalidInput,
                    "height field tracer: depth scale " + formatNumber(depthScale) + " is not > 0");
    mWidth = depth.width();
    mHeight = depth.height();
    mScale = depthScale;
    mDepth.resize(depth.texelCount());
    mMinDepth = kInfinity;
    mMaxDepth = -kInfinity;
    for (int y = 0; y < mHeight; ++y) {
        for (int x = 0; x < mWidth; ++x) {
            const double value = static_cast<double>(depth.at(x, y));
            if (!std::isfinite(value))
                throw Error(ErrorKind::InvalidInput, "height field tracer: depth texel (" +
                                                         std::to_string(x) + ", " + std::to_string(y) +
                                                         ") is " + formatNumber(value));
            mDepth[static_cast<std::size_t>(y) * static_cast<std::size_t>(mWidth) +
                   static_cast<std::size_t>(x)] = value;
            mMinDepth = std::min(mMinDepth, value);
            mMaxDepth = std::max(mMaxDepth, value);
        }
    }
    // Block (I, J) holds cells [8I, 8I + 8) x [8J, 8J + 8) (the last ones narrower when 8 does not divide the
    // size); a cell's corners are texels i..i+1, so the block's highest point is the smallest depth over the
    // texels [8I, 8I + 8] x [8J, 8J + 8], wrapped.
    mBlocksX = (mWidth + kBlockSize - 1) / kBlockSize;
    mBlocksY = (mHeight + kBlockSize - 1) / kBlockSize;
    mBlocks.resize(static_cast<std::size_t>(mBlocksX) * static_cast<std::size_t>(mBlocksY));
    for (int by = 0; by < mBlocksY; ++by) {
        for (int bx = 0; bx < mBlocksX; ++bx) {
            const int x1 = std::min(bx * kBlockSize + kBlockSize, mWidth);
            const int y1 = std::min(by * kBlockSize + kBlockSize, mHeight);
            double lowest = kInfinity;
            for (int y = by * kBlockSize; y <= y1; ++y)
                for (int x = bx * kBlockSize; x <= x1; ++x) lowest = std::min(lowest, texel(x, y));
            mBlocks[static_cast<std::size_t>(by) * static_cast<std::size_t>(mBlocksX) +
                    static_cast<std::size_t>(bx)]
                .minDepth = lowest;
        }
    }
}

double HeightFieldTracer::texel(int x, int y) const {
    const int wx = Image::wrap(x, mWidth);
    const int wy = Image::wrap(y, mHeight);
    return mDepth[static_cast<std::size_t>(wy) * static_cast<std::size_t>(mWidth) +
                  static_cast<std::size_t>(wx)];
}

double HeightFieldTracer::depthAt(double u, double v) const {
    const double x = (u - std::floor(u)) * mWidth - 0.5;
    const double y = (1.0 - (v - std::floor(v))) * mHeight - 0.5;
    const double fx = std::floor(x);
    const double fy = std::floor(y);
    const int i = static_cast<int>(fx);
    const int j = static_cast<int>(fy);
    const double tx = x - fx;
    const double ty = y - fy;
    const double top = texel(i, j) + tx * (texel(i + 1, j) - texel(i, j));
    const double bottom = texel(i, j + 1) + tx * (texel(i + 1, j + 1) - texel(i, j + 1));
    return top + ty * (bottom - top);
}

double HeightFieldTracer::surfaceZ(double u, double v) const {
    return -mScale * depthAt(u, v);
}

// The walk over s in [sStart, sEnd] (both finite). Outer loop: acceleration blocks, skipped whole when the
// ray's lowest z over the block is above the block's highest point. Inner loop: the block's cells, each
// solved exactly. WalkMode::FromSurface: occludedFromSurface's query (first cell in factored form, tolerance
// elsewhere); HitOpenStart / HitClosedStart: firstHit's, with sStart excluded (it is tMin) or included (it
// is the slab entry, after tMin). Returns the s of the hit (firstHit: the first point on or below the
// surface; occludedFromSurface: a point below it), or kInfinity.
double HeightFieldTracer::walk(const Ray& ray, double sStart, double sEnd, WalkMode mode) const {
    const bool fromSurface = mode == WalkMode::FromSurface;
    const double slack = fromSurface ? kSurfaceTolerance * mScale : 0.0;
    int ci = cellIndex(ray.x0 + ray.qx * sStart, ray.sx);
    int cj = cellIndex(ray.y0 + ray.qy * sStart, ray.sy);
    double s = sStart;
    bool firstCell = true;
    while (s < sEnd || firstCell) {
        // The block holding cell (ci, cj), in unwrapped cell indices: [bx0, bx1) x [by0, by1).
        const int tileX = floorDiv(ci, mWidth);
        const int tileY = floorDiv(cj, mHeight);
        const int blockX = (ci - tileX * mWidth) / kBlockSize;
        const int blockY = (cj - tileY * mHeight) / kBlockSize;
        const int bx0 = tileX * mWidth + blockX * kBlockSize;
        const int by0 = tileY * mHeight + blockY * kBlockSize;
        const int bx1 = tileX * mWidth + std::min(blockX * kBlockSize + kBlockSize, mWidth);
        const int by1 = tileY * mHeight + std::min(blockY * kBlockSize + kBlockSize, mHeight);
        const double blockExitX = crossing(ray.sx > 0 ? bx1 : bx0, ray.x0, ray.qx);
        const double blockExitY = crossing(ray.sy > 0 ? by1 : by0, ray.y0, ray.qy);
        const double blockEnd = std::min({blockExitX, blockExitY, sEnd});
        const double blockTop =
            -mScale * mBlocks[static_cast<std::size_t>(blockY) * static_cast<std::size_t>(mBlocksX) +
                              static_cast<std::size_t>(blockX)]
                          .minDepth;
        const double lowestZ = std::min(ray.z0 + ray.dz * s, ray.z0 + ray.dz * std::max(blockEnd, s));
        if (!firstCell && lowestZ > blockTop - slack) {
            if (blockEnd >= sEnd) return kInfinity;
            // Into the neighbouring block: step across the side(s) left through, and find the other index at
            // the exit point, kept inside this block's range against rounding.
            s = std::max(s, blockEnd);
            if (blockExitX <= blockExitY) {
                ci = ray.sx > 0 ? bx1 : bx0 - 1;
                if (blockExitY > blockExitX)
                    cj = std::clamp(cellIndex(ray.y0 + ray.qy * s, ray.sy), by0, by1 - 1);
            }
            if (blockExitY <= blockExitX) {
                cj = ray.sy > 0 ? by1 : by0 - 1;
                if (blockExitX > blockExitY)
                    ci = std::clamp(cellIndex(ray.x0 + ray.qx * s, ray.sx), bx0, bx1 - 1);
            }
            continue;
        }
        // The cells of this block, in order along the ray.
        while (ci >= bx0 && ci < bx1 && cj >= by0 && cj < by1) {
            const double exitX = crossing(ray.sx > 0 ? ci + 1 : ci, ray.x0, ray.qx);
            const double exitY = crossing(ray.sy > 0 ? cj + 1 : cj, ray.y0, ray.qy);
            const double cellEnd = std::max(s, std::min({exitX, exitY, sEnd}));
            const double length = cellEnd - s;
            const double d00 = texel(ci, cj);
            const double d10 = texel(ci + 1, cj);
            const double d01 = texel(ci, cj + 1);
            const double d11 = texel(ci + 1, cj + 1);
            const double cellTop = -mScale * std::min(std::min(d00, d10), std::min(d01, d11));
            const double zIn = ray.z0 + ray.dz * s;
            const double zOut = ray.z0 + ray.dz * cellEnd;
            if (firstCell || std::min(zIn, zOut) <= cellTop - slack) {
                // Bilinear d = d00 + e1 fx + e2 fy + e3 fx fy with fx = fx0 + qx r, fy = fy0 + qy r (r = s -
                // s_in) is D0 + D1 r + D2 r^2 along the ray; g(r) = z(r) + S d is the signed height above the
                // surface.
                const double e1 = d10 - d00;
                const double e2 = d01 - d00;
                const double e3 = d00 - d10 - d01 + d11;
                const double fx0 = ray.x0 + ray.qx * s - ci;
                const double fy0 = ray.y0 + ray.qy * s - cj;
                const double depth0 = d00 + e1 * fx0 + e2 * fy0 + e3 * fx0 * fy0;
                const double depth1 = e1 * ray.qx + e2 * ray.qy + e3 * (fx0 * ray.qy + fy0 * ray.qx);
                const double depth2 = e3 * ray.qx * ray.qy;
                const double g1 = ray.dz + mScale * depth1;
                const double g2 = mScale * depth2;
                if (fromSurface) {
                    if (firstCell) {
                        // g(0) = 0 exactly at the start point: g = r (g1 + g2 r), below the surface somewhere
                        // in (0, length] iff g1 < 0 or g1 + g2 length < 0 (linear in r).
                        if (g1 < 0.0 || (length > 0.0 && g1 + g2 * length < 0.0)) return s;
                    } else {
                        const double g0 = zIn + mScale * depth0;
                        const double limit = -slack;
                        if (g0 < limit) return s;
                        if (g0 + g1 * length + g2 * length * length < limit) return cellEnd;
                        if (g2 > 0.0) {
                            const double r = -g1 / (2.0 * g2);
                            if (r > 0.0 && r < length && g0 + r * (g1 + g2 * r) < limit) return s + r;
                        }
                    }
                } else {
                    const double g0 = zIn + mScale * depth0;
                    if (firstCell && mode == WalkMode::HitOpenStart) {
                        // t_hit = inf {t > tMin : g <= 0}: at the start itself only if the ray is below the
                        // surface or on it and not leaving upwards.
                        if (g0 < 0.0 || (g0 == 0.0 && (g1 < 0.0 || (g1 == 0.0 && g2 <= 0.0)))) return s;
                    } else if (g0 <= 0.0) {
                        return s;
                    }
                    if (g0 > 0.0) {
                        const double r = firstRoot(g0, g1, g2, length);
                        if (r <= length) return s + r;
                        // Rounding fallback: the end is on or below the surface though no root was found.
                        if (g0 + g1 * length + g2 * length * length <= 0.0) return cellEnd;
                    }
                }
            }
            firstCell = false;
            s = cellEnd;
            if (cellEnd >= sEnd) return kInfinity;
            if (exitX <= exitY) ci += ray.sx;
            if (exitY <= exitX) cj += ray.sy;
        }
    }
    return kInfinity;
}

std::optional<HeightFieldTracer::Hit> HeightFieldTracer::firstHit(const glm::dvec3& origin,
                                                                  const glm::dvec3& direction, double tMin,
                                                                  double tMax) const {
    STRATA_CHECK(finite(origin));
    STRATA_CHECK(finite(direction));
    STRATA_CHECK(direction != glm::dvec3(0.0));
    STRATA_CHECK(std::isfinite(tMin));
    STRATA_CHECK_LE(tMin, tMax);

    // Clip (tMin, tMax] to where the ray is at or below the relief's top (z <= -S min d): nothing above
    // can be hit. Below the bottom (z <= -S max d) everything is solid, so a hit comes no later than there.
    const double top = -mScale * mMinDepth;
    const double bottom = -mScale * mMaxDepth;
    double tStart = tMin;
    double tEnd = tMax;
    bool endsAtBottom = false;  // tEnd is where the ray reaches the bottom: a hit at tEnd at the latest
    if (direction.z > 0.0) {
        tEnd = std::min(tEnd, (top - origin.z) / direction.z);
    } else if (direction.z < 0.0) {
        tStart = std::max(tStart, (top - origin.z) / direction.z);
        const double tBottom = std::max(tStart, (bottom - origin.z) / direction.z);
        endsAtBottom = tBottom <= tEnd;
        tEnd = std::min(tEnd, tBottom);
    } else if (origin.z > top) {
        return std::nullopt;
    }
    const double horizontal = std::hypot(direction.x, direction.y);
    if (horizontal > 0.0 && tStart + kMaxTravelTiles / horizontal < tEnd) {
        tEnd = tStart + kMaxTravelTiles / horizontal;
        endsAtBottom = false;
    }
    if (tEnd < tStart) return std::nullopt;
    if (!std::isfinite(tEnd)) return std::nullopt;  // unreachable: z moves or horizontal travel is capped

    // Rebase at tStart, shifted by whole tiles into tile 0, in texel units.
    const glm::dvec3 base = origin + tStart * direction;
    Ray ray{};
    ray.x0 = (base.x - std::floor(base.x)) * mWidth - 0.5;
    ray.y0 = (1.0 - (base.y - std::floor(base.y))) * mHeight - 0.5;
    ray.z0 = base.z;
    ray.qx = direction.x * mWidth;
    ray.qy = -direction.y * mHeight;
    ray.dz = direction.z;
    ray.sx = signOf(ray.qx);
    ray.sy = signOf(ray.qy);
    // The open end tMin is excluded from the hits; a slab entry after it is not.
    const double s =
        walk(ray, 0.0, tEnd - tStart, tStart == tMin ? WalkMode::HitOpenStart : WalkMode::HitClosedStart);
    // At the bottom f = z + S d <= 0 exactly; a root within rounding of it may still have been missed (a
    // flat map's slab has zero thickness): the hit is there.
    if (!(s < kInfinity) && !endsAtBottom) return std::nullopt;

    Hit hit{};
    hit.t = s < kInfinity ? tStart + s : tEnd;
    hit.point = origin + hit.t * direction;
    hit.u = hit.point.x - std::floor(hit.point.x);
    hit.v = hit.point.y - std::floor(hit.point.y);
    if (hit.u >= 1.0) hit.u = 0.0;
    if (hit.v >= 1.0) hit.v = 0.0;
    hit.depth = depthAt(hit.u, hit.v);
    return hit;
}

bool HeightFieldTracer::occludedFromSurface(double u, double v, const glm::dvec3& direction,
                                            double maxDistance) const {
    STRATA_CHECK(std::isfinite(u) && std::isfinite(v));
    STRATA_CHECK(finite(direction));
    STRATA_CHECK(direction != glm::dvec3(0.0));
    STRATA_CHECK(maxDistance >= 0.0);
    if (maxDistance == 0.0) return false;

    Ray ray{};
    ray.x0 = (u - std::floor(u)) * mWidth - 0.5;
    ray.y0 = (1.0 - (v - std::floor(v))) * mHeight - 0.5;
    // A start within kSnapTexels of a texel-centre line (a cell border) is put on it: (i + 0.5) / W * W - 0.5
    // is i only up to rounding, and a start 1e-16 before the border would begin in a sliver of the
    // neighbouring cell, whose slope is not the one the ray leaves along.
    auto snap = [](double p) {
        const double nearest = std::round(p);
        return std::abs(p - nearest) <= kSnapTexels ? nearest : p;
    };
    ray.x0 = snap(ray.x0);
    ray.y0 = snap(ray.y0);
    ray.z0 = 0.0;  // set below, from the starting cell's own reconstruction
    ray.qx = direction.x * mWidth;
    ray.qy = -direction.y * mHeight;
    ray.dz = direction.z;
    ray.sx = signOf(ray.qx);
    ray.sy = signOf(ray.qy);
    {
        const int i = cellIndex(ray.x0, ray.sx);
        const int j = cellIndex(ray.y0, ray.sy);
        const double fx = ray.x0 - i;
        const double fy = ray.y0 - j;
        // The same expression as the walk's depth0 at s = 0 in this cell, expanded the same way, so that the
        // start is on the walk's surface up to one rounding.
        const double e1 = texel(i + 1, j) - texel(i, j);
        const double e2 = texel(i, j + 1) - texel(i, j);
        const double e3 = texel(i, j) - texel(i + 1, j) - texel(i, j + 1) + texel(i + 1, j + 1);
        ray.z0 = -mScale * (texel(i, j) + e1 * fx + e2 * fy + e3 * fx * fy);
    }

    // Above the relief's top nothing occludes; an upward ray is done when it gets there.
    double sEnd = maxDistance;
    const double top = -mScale * mMinDepth;
    if (ray.dz > 0.0) sEnd = std::min(sEnd, std::max(0.0, (top - ray.z0) / ray.dz));
    const double horizontal = std::hypot(direction.x, direction.y);
    if (horizontal > 0.0) sEnd = std::min(sEnd, kMaxTravelTiles / horizontal);
    // A downward ray is below the surface (by more than the tolerance) once under the relief's bottom.
    const double bottom = -mScale * mMaxDepth - 2.0 * kSurfaceTolerance * mScale;
    if (ray.dz < 0.0) sEnd = std::min(sEnd, std::max(0.0, (bottom - ray.z0) / ray.dz));
    if (!std::isfinite(sEnd)) return false;  // unreachable: z moves or horizontal travel is capped
    return walk(ray, 0.0, sEnd, WalkMode::FromSurface) < kInfinity;
}

}  // namespace strata
