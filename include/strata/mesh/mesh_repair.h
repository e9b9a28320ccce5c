// What Strata does to a mesh that comes from outside (a file) before using it, and what it refuses.
//
// repairMesh, in this order:
//  1. Refuses (Error(InvalidInput), message starting with Mesh::name): no vertices or no triangles; an
//     index count that is not a multiple of 3; an index out of range; a non-finite position, normal, uv or
//     tangent (the message names the vertex and the attribute).
//  2. Drops triangles that repeat an index (degenerate-index triangles) and triangles of zero area:
//     |cross(p1 - p0, p2 - p0)| <= 1e-7 * (longest edge)^2, i.e. flatter than float rounding of the
//     positions can resolve (their normal would be noise).
//  3. Refuses a mesh with no triangle left ("all N triangles are degenerate").
//  4. Counts the triangles with zero uv area (|det(uv1 - uv0, uv2 - uv0)| <= 1e-7 * |uv1 - uv0| *
//     |uv2 - uv0|). They are kept (they are real geometry) but carry no tangent information
//     (tangent_space.h). If every triangle has zero uv area the mesh is refused: "texture coordinates are
//     degenerate on every triangle" (relief mapping would have no texture space; never garbage).
//  5. Removes vertices that no triangle references any more.
// The caller fills the normal/tangent fields of the report (the loader does, see mesh_loader.h).
#pragma once

#include "strata/mesh/mesh.h"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace strata {

struct MeshRepairReport {
    std::size_t repeatedIndexTriangles = 0;  // dropped: two corners share an index
    std::size_t zeroAreaTriangles = 0;       // dropped: zero area (see above)
    std::size_t zeroUvAreaTriangles = 0;     // kept, but contribute no tangent
    std::size_t removedVertices = 0;         // unreferenced vertices removed
    bool normalsComputed = false;            // the file had no normals (or they were ignored): smooth normals
    std::size_t normalsRepaired = 0;         // file normals of zero length replaced by smooth normals
    bool tangentsComputed = false;           // tangents computed by computeTangents (not read from the file)
    std::size_t tangentsRepaired = 0;        // vertices with no usable tangent (see tangent_space.h)
    std::size_t skippedPrimitives = 0;       // glTF primitives that are points or lines (ignored)

    // Number of triangles dropped in step 2.
    std::size_t droppedTriangles() const { return repeatedIndexTriangles + zeroAreaTriangles; }
};

// Marks a removed vertex in the remap of repairMesh.
constexpr std::uint32_t kRemovedVertex = std::numeric_limits<std::uint32_t>::max();

// Validates and repairs `mesh` in place (steps above) and returns what it did. Throws Error(InvalidInput)
// naming mesh.name in the cases listed above; the mesh is then unspecified. If vertexRemap is given it
// receives, for every vertex of the input, its index in the output or kRemovedVertex.
MeshRepairReport repairMesh(Mesh& mesh, std::vector<std::uint32_t>* vertexRemap = nullptr);

}  // namespace strata
