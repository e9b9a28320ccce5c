// The signed distance volume of a mesostructure's solid mesh (issue 18, "Beyond the paper: refine"): at every
// voxel centre of a GDM grid (CONVENTIONS §8 sampling, x fastest), the Euclidean distance to the periodic
// solid's surface in tile widths (the isotropic frame (u, v, w H)), negative inside. It is not in the paper:
// the GL renderer's refine technique sphere-traces its trilinear interpolation (gdm_renderer.h), and takes
// its shading normals from its gradient.
//
//   - The solid is the bake's (gdm_bake.h): the union of the mesh's integer translates in x and y, clipped to
//     the slab 0 <= z <= H. The sign is the bake's inside test (insideSolid, a majority of 5 winding counts,
//     on the same Embree scene), so a voxel is negative exactly where gdmOccupancy(bakeGdm(...)) is 1.
//   - The magnitude is the distance to the nearest triangle of the periodic mesh, exact to float rounding
//     (Embree 3's rtcPointQuery over the bake's periodic scene, closest point on each candidate triangle in
//     double), searched up to kGdmDistanceReach: farther values are clamped to +-kGdmDistanceReach, which
//     keeps |value| <= the true distance (sphere tracing stays safe).
//   - Clipping: inside, the value is max(d_mesh, -z, z - H) (the nearer of the mesh's surface and the slab's
//     cut faces: exact); outside it is d_mesh, a lower bound of the distance to the clipped solid (equal
//     where the mesh lies in the slab, as the built-ins do).
//
// Failure: throws as bakeGdm (Error(InvalidInput) naming "GDM distance of <solid.source>" for dims or H that
// validateGdmDims refuses or a broken mesh; Error(Runtime) if Embree fails). A mesh with no triangles gives
// +kGdmDistanceReach everywhere.
#pragma once

#include "strata/gdm/gdm.h"
#include "strata/gdm/solid_mesh.h"

#include <vector>

namespace strata {

// Tile widths: how far the distance search looks (the periodic scene's reach around the tile,
// periodic_scene.h).
inline constexpr double kGdmDistanceReach = 0.2;

// The signed distance at every voxel centre of `dims` (height = solid.height), Nx Ny Nz floats, x fastest.
// Parallel over voxel rows; the result does not depend on the number of threads.
std::vector<float> bakeGdmDistance(const SolidMesh& solid, const GdmDims& dims);

}  // namespace strata
