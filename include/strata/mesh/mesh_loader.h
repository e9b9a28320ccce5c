// Loading triangle meshes from files: Wavefront OBJ (tinyobjloader), glTF 2.0 (tinygltf) and OFF.
//
// By extension (case-insensitive):
//  .obj          polygons are triangulated; every face must have texture coordinates (vt); faces may
//                use several materials (ignored). Vertices are unwelded: one vertex per distinct
//                (position, uv, normal) index triple. OBJ's vt has v up, like Strata: no flip.
//  .gltf / .glb  every triangle primitive (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN) of every mesh
//                instanced by the nodes of the default scene (scene 0 if none is marked; every mesh once,
//                untransformed, if the file has no scenes), with the node transforms applied: positions by
//                the world matrix, normals by its inverse transpose, tangents by its upper 3x3 (w negated
//                and the winding reversed when the matrix mirrors). Points and lines are skipped (counted).
//                TEXCOORD_0 is the uv, with glTF's top-left origin flipped to Strata's: v = 1 - v_gltf.
//                A TANGENT attribute is used as given (its B = w * cross(N, T) already points image-up,
//                i.e. along Strata's increasing v), re-orthogonalised against the normal.
//                Images are not decoded.
//  .off          plain OFF (Geomview; the Stanford bunny that Debian ships is one): "OFF", the counts
//                "V F E" (on the header line or the next), V lines "x y z", F lines "n i0 .. i(n-1)" (any
//                trailing colour ignored), '#' comments. Polygons become fans. OFF has no uvs or normals:
//                it loads only with requireUvs = false. The per-vertex variants (COFF, NOFF, STOFF, ...)
//                are Error(Unsupported).
// Without requireUvs, a file (or a glTF primitive, or an OBJ face) without texture coordinates gives every
// vertex of the mesh planar uvs: the positions projected onto the plane of the bounds' two largest extents,
// scaled by the larger into [0, 1]. That is enough for the repairs and tangents, not a texture layout.
// Then the mesh is repaired (mesh_repair.h); a file without normals gets area-weighted smooth normals and
// one without tangents MikkTSpace tangents (tangent_space.h; they can split vertices). Mesh::name is the
// path.
//
// Errors (the message starts with the path):
//   Error(Io)            the file does not exist or cannot be read;
//   Error(Unsupported)   another extension; a sparse glTF accessor;
//   Error(InvalidInput)  the parser's message for a malformed file; "has no texture coordinates; relief
//                        mapping needs them" (with requireUvs); non-finite values; indices out of range; an
//                        empty mesh; and the refusals of repairMesh.
#pragma once

#include "strata/mesh/mesh.h"
#include "strata/mesh/mesh_repair.h"

#include <filesystem>

namespace strata {

struct MeshLoadOptions {
    // Ignore the file's normals and compute area-weighted smooth normals. Default false.
    bool recomputeNormals = false;
    // Ignore the file's tangents (glTF TANGENT) and compute them (tangent_space.h). Default false.
    bool recomputeTangents = false;
    // Refuse a file without texture coordinates (relief mapping needs them). False: give it planar uvs
    // (above), for uses that need only positions and normals, such as dual-depth sampling. Default true.
    bool requireUvs = true;
};

Mesh loadMesh(const std::filesystem::path& path, const MeshLoadOptions& options = {});

// As above, and reports what was repaired or computed.
Mesh loadMesh(const std::filesystem::path& path, const MeshLoadOptions& options, MeshRepairReport& report);

}  // namespace strata
