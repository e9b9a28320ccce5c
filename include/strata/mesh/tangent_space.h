// Vertex normals and tangent frames for meshes that do not bring their own (files; see mesh_loader.h).
// The convention is mesh.h's: T along increasing u, B = w * cross(N, T) along increasing v, w = +-1.
#pragma once

#include "strata/mesh/mesh.h"

#include <cstddef>

namespace strata {

// Area-weighted smooth normals: each vertex gets the normalised sum of cross(p1 - p0, p2 - p0) (twice the
// area times the unit face normal) over the triangles around its position. Vertices with bit-identical
// positions are treated as one, so uv seams do not show as shading seams. A position whose sum is zero
// (no triangle with area, or faces that cancel) gets +z; returns how many vertices got that repair.
std::size_t computeSmoothNormals(Mesh& mesh);

// MikkTSpace-equivalent tangents on the mesh's shared vertices (Mikkelsen, "Simulation of Wrinkled
// Surfaces Revisited", 2008, as implemented by mikktspace.c), computed from positions, uvs and the
// existing unit normals (checked):
//  - per triangle, the tangent and bitangent (dP/du, dP/dv) from its positions and uvs;
//  - on each vertex, the sum over its triangles of those directions projected into the plane of the
//    vertex normal and normalised, weighted by the triangle's corner angle at the vertex;
//  - T = the tangent sum, Gram-Schmidt orthogonalised against N and normalised;
//  - w = +1 if dot(cross(N, T), bitangent sum) >= 0, else -1.
// Triangles with zero uv area (see mesh_repair.h) contribute nothing. A vertex with no usable tangent (all
// its triangles have zero uv area, or the sum vanishes) is repaired with a unit vector orthogonal to N
// (the cross product of N with the coordinate axis least aligned with it) and w = +1. Returns how many
// vertices were repaired so.
std::size_t computeTangents(Mesh& mesh);

}  // namespace strata
