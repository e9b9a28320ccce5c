// The GDM bake (Wang et al. 2004, "Generalized Displacement Maps", Sec. 3.1): the raw 5-D GDM of a
// mesostructure given as a solid triangle mesh, with Embree 3 as the ray engine. The value at every voxel
// centre and direction is the one CONVENTIONS §8 defines (see gdm.h), computed exactly for the solid given,
// to the float precision of Embree's ray / triangle test:
//
//   - The solid is the union of the mesh translated by every integer (i, j), intersected with the slab
//     0 <= z <= H. A point belongs to the union where the mesh's winding number there is >= 1, so copies
//     that overlap their neighbours, and separate closed parts that interpenetrate, are a union as well.
//   - Inside test: the winding number of the voxel centre is counted along 5 fixed, slightly tilted,
//     near-vertical rays that run out of the mesh's z range (each crossing of a face counts +1 where the
//     ray leaves through it, -1 where it enters); the centre is inside when a majority of the 5 counts
//     is >= 1, so a ray that grazes an edge or a vertex is outvoted. Inside: d = 0 for every direction,
//     and no other ray is cast.
//   - Otherwise the ray from the centre is traced in the periodic solid (it wraps in u and v) up to the
//     slab's top or bottom: d is the distance to the first face it meets there, whichever side the face
//     shows, or kGdmMiss if it meets none. A hit exactly at the slab's boundary counts.
//   - Clipping: rays never leave the slab, so no face outside 0 <= z <= H is ever hit, and a voxel centre
//     (strictly inside the slab) is inside the clipped solid exactly when it is inside the mesh. The cut
//     faces that clipping makes at z = 0 and z = H need no geometry: a ray that reaches the slab's boundary
//     through free space can meet a cut face there only on the face's rim (a set of measure zero).
//   - A ray within about H / kGdmBakeMaxTravel of horizontal may never leave the slab (theta = pi / 2, when
//     Ntheta is odd): after kGdmBakeMaxTravel tile widths without a hit it is recorded as kGdmMiss.
//
// Failure: throws Error(InvalidInput) naming "GDM bake of <solid.source>" for dims or H that
// validateGdmDims refuses, a triangle index out of range, or a position that is not finite;
// Error(Runtime) if Embree fails (e.g. out of memory). A mesh with no triangles is an empty volume, not an
// error: every value is kGdmMiss. A mesh that is not closed gives what its winding numbers say.
#pragma once

#include "strata/gdm/gdm.h"
#include "strata/gdm/solid_mesh.h"

#include <functional>

namespace strata {

// Tile widths a ray may travel in the slab without a hit before it is recorded as kGdmMiss.
inline constexpr double kGdmBakeMaxTravel = 64.0;

// Optional report of a long bake's progress: called with the fraction of voxels done, in [0, 1],
// non-decreasing, ending with 1. It may be called from any of the bake's threads, but never by two at once.
// An exception it throws cancels the bake and reaches bakeGdm's caller.
using GdmBakeProgress = std::function<void(double fractionDone)>;

// Bakes the raw GDM of `solid` at `dims` (§8 sampling; height = solid.height). Parallel over voxel rows
// (strata::parallelFor); the result does not depend on the number of threads.
Gdm bakeGdm(const SolidMesh& solid, const GdmDims& dims, const GdmBakeProgress& progress = {});

}  // namespace strata
