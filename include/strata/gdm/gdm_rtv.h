// The diffuse radiance transfer volume (RTV) of a GDM (Wang et al. 2004, "Generalized Displacement Maps",
// Sec. 3.2 "Global Illumination" and Sec. 4.1): at every voxel of the GDM grid, the 16 spherical-harmonic
// coefficients per RGB channel of the linear map from the meso-scale incident radiance (SH in the tangent
// frame) to the outgoing radiance of a Lambertian surface there, with the mesostructure's own shadowing and
// (bounces >= 1) interreflection. The paper stores, per voxel, the transfer of Sloan et al.'s PRT, computed
// "for each voxel in the volume" from the GDM's visibility and compressed with the same SVD as the GDM; the
// renderer shades a hit by the dot product of the transfer at the hit's texture point with the local SH
// lighting. This is that, for a diffuse surface (a transfer vector per channel, not a matrix).
//
// Frame: the tile's isotropic frame (u, v, z = w H) of CONVENTIONS §8; SH in it after CONVENTIONS §9
// (spherical_harmonics.h: polar angle from +w, azimuth from +u towards +v). On the flat quad of the GDM
// verification scene the frame is world space, so the lighting SH is the environment's own (Environment::sh).
//
// Definitions, at a voxel centre p (gdmVoxelCentre) that lies outside the solid (signed distance D(p) >= 0):
//   - Normal n(p): the normalised gradient of the signed distance volume D (bakeGdmDistance), central
//     differences between the neighbouring voxel centres (wrapping in u and v; one-sided at the bottom and
//     top layers). A zero gradient (the distance clamped at kGdmDistanceReach far from the solid) gives
//     n = +w.
//   - Surface albedo rho_s(p): the caller's GdmAlbedo (linear RGB) at the surface point the voxel stands for,
//     s(p) = p - D(p) n(p) (wrapped in u, v; w clamped to [0, 1]), not at p itself: a texture's albedo off
//     the surface is whatever its volume holds there (on the weave, the albedo at the voxel centres instead
//     of the surface raised the relative RMSE from about 9% to 21%).
//   - Visibility V(p, w) = 1 iff the GDM's raw value at p in direction w is an exit (kGdmMiss) and w points
//     up (w_z > 0): the ray leaves the slab through its top without a hit. Rays leaving through the bottom
//     are blocked, as in pathTraceGdm (the macro surface lies below; the bi-scale split).
//   - The transfer is stored WITHOUT the albedo of the shaded point itself (the shader multiplies by the
//     albedo at the hit, which a voxel grid cannot resolve where the albedo has sharp edges); the albedo of
//     every interreflecting point is in it. Direct transfer:
//       T0_k(p) = 1 / pi * sum over the GDM's Ntheta x Nphi direction samples w_ts of
//                 Y_k(w_ts) V(p, w_ts) max(n . w_ts, 0) dOmega_t,
//     with dOmega_t = 2 pi / Nphi (cos theta0 - cos theta1) the exact solid angle of the sample's cell
//     theta in [t pi / Ntheta, (t + 1) pi / Ntheta] (the same for every channel).
//   - Interreflection (Jacobi iteration, each pass reads only the previous one):
//       T(b+1)_k(p) = T0_k(p) + 1 / pi * sum over the direction samples whose raw value d is finite and > 0
//                     (the ray hits the solid) of (rho_s Tb_k)(q) max(n . w_ts, 0) dOmega_t,
//     at q = p + max(d - kGdmRtvBackOff H / Nz, 0) w_ts wrapped in u and v (backed off towards p, off the
//     solid), (rho_s Tb) looked up as gdmRtvTransferAt does (trilinear, inside voxels left out). With
//     `bounces` = B the result is TB. Rays leaving through the bottom add nothing.
//   - Voxels inside the solid (D < 0) hold 0.
// Shading (gdmRtvRadiance, shadeGdmSceneRtv): the radiance leaving a surface point x of albedo rho(x) is
// rho(x) sum_k T_k(x) L_k per channel, with L the incident radiance's SH in the tangent frame and T(x)
// trilinear between the voxel centres around x (wrapping in u, v, clamped in w, §8), the corners inside the
// solid left out and the rest's weights renormalised (they hold 0, not the surface's transfer).
// All 8 corners inside (a surface point in a cell whose corners all lie inside the solid: a feature thinner
// than a voxel): the nearest outside voxel centre of the 4 x 4 x 4 voxels around the cell instead; none: 0.
//
// Accuracy (measured against pathTraceGdm on the same scene, tests/gdm/test_gdm_rtv.cpp and
// bench/bench_gdm_rtv.cpp): for band-limited lighting L = sum_k L_k Y_k the SH projection of the transfer
// loses nothing (the radiance is sum_k L_k T_k exactly), so the error comes from the 16 x 32 direction
// sampling of V and of the cosine, the voxel grid (T at voxel centres up to half a voxel off the surface,
// interpolated: a voxel's visibility is not the surface's, it sees a little more sky), and the normals of
// the distance volume. Relative RMSE over the surface hits with 1 bounce, overcast sky, 45 degree view:
// the weave 8.0% at 32 x 32 x 8 voxels (64 x 64 pixels), 3.7% at 64 x 64 x 16 (256 x 256); the chain, whose
// links are a few voxels thick, 12.0% at 64 x 64 x 16, falling with the voxel grid (16.6%, 12.1%, 10.8% at
// 32, 64, 96 voxels across, 96 x 96 pixels).
//
// Thread safety: pure functions of their arguments; the bake runs its voxel rows in parallel
// (strata::parallelFor), so the albedo callable must be safe to call from several threads at once.
#pragma once

