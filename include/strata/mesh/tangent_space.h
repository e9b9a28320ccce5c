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

// MikkTSpace tangents (Mikkelsen, "Simulation of Wrinkled Surfaces Revisited", 2008): the algorithm of the
// reference mikktspace.c with its default settings (as Blender's calc_tangents, glTF and the bakers use it),
// from positions, uvs and the existing unit normals (checked), taken as given:
//  - corners whose vertices have identical position, normal and uv (float ==) are one vertex ("welded");
//  - a triangle with two corners at the same position is degenerate: its corners copy the tangent of the
//    first good triangle's corner at the same welded vertex;
//  - per good triangle, in float: the uv orientation (signed uv area > 0) and the unit dP/du; a triangle
//    whose uv area, |dP/du| or |dP/dv| is zero (|x| <= FLT_MIN) contributes nothing and joins ("groups
//    with anything") the first tangent group that reaches it across an edge, taking its orientation;
//  - groups: around each welded vertex, the triangles connected across shared edges (of welded vertices)
//    with the same uv orientation. A group's tangent is the normalised sum over its corners of dP/du
//    projected into the plane of the normal and normalised, weighted by the corner's angle measured in
//    that plane (exact acos, where Blender uses a fast approximation: < 1e-3 degree apart);
//  - w = +1 for an orientation-preserving group, else -1 (not the sign of a summed bitangent).
// Mesh has one tangent per vertex: a vertex whose corners fall in several groups (a mirror seam, a uv
// orientation flip, fans that share only the vertex) is split, one copy per group (the first keeps its
// index), so the vertex count can grow. A corner no group reaches (a triangle with zero uv area and no good
// neighbour: the reference leaves (1, 0, 0), -1 there) takes the vertex's tangent from its other corners;
// a vertex with none, or whose sum vanishes, is repaired with a unit vector orthogonal to N (the cross
// product of N with the coordinate axis least aligned with it) and w = +1. Returns how many vertices were
// repaired so. tests/mesh/test_mikktspace_reference.cpp compares with Blender's (docs/meshes.md).
std::size_t computeTangents(Mesh& mesh);

}  // namespace strata
