// strata::Mesh: an indexed triangle mesh with the per-vertex attributes relief mapping needs.
//
// Conventions (CONVENTIONS §1, §7): right-handed world space, +z up for the built-ins. Per vertex: position,
// unit normal, uv (mesh texture coordinates; tile coordinates are tiling * uv), and a tangent frame:
// tangent.xyz is the unit tangent T (direction of increasing u, orthogonal to the normal), tangent.w = +1 or
// -1 is the handedness, and the bitangent is B = tangent.w * cross(normal, tangent.xyz) (direction of
// increasing v). This is the MikkTSpace / glTF convention. Triangles are counter-clockwise seen from outside.
//
// Related headers: builtin_meshes.h (teapot, cube, sphere, ... and the unit quad of CONVENTIONS §7),
// mesh_loader.h (OBJ / glTF files), tangent_space.h (normals and MikkTSpace tangents),
// mesh_repair.h (what is done to meshes from outside). docs/meshes.md has the whole story.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace strata {

// One vertex. Vertices are not shared across UV seams or creases: a position with two uvs or two normals
// is two vertices.
struct MeshVertex {
    // World/object-space position (the units of the file; the built-ins are about 1 across).
    glm::vec3 position{0.0f};
    // Unit shading normal N, pointing out of the surface.
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    // Mesh texture coordinates; v increases upwards in the image (CONVENTIONS §1: v = 1 is the file's
    // top row). Not limited to [0, 1]: tile coordinates are tiling * uv and wrap.
    glm::vec2 uv{0.0f};
    // xyz: unit tangent T along increasing u, orthogonal to N; w: handedness, exactly +1 or -1, with
    // bitangent B = w * cross(N, T) along increasing v.
    glm::vec4 tangent{1.0f, 0.0f, 0.0f, 1.0f};
};

struct Mesh {
    std::string name;  // for messages: a built-in's name or the file's path
    std::vector<MeshVertex> vertices;
    std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from outside
};

// Axis-aligned bounds of the positions (min, max); both zero for an empty mesh.
struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
};
Bounds meshBounds(const Mesh& mesh);

// Per vertex, the object-space length of one unit of uv along T and along B: (|dP/du|, |dP/dv|), the
// columns of each triangle's uv -> position Jacobian, as the area-weighted mean over the triangles around
// the vertex. A triangle counts only where its uv determinant is above 1e-20 in magnitude, its area is > 0
// and both lengths are finite; a vertex with no such triangle gets (1, 1). Indices must be in range and
// come three per triangle (a trailing incomplete triangle is ignored). One entry per vertex, in double.
// The renderer turns these into the world size of a tile unit (strata/gl/gpu_mesh.h, docs/renderer.md).
std::vector<glm::dvec2> uvLengths(const Mesh& mesh);

}  // namespace strata
