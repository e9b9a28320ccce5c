// Reading, checking and writing a mesostructure given as a mesh (CONVENTIONS §8): OBJ in tile units (x, y
// in [0, 1], z in [0, H]; geometry that crosses a tile side wraps, geometry outside 0 <= z <= H is clipped
// away), or an OpenVDB level set.
#pragma once

#include "strata/gdm/solid_mesh.h"

#include <filesystem>
#include <string>

namespace strata {

// How far outside the tile box [0, 1]^2 x [0, H] a vertex may lie, in tile widths: geometry that crosses a
// tile side wraps and geometry outside 0 <= z <= H is clipped away (CONVENTIONS §8), but a vertex further
// out than this is refused (it would only multiply the translates of the bake's periodic scene and
// lengthen the rays of its inside test).
inline constexpr double kSolidMeshReach = 1.0;
// Rounding allowed beyond those bounds (and in the test that the mesh meets the tile box), tile widths: a
// mesh written with 6 significant digits, or clamped in float, stays well inside it.
inline constexpr double kSolidMeshTolerance = 1e-4;

// Checks what the GDM bake needs of a solid mesh, and throws Error(InvalidInput) whose message starts with
// `what` (a file name) and names the first offending element (indices are 1-based, as in OBJ):
//   - empty: no triangles;
//   - a vertex index out of range, or a triangle with a repeated vertex (degenerate);
//   - a vertex that is not finite (NaN, inf);
//   - a vertex more than kSolidMeshReach outside the tile box [0, 1]^2 x [0, H] (x, y in [-1, 2], z in
//     [-1, H + 1]), by more than kSolidMeshTolerance. Closer, it is accepted: the bake wraps what crosses
//     a tile side (the solid is the union of the mesh's integer translates) and clips what lies outside
//     0 <= z <= H;
//   - a mesh whose vertices' bounding box does not meet the tile box at all ("lies entirely outside the
//     tile"; one that lies in a neighbouring tile must be moved by whole tiles);
//   - open: an edge used by one triangle only;
//   - non-manifold: an edge used by more than two triangles;
//   - inconsistently oriented: two triangles that use an edge in the same direction (every edge must be
//     shared by exactly two triangles, in opposite directions).
void validateSolidMesh(const SolidMesh& mesh, const std::string& what);

// Reads an OBJ: `v x y z` (extra components ignored) and `f` lines (polygons are split into fans; indices may
// be negative, relative, and carry /vt/vn parts, which are ignored); other lines are ignored. Throws
// Error(Io) if the file cannot be read, Error(InvalidInput) naming the file and line for a malformed line,
// and validateSolidMesh's errors (with the file name) otherwise. Also refuses a height that is not > 0.
SolidMesh readSolidObj(const std::filesystem::path& path, double height);

// readSolidObj on OBJ text already read: `what` (a file name) starts every message. The mesh's source is
// left empty.
SolidMesh parseSolidObj(const std::string& text, const std::string& what, double height);

// Reads the first level-set FloatGrid (class GRID_LEVEL_SET) of a .vdb, in tile units (world space is the
// tile frame), and meshes its zero isosurface as meshMesostructure does. Throws Error(Io) if the file cannot
// be opened, Error(InvalidInput) naming the file if it holds no level-set FloatGrid or the mesh fails
// validateSolidMesh with this height.
SolidMesh readSolidVdb(const std::filesystem::path& path, double height);

// Writes `v` and `f` lines (1-based, counter-clockwise from outside), 9 significant digits (every float
// reads back exactly), with a comment naming the source and H. Atomic (writeFileAtomic). Throws Error(Io) if
// it cannot be written.
void writeSolidObj(const std::filesystem::path& path, const SolidMesh& mesh);
// The text writeSolidObj writes.
std::string solidObjText(const SolidMesh& mesh);

}  // namespace strata
