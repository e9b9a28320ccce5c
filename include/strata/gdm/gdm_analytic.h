// GDMs in closed form, for tests and benchmarks that must not depend on the bake: the empty tile, a flat
// slab (exact), and a wavy slab (a smooth synthetic stand-in, not the exact GDM of any solid). All follow
// CONVENTIONS §8 (gdm.h): voxel centres, direction samples, 0 inside the solid, kGdmMiss for a ray that
// leaves the slab 0 <= z <= H without a hit.
#pragma once

#include "strata/gdm/gdm.h"

namespace strata {

// The empty tile: no solid, every value kGdmMiss. Throws as validateGdmDims.
Gdm makeEmptyGdm(const GdmDims& dims, double height);

// The exact GDM of the solid 0 <= w < level (a horizontal slab filling the tile below w = level), level in
// [0, 1] (0: the empty tile). A voxel centre below the level is inside (0); above it a ray going down
// meets the slab's top at (z - level H) / -cos(theta), and a ray going up leaves through the top
// (kGdmMiss). Throws as validateGdmDims, and Error(InvalidInput) for a level outside [0, 1].
Gdm makeSlabGdm(const GdmDims& dims, double height, double level);

// A synthetic, smooth GDM with the structure of a baked one (zeros inside, 1 / cos(theta) distances, misses
// up and, through holes, down): the solid below the height field
//     h(u, v) = H (0.3 + 0.3 sin(2 pi u) sin(2 pi v) + 0.15 cos(2 pi (u + 2 v))),
// which dips below 0 (holes) in places. Inside (z < h): 0. Going up: kGdmMiss. Going down: one step of the
// fixed-point iteration for the ray / height-field intersection, d = (z - h(q)) / -cos(theta), where q is
// where the ray meets the plane z = h(u, v) under the voxel centre; kGdmMiss where h(q) <= 0, and d
// clamped to >= 0. Not the exact GDM of that height field (it ignores occlusion by a second crest). Throws
// as validateGdmDims.
Gdm makeWavySlabGdm(const GdmDims& dims, double height);

}  // namespace strata
