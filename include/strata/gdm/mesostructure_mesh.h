// A mesostructure's solid as a closed triangle mesh of one tile (CONVENTIONS §8), for the GDM bake and for
// `strata meso`.
#pragma once

#include "strata/gdm/mesostructure.h"
#include "strata/gdm/solid_mesh.h"

namespace strata {

inline constexpr int kMinMeshResolution = 4;
inline constexpr int kMaxMeshResolution = 1024;

// Meshes the solid intersected with the tile box [0, 1]^2 x [0, H]: the distance max(d(p), box(p)) is
// sampled at the centres of a grid of `resolution` voxels per tile width (ceil(H * resolution) along z), with
// a margin of 3 voxels on every side, and stored as an OpenVDB level set (narrow band of 3 voxels); its zero
// isosurface is extracted with openvdb::tools::volumeToMesh (adaptivity 0), each quad split into two
// triangles. Geometry that crosses a tile side is cut there, so each tile's mesh is closed, and the union of
// its integer translates (u, v) reproduces the periodic solid (the cut faces of neighbouring tiles coincide).
// Vertices within half a voxel of a tile side are moved onto it (the extraction chamfers the cut faces'
// rims); the rims still lie about 0.3 voxel inside the true section (docs/gdm.md).
// Triangles are counter-clockwise seen from outside (OpenVDB's quads face the other way for a level set that
// is negative inside; they are reversed). Positions are clamped into the box (the extraction can overshoot
// its faces by float rounding). source = meso.name(), height = meso.height().
// Throws Error(InvalidInput) for a resolution outside [kMinMeshResolution, kMaxMeshResolution] and
// Error(Runtime) if the mesh comes out empty (every part thinner than a voxel).
SolidMesh meshMesostructure(const Mesostructure& meso, int resolution = 64);

}  // namespace strata