#include "strata/environment/spherical_harmonics.h"
#include "strata/gdm/gdm.h"
#include "strata/gdm/gdm_path_trace.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/image/image.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace strata {

// The back-off of a bounce's lookup point, in voxels along w (H / Nz): q = p + (d - kGdmRtvBackOff H / Nz) w.
inline constexpr double kGdmRtvBackOff = 0.5;

struct GdmRtvOptions {
    // Interreflections, [0, kMaxBounces]: 0 = direct lighting with the mesostructure's shadowing; each more
    // adds one interreflection. Default 1.
    int bounces = 1;
    static constexpr int kMaxBounces = 8;
};

// A diffuse RTV on a GDM's voxel grid.
struct GdmRtv {
    GdmDims dims;          // the GDM's (only nx, ny, nz address the volume)
    double height = 0.25;  // H, tile widths
    // kShCount x 3 floats per voxel, voxels in §8 order (x fastest), then coefficient k, then channel c:
    // transfer[(voxel * kShCount + k) * 3 + c]: radiance per unit SH lighting coefficient, for albedo 1 at
    // the shaded point (above).
    std::vector<float> transfer;
    // The signed distance per voxel (bakeGdmDistance), kept for the lookup's inside test (< 0: inside).
    std::vector<float> distance;

    std::size_t voxelIndex(int i, int j, int k) const {
        return std::size_t(i) +
               std::size_t(dims.nx) * (std::size_t(j) + std::size_t(dims.ny) * std::size_t(k));
    }
    std::size_t bytes() const { return (transfer.size() + distance.size()) * sizeof(float); }
};

// Bakes the RTV of `gdm` (raw values, bakeGdm) with the signed distance volume `distance` of the same solid
// on the same voxel grid (bakeGdmDistance(solid, gdm.dims)) and the surface albedo `albedo` (linear RGB at a
// texture point). Throws Error(InvalidInput) for a GDM whose value count does not match its dims, a
// distance volume of the wrong size, an empty albedo callable, or bounces outside [0, kMaxBounces] (the
// message names the value).
GdmRtv bakeGdmRtv(const Gdm& gdm, const std::vector<float>& distance, const GdmAlbedo& albedo,
                  const GdmRtvOptions& options = {});

