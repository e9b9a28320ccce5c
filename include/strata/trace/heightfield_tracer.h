// Exact CPU reference for rays against the relief height field (CONVENTIONS §1, §2, §7).
//
// Geometry. One relief tile covers (u, v) in [0, 1)^2 and repeats toroidally. The depth map d (one
// channel, d in [0, 1], 0 = top) is reconstructed bilinearly between texel centres with wrap-around, in
// continuous texel coordinates
//     x = u W - 0.5,   y = (1 - v) H - 0.5        (integer (x, y) = a texel centre; rows go down as v goes
//     up)
// exactly as Image::sampleTexel does. The relief surface is the set of points (u, v, -S d(u, v)) in tile
// units (S = depth scale, in tile widths). Above it (z > -S d) is empty space, below it is solid; all of
// it lies in the slab z in [-S max d, -S min d] (within [-S, 0]).
//
// Method: an exact 2-D DDA over the bilinear cells the ray's (x, y) projection crosses, with the ray's
// height above the surface solved in closed form per cell (a quadratic), in double precision; blocks of
// kBlockSize x kBlockSize cells whose relief lies wholly below the ray are skipped. docs/trace.md derives
// it and gives its measured accuracy.
//
// Thread safety: the tracer is immutable after construction; every method is const and may be called
// from any number of threads at once (callers parallelise with strata::parallelFor).
#pragma once

#include "strata/image/image.h"

#include <glm/vec3.hpp>

#include <limits>
#include <optional>
#include <vector>

namespace strata {

class HeightFieldTracer {
public:
    // Cells per side of the acceleration blocks (their min/max depth is precomputed).
    static constexpr int kBlockSize = 8;
    // The longest horizontal (u, v) travel, in tile widths, that one query walks inside the slab. Only a
    // ray within about atan(S / kMaxTravelTiles) of horizontal can stay in the slab longer; past this
    // distance it is reported as not hitting (firstHit) / not occluded (occludedFromSurface).
    static constexpr double kMaxTravelTiles = 64.0;
    static constexpr double kInfinity = std::numeric_limits<double>::infinity();

    // depth: one channel, W x H texels, the depth map d (values are used as they are; the convention is
    // [0, 1]). depthScale: S > 0, in tile widths. Copies the map (as double) and precomputes the global
    // min/max and per-block min depth. Throws Error(InvalidInput) for an empty map, a map of more than one
    // channel, a non-finite texel, or a depth scale that is not finite and > 0.
    HeightFieldTracer(const Image& depth, double depthScale);

    int width() const { return mWidth; }
    int height() const { return mHeight; }
    double depthScale() const { return mScale; }
    double minDepth() const { return mMinDepth; }  // smallest texel depth (the relief's highest point)
    double maxDepth() const { return mMaxDepth; }  // largest texel depth (the relief's lowest point)

    // The reconstructed depth at (u, v), any real u, v (wrap-around). The same reconstruction as
    // Image::sample, evaluated in double (Image::sample uses float weights: they agree to ~1e-7). At a
    // texel centre it is that texel's value.
    double depthAt(double u, double v) const;
    // The relief's z at (u, v): -S * depthAt(u, v), in tile units.
    double surfaceZ(double u, double v) const;

    struct Hit {
        double t;          // ray parameter of the hit: point = origin + t * direction
        glm::dvec3 point;  // the hit in tile units, not wrapped (it may lie in a neighbouring tile)
        double u;          // point.x wrapped to [0, 1)
        double v;          // point.y wrapped to [0, 1)
        double depth;      // reconstructed d at the hit (= -point.z / S up to rounding)
    };

    // The first point where the ray origin + t * direction, t in (tMin, tMax], meets the relief:
    //     t_hit = inf { t in (tMin, tMax] : origin.z + t direction.z <= -S d(origin.xy + t direction.xy) }.
    // The origin may be anywhere (typically above z = 0: the ray enters the slab, and may cross many tiles,
    // wrapping). direction: finite and non-zero, need not be unit (t is in multiples of its length). A ray
    // that is strictly inside the solid at tMin returns t = tMin. An origin exactly on the surface is NOT
    // robust here (rounding may report the start point): use occludedFromSurface for rays that leave the
    // surface. nullopt: no hit in (tMin, tMax] (or within kMaxTravelTiles of horizontal travel).
    // Checked (STRATA_CHECK): finite origin, finite non-zero direction, tMin finite, tMin <= tMax.
    std::optional<Hit> firstHit(const glm::dvec3& origin, const glm::dvec3& direction, double tMin = 0.0,
                                double tMax = kInfinity) const;

    // Shadow / AO query from the surface point (u, v, surfaceZ(u, v)): is any of the relief strictly
    // between that point and the point maxDistance along direction, i.e. does the ray go below the surface
    // for some t in (0, maxDistance]? direction: finite, non-zero, need not be unit (maxDistance is in
    // multiples of its length, so tile widths for a unit direction); maxDistance >= 0 (may be kInfinity).
    // Robust at the start point: f(t) = z(t) + S d is solved in the starting cell as t (b + c t), exactly
    // zero at t = 0, so the start point never occludes itself:
    //   - a ray that leaves below the local tangent plane (into the solid, b < 0) is occluded, however small
    //     maxDistance > 0 is;
    //   - a ray along the tangent plane of a flat region (f = 0 identically) is NOT occluded (touching the
    //     surface does not occlude; only going below it does);
    //   - a start within kSnapTexels of a texel-centre line (x or y integer: a cell border) is moved onto it,
    //     so that a start computed as (i + 0.5) / W is on the texel centre, not in a 1e-16 sliver of the
    //     neighbouring cell (whose slope differs);
    //   - in later cells the ray counts as below the surface only where f < -kSurfaceTolerance * S, which
    //     absorbs rounding where the start lies within ~1e-12 texel of a cell border.
    bool occludedFromSurface(double u, double v, const glm::dvec3& direction, double maxDistance) const;

    // Relative tolerance (times S, in tile units) that occludedFromSurface allows below the surface outside
    // the starting cell. It moves an occlusion boundary by about 1e-12 rad.
    static constexpr double kSurfaceTolerance = 1e-12;
    // How close (in texels) a start of occludedFromSurface must be to a texel-centre line to be snapped onto
    // it.
    static constexpr double kSnapTexels = 1e-9;

private:
    struct Block {
        double minDepth;  // smallest corner depth of the block's cells (its highest point)
    };
    struct Ray;  // the ray in the walk's frame (heightfield_tracer.cpp)
    enum class WalkMode { HitOpenStart, HitClosedStart, FromSurface };

    double texel(int x, int y) const;  // wrap-around texel lookup
    // Walks the ray over s in [sStart, sEnd]; see the .cpp. Returns the hit's s or kInfinity.
    double walk(const Ray& ray, double sStart, double sEnd, WalkMode mode) const;

    int mWidth = 0;
    int mHeight = 0;
    int mBlocksX = 0;
    int mBlocksY = 0;
    double mScale = 0.0;
    double mMinDepth = 0.0;
    double mMaxDepth = 0.0;
    std::vector<double> mDepth;  // row-major, top row first, like Image
    std::vector<Block> mBlocks;  // mBlocksX x mBlocksY, block (I, J) = cells [8I, 8I+8) x [8J, 8J+8)
};

}  // namespace strata
