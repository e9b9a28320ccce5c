// The macro-scale transfer of bi-scale precomputed radiance transfer (Sloan, Liu, Shum, Snyder 2003), as the
// GDM paper uses it for global illumination (Wang et al. 2004, Sec. 3.2 "Global Illumination"): per mesh
// vertex, a 16 x 16 matrix that carries the distant lighting, as SH coefficients in world space
// (strata/environment/spherical_harmonics.h), to the meso-scale lighting at that vertex, as SH coefficients
// in the vertex's own tangent frame (T, B, N): the base mesh's own shadowing and the rotation in one matrix.
//
//   local_i = sum_j M_ij world_j,   M_ij = integral over the sphere of Y_i(R w) V(w) Y_j(w) dw,
//
// with w a world direction, R the rotation from world to the vertex's frame (rows T, B, N, the mesh's unit
// normal and its tangent made orthogonal to it), and V(w) = 1 where a ray from just above the shell at the
// vertex (P + T N, lifted by `offset` along N) in direction w leaves the mesh without meeting one of its
// triangles (Embree), else 0; directions below the vertex's tangent plane count as visible unless
// options.lowerHemisphere (see there). The integral runs over shQuadrature()'s 2560 directions, exact for
// products of band-3 functions, so M = D(R) (I - sum over the occluded directions of w Y Y^T), D(R) the SH
// rotation (ShRotation). Without occlusion (options.occlusion = false) V = 1 and M = D(R).
#pragma once

#include "strata/environment/spherical_harmonics.h"
#include "strata/mesh/mesh.h"

#include <cstddef>
#include <vector>

namespace strata {

struct MacroTransferOptions {
    // T, world units, >= 0: the rays start at the top of the prism shell (the mesostructure's highest
    // level), where the meso-scale lighting is gathered. Default 0: at the base surface.
    double shellThickness = 0.0;
    // The rays' origins are lifted this far along the normal, times the mesh's bounding-box diagonal, off
    // the surface they start on. > 0; default 1e-4.
    double offset = 1e-4;
    // The mesh shadows itself (true, default) or is transparent (false: M is the pure rotation).
    bool occlusion = true;
    // Whether directions below the vertex's tangent plane (w . N <= 0) are tested too. Default false: they
    // are left visible, because the meso-scale transfer already blocks them (the RTV, like pathTraceGdm,
    // blocks every ray that leaves the mesostructure through its base), and masking them here as well would,
    // through the band-3 projection of the hemisphere's sharp edge, ring into the upper hemisphere: on a flat
    // plane the lighting would no longer be the environment's (at a corner of the quad M_00 would be 7/8).
    // With it false, M is the pure rotation wherever the mesh is nowhere above a vertex's tangent plane.
    bool lowerHemisphere = false;
};

// Per vertex of the mesh, in its order: 256 floats, M row-major (M[16 i + j]).
struct MacroTransfer {
    std::vector<float> matrices;
    std::size_t vertexCount() const { return matrices.size() / (kShCount * kShCount); }
    const float* matrix(std::size_t vertex) const { return matrices.data() + vertex * kShCount * kShCount; }
};

// Bakes the transfer for every vertex of `mesh` (parallel over vertices). Throws Error(InvalidInput) naming
// the mesh for an empty mesh, indices not in threes or out of range, a non-finite position or normal, or
// options out of range, and Error(Runtime) for an Embree failure.
MacroTransfer bakeMacroTransfer(const Mesh& mesh, const MacroTransferOptions& options = {});

// local = M world, per channel: the meso-scale lighting at a vertex (linear RGB SH coefficients in its
// tangent frame) from the distant lighting (in world space).
ShColor applyMacroTransfer(const float* matrix, const ShColor& world);

}  // namespace strata