// The transfer at a point (u, v, z) of the isotropic frame (z = w H; u, v wrap, w is clamped to the voxel
// centres), trilinear with the inside corners left out (see above).
ShColor gdmRtvTransferAt(const GdmRtv& rtv, const glm::dvec3& point);

// Radiance (linear RGB) leaving a surface point of albedo 1 lit by `lighting` (SH of the incident radiance
// in the tangent frame): sum_k T_k(point) * lighting_k per channel; times the point's albedo for its
// radiance.
glm::dvec3 gdmRtvRadiance(const GdmRtv& rtv, const glm::dvec3& point, const ShColor& lighting);

// The §8 scene shaded with the RTV: for every pixel where `hits` has a hit (mask 1), the radiance
// albedo(u, v, w) * gdmRtvRadiance(rtv, (u, v, w H), lighting) at its hit; 0 elsewhere. 3 channels, linear
// RGB, the size of hits.uvw. Pixels run in parallel. Throws Error(InvalidInput) for an empty albedo.
Image shadeGdmSceneRtv(const GdmSceneImages& hits, const GdmRtv& rtv, const ShColor& lighting,
                       const GdmAlbedo& albedo);

// The hits of `hits` that lie on a surface of the solid: its mask without the pixels whose hit lies on a
// side of the scene's box (u or v within 1e-6 of 0 or 1: a cut face, where the ray enters the box inside
// the periodic solid). A cut face has no counterpart on a mapped surface (there the neighbouring tiles go
// on); pathTraceGdm lights it only through the solid's gaps (its rays start inside the solid, nearly
// black), while the RTV lookup there, across the wrap, reads the open space's transfer. 1 channel.
Image gdmSurfaceHitMask(const GdmSceneImages& hits);

// The RTV's SVD (Sec. 4.1: the paper compresses the RTV "in the same manner" as the GDM, by SVD). The
// matrix A has one row per voxel (x, y, z in §8 order, inside voxels included as zero rows) and one column
// per coefficient and channel (k, c), column k * 3 + c: kShCount * 3 = 48 columns, the RTV's own layout.
// A ~ W E with W = U S (voxelCount x rank, the singular values folded in) and E = V^T (rank x 48), the best
// rank-`rank` approximation in the Frobenius norm. Rows (x, y, z) are the natural choice here: the
// transfer of one voxel is one short vector, and a rank-r RTV costs r floats per voxel plus 48 r floats
// (the paper's (x, y, phi) x (theta, z) layout exists for the GDM's direction axes, which the RTV has not).
// Decomposition: the 48 x 48 Gram matrix A^T A in double, diagonalised with Eigen's SelfAdjointEigenSolver.
struct GdmRtvSvd {
    GdmDims dims;          // the RTV's
    double height = 0.25;  // H
    int rank = 0;
    std::vector<float> weights;          // voxelCount x rank, row-major: W = U S
    std::vector<float> basis;            // rank x 48, row-major: E = V^T
    std::vector<double> singularValues;  // all 48, descending (>= 0)
    std::vector<float> distance;         // the RTV's signed distance volume, for the lookup

    // The rank-`rank` RTV, W E (same dims, height and distance).
    GdmRtv reconstruct() const;
    // sqrt(sum over i >= rank of s_i^2 / sum of s_i^2): the relative Frobenius error of W E against A
    // (0 when A is 0).
    double relativeError() const;
    std::size_t bytes() const { return (weights.size() + basis.size() + distance.size()) * sizeof(float); }
};

// Throws Error(InvalidInput) for a rank outside [1, 48] or an RTV whose transfer size does not match its
// dims.
GdmRtvSvd compressGdmRtv(const GdmRtv& rtv, int rank);

// Relative RMSE of `test` against `reference` (3-channel radiance images of the same size) over the pixels
// where both masks are 1: sqrt(sum |a - b|^2 / sum |b|^2), the sums over those pixels and the 3 channels.
// Throws Error(InvalidInput) when the sizes differ; 0 when the reference is 0 there.
double gdmRelativeRmse(const Image& test, const Image& testMask, const Image& reference,
                       const Image& referenceMask);

}  // namespace strata
