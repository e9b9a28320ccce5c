// The prism shell of CONVENTIONS §8 on any triangle mesh (Wang et al. 2004, Sec. 3.2, Fig. 3): every vertex
// extruded along its unit vertex normal by T world units, every base triangle a prism of its base, its
// top and three fins, each fin the bilinear quad between two neighbouring prisms drawn as two triangles
// with the same diagonal in both. The GDM renderer draws it; the shell itself is plain geometry.
//
// Shell vertices. A mesh repeats a position where uvs or normals differ (uv seams, creases: mesh.h). The
// shell welds them (positions within 1e-6 of the mesh's size of each other are one), so that the prisms on
// both sides of a seam or a crease share their base and top corners and their fins, and the shell has no
// cracks. A welded vertex is extruded along the normalised sum of its mesh vertices' normals (the mesh's own
// normals, CONVENTIONS §8; at a crease their mean direction); where that sum vanishes, along the sum of the
// area-weighted normals of the triangles around it.
//
// Thickness. By default T = H times the world length of one tile: the area-weighted mean, over the mesh's
// triangles, of sqrt(|dP/du| |dP/dv| / (tiling.x tiling.y)), the square root of a tile's world area (the
// relief renderer's tile length along N, docs/renderer.md). §8 asks for one T per mesh ("by T world
// units"), measured from the uv-to-world scale and the tiling; this is that measure. A caller may give T.
//
// Fins. The fin over the edge between shell vertices p and q is the quad (base p, base q, top q, top p),
// split along the diagonal from base(min(p, q)) to top(max(p, q)): a rule of the two indices alone, so the
// two prisms on an edge split it the same way.
#pragma once

#include "strata/mesh/mesh.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace strata {

struct PrismShellOptions {
    double height = 0.25;             // H, the shell's thickness in tile widths (> 0)
    glm::dvec2 tiling{1.0, 1.0};      // tile coordinates = tiling * uv (> 0 each)
    std::optional<double> thickness;  // T in world units (> 0); default: H times a tile's world length
};

struct PrismShell {
    double thickness = 0.0;   // T, world units
    double tileLength = 0.0;  // the world length of one tile the default T is measured from
    // Per shell vertex (welded base position).
    std::vector<glm::vec3> base;    // P_i
    std::vector<glm::vec3> normal;  // N_i, unit
    std::vector<glm::vec3> top;     // P_i + T N_i
    // Per prism, one per mesh triangle with three distinct shell vertices, in the mesh's order
    // (counter-clockwise seen from outside): its shell vertices and its mesh vertices (for the uvs,
    // tile coordinates = tiling * uv, which differ across a seam while the shell vertex does not).
    std::vector<std::array<std::uint32_t, 3>> prisms;
    std::vector<std::array<std::uint32_t, 3>> corners;
    // Mesh triangles left out: a zero-area triangle whose corners weld into fewer than three.
    std::size_t degenerateTriangles = 0;
};

// One triangle of the shell, as three points.
using ShellTriangle = std::array<glm::vec3, 3>;

// The 8 triangles of prism `p`: [0] its base and [1] its top (both counter-clockwise seen along +N, from
// outside the base surface), then two per fin, for the edges (corner 0, 1), (1, 2), (2, 0), oriented
// outward from the prism.
std::array<ShellTriangle, 8> prismTriangles(const PrismShell& shell, std::size_t p);

// The same triangles as prism corners: which of the prism's three corners (0, 1, 2, the order of
// PrismShell::prisms and corners), at its base or its top. A renderer gives each corner its texture position
// (tiling * uv of PrismShell::corners, w = 0 at the base and 1 at the top).
struct PrismCorner {
    int corner = 0;
    bool top = false;
};
std::array<std::array<PrismCorner, 3>, 8> prismTriangleCorners(const PrismShell& shell, std::size_t p);

// Builds the shell of `mesh`. Throws Error(InvalidInput) naming the mesh for an empty mesh, indices not in
// threes or out of range, a position or normal that is not finite, H or a tiling that is not > 0, or a
// thickness that is given and not > 0 (or the default that comes out 0: a mesh whose uvs are all
// degenerate).
PrismShell buildPrismShell(const Mesh& mesh, const PrismShellOptions& options = {});

}  // namespace strata
