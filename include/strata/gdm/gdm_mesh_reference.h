// The exact reference of a mesostructure on a curved base (issue 18, "Curved bases"), and the silhouette
// measures that compare a renderer's mask with it.
//
// Scene. The prism shell of CONVENTIONS §8 on `mesh` (buildPrismShell, strata/gdm/prism_shell.h, with the
// solid's H as its height). Prism p has corners i = 0, 1, 2 with base positions P_i, unit normals N_i
// (PrismShell::base, normal), the shell's thickness T, and tile coordinates t_i = tiling * uv_i of its mesh
// vertices. Its texture-space volume is the footprint triangle F = (t_0, t_1, t_2) times 0 <= z <= H
// (z = w H, the isotropic frame of §8), and the prism map takes a texture point (u, v, z) of it to
//     X(u, v, z) = sum_i b_i(u, v) (P_i + (z / H) T N_i),
// b the barycentrics of (u, v) in F: Wang et al. 2004, Sec. 3.2 (Fig. 3), on the shell the GL renderer
// draws. The map is linear in (u, v) for fixed z and in z for fixed (u, v): tops and bases are flat, fins
// are bilinear quads, and the solid's faces come out curved (quadratic).
//
// Visible geometry: the periodic solid (the SolidMesh's integer translates, §8) warped by each prism's map,
// each prism taking the part of the solid inside its own volume; i.e. the warped solid intersected with the
// shell's volume. Per pixel, the first point of the camera ray that lies in it:
//   - on a warped solid face that the ray enters the solid through (the face's outward normal against the
//     ray), or
//   - on the shell's boundary, where the ray enters the shell's volume at a point inside the solid: it hits
//     there, on the cut face, whose normal is the boundary's outward normal (§8's rule for the box, on any
//     shell). The boundary is every prism's top, every prism's base and the fins that only one prism has
//     (an open mesh's rim). Fins shared by two prisms are inside the shell and are not faces, except at a
//     seam: where the two prisms' tile coordinates do not continue across the fin (they differ by other
//     than a whole tile, e.g. a planar-mapped cap against a cylinder's side), the solid does not continue
//     either, and each prism's side of the fin is a boundary of its own. The base surface itself is not
//     solid (§8): a ray that meets no solid passes through it, into the mesh and out of it, and may enter
//     the shell again, from below through a base (the GL renderer never starts a ray at a base: it enters
//     prisms through their tops and fins only, so it shows that far side only where a far prism's inner fin
//     faces the ray; GdmMeshReferenceOptions::throughBase).
//   A face of a neighbouring tile's copy that lies in a prism's side, with its solid outside the prism, is
//   not kept (it belongs to the next prism): a ray that leaves a prism through the solid's section does not
//   hit there. (§8's flat reference, which traces the whole periodic solid, may: docs/gdm.md.)
// The inside test at a boundary point is the bake's winding-number test (gdm_bake.h) at the point's texture
// position, 1e-7 tile widths inside the prism. A ray walks its crossings in order; a face it has crossed is
// not reported again, so that faces at the same distance (both sides of a seam) are each met.
//
// How exact. The curved faces are cut into flat triangles, each solid triangle first clipped to each prism
// volume it crosses (in texture space, exactly: the clip planes are b_i = 0, z = 0 and z = H), then split at
// edge midpoints (in texture space) until the flat triangles lie within `chordTolerance` T of the curved
// surface. The map's second derivative along a texture-space edge e = (du, dv, dz) is
//     Q(e) = 2 (dz / H) T sum_i (grad b_i . (du, dv)) N_i,
// a linear interpolant on an edge is within |Q| / 8 of the quadratic and on a triangle within max |Q| / 6
// over its edges (the interpolation error of a quadratic is -1/2 sum_{i<j} b_i b_j Q(e_ij)); so an edge is
// split while |Q(e)| / 6 > chordTolerance T (and longer than 1e-5 tile widths). The decision is the edge's
// own (its two end points), so neighbouring triangles split a shared edge alike and the subdivision has no
// T-junctions. Boundary fins are cut the same way, and tops and bases are exact. The texture position of a
// hit is interpolated linearly on its flat triangle (within the same tolerance). docs/gdm.md gives the
// tolerance's measured effect.
//
// Outputs (GdmSceneImages, strata/gdm/gdm_trace.h), per pixel centre ray (pixelRayDirection), no
// antialiasing:
//   uvw: (u, v, w, 1) of the first hit: u, v its tile coordinates modulo 1, in [0, 1) (as renderGdmReference
//        writes them), w = z / H in [0, 1]; all 0 where there is no hit.
//   mask: 1 on a hit, else 0.
//   shadow: 1 where the hit is lit by the point light P (world units), else 0. Lit iff the hit's normal
//        (outward, as above) faces P (dot(n, P - X) > 0) and the segment from X (moved 1e-5 tile lengths,
//        T / H, along n) to P meets no warped solid inside the shell: no warped solid face, either way
//        round, and no boundary point where it enters the shell inside the solid. The blockers are the
//        whole shell's, any prism's, not only the hit's neighbourhood, and neither the base surface nor
//        anything outside the shell casts a shadow. (§8's flat reference takes the solid in the infinite
//        slab instead; on the flat quad the two differ only where the light ray leaves the unit box.)
//
// Prisms whose footprint has no area (|det| below 1e-12 of its bounding box's area) carry no texture and
// are left out (GdmMeshReferenceStats::skippedPrisms).
//
// Thread safety: a pure function of its arguments; rows run in parallel (strata::parallelFor), and the
// result does not depend on the number of threads.
#pragma once

#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gdm/solid_mesh.h"
#include "strata/image/image.h"
#include "strata/mesh/mesh.h"
#include "strata/scene/camera.h"

#include <glm/vec3.hpp>

#include <cstddef>

namespace strata {

struct GdmMeshReferenceOptions {
    // The largest distance allowed between a flat triangle and the curved face it stands for, as a fraction
    // of the shell's thickness T. (0, 1], default 1e-3 (1/125 of a voxel at 8 voxels over H).
    double chordTolerance = 1e-3;
    // true: the exact answer above. false: a camera ray ends, as a miss, where it enters the shell through a
    // base (from inside the mesh): what the GL renderer draws, which enters prisms through their tops and
    // fins only; for measuring that difference apart from the others. Shadow rays keep the exact rule.
    bool throughBase = true;
};

// What the reference built, for tests and docs.
struct GdmMeshReferenceStats {
    std::size_t prisms = 0;            // prisms of the shell
    std::size_t skippedPrisms = 0;     // left out: footprint without area
    std::size_t rimFins = 0;           // fins of one prism only: the shell's rim
    std::size_t seamFins = 0;          // fins between prisms whose texture positions do not continue (one per
                                       // prism side)
    std::size_t clippedTriangles = 0;  // solid triangles clipped into prisms (fan triangles of each clip)
    std::size_t solidTriangles = 0;    // flat triangles of the warped solid, after subdivision
    std::size_t boundaryTriangles = 0;  // flat triangles of the shell's boundary (tops, bases, open fins)
    std::size_t exitFaceCrossings = 0;  // camera rays that met a solid face from inside before any hit
                                        // (rays through a crack, or float rounding at an edge): skipped
    std::size_t hitsFromBelow = 0;      // hits on rays that entered the shell through a base, from inside the
                                        // mesh
};

// The exact reference (above). Throws Error(InvalidInput) for a camera validateCamera refuses, a picture
// size validateGdmPicture refuses, a solid height that is not finite and > 0, the solid mesh's errors that
// renderGdmReference throws, the mesh's errors that buildPrismShell throws (its height is the solid's), and
// a chordTolerance outside (0, 1]; Error(Runtime) if Embree fails.
GdmSceneImages renderGdmMeshReference(const SolidMesh& solid, const Mesh& mesh,
                                      const PrismShellOptions& shell, const Camera& camera, glm::dvec3 light,
                                      int width, int height, const GdmMeshReferenceOptions& options = {},
                                      GdmMeshReferenceStats* stats = nullptr);

// Silhouette measures between two masks of one picture (1 channel each, same size; a pixel is in a mask
// where its value is > 0.5).
//
// silhouetteIoU: |A and B| / |A or B|, in [0, 1]; 1 when both masks are empty.
// silhouetteHausdorff: the symmetric Hausdorff distance, in pixels, between the masks' boundaries: a
// boundary pixel is a mask pixel with at least one of its 4 neighbours outside the mask (a pixel outside
// the picture counts as outside), and the distance between two pixels is the Euclidean distance between
// their centres. max(max_{a in dA} min_{b in dB} |a - b|, max_{b in dB} min_{a in dA} |a - b|): 0 when
// both masks are empty, +infinity when exactly one is.
// Both throw Error(InvalidInput) for masks whose sizes differ or that do not have 1 channel.
double silhouetteIoU(const Image& maskA, const Image& maskB);
double silhouetteHausdorff(const Image& maskA, const Image& maskB);

}  // namespace strata
