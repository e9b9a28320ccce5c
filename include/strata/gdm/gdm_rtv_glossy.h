// The view-dependent (glossy) radiance transfer volume of a GDM (Wang et al. 2004, "Generalized
// Displacement Maps", Sec. 3.2 "Global Illumination" and Sec. 4.1): the paper's RTV "is expressed as a set
// of 5D functions that correspond to spherical harmonic coefficients f_i(x, y, z, theta, phi)", (theta, phi)
// the viewing direction, reorganised "into matrices where the rows are indexed by x, y, z and columns are
// indexed by theta, phi" and "compressed by SVD". This is that for a glossy term added to the diffuse RTV
// (gdm_rtv.h), whose definitions it reuses: the frame, the voxel normals n(p) (gradient of the signed
// distance volume), the visibility V(p, w) (raw GDM value kGdmMiss and w_z > 0), the exact cell solid
// angles dOmega_t, inside voxels holding 0 and the trilinear lookup leaving out inside corners.
//
// Model: a white normalised Phong lobe, per unit specular coefficient (the shader multiplies by it):
//   f_s(w, w_o) = (s + 2) / (2 pi) max(w . r, 0)^s,  r = 2 (n . w_o) n - w_o (the mirror of w_o about n),
// w_o the unit view direction from the surface towards the eye (tangent frame), s the shininess. (s + 2) /
// (2 pi) makes the lobe's directional albedo, integral of f_s max(n . w, 0) dw, exactly 1 at normal view and
// less at oblique views (the lobe is cut by the horizon). Outgoing glossy radiance, direct environment light
// with the mesostructure's shadowing only (interreflected light in the glossy term is left out; the
// diffuse RTV carries the interreflection of the diffuse term):
//   L_g(p, w_o) = specular * sum_k G_k(p, w_o) L_k,  G_k(p, w_o) = integral of Y_k V(p, w) f_s(w, w_o)
//   max(n . w, 0) dw.
// Computed the Sloan et al. 2002 way, G = M b:
//   - M_kj(p) = sum over the GDM's Ntheta x Nphi direction samples w_ts of Y_k Y_j V(p, w_ts) dOmega_t
//     (16 x 16, symmetric): the shadowed transfer matrix.
//   - b_j(n, w_o) = the SH projection of the unshadowed lobe g(w) = f_s(w, w_o) max(n . w, 0) (bands 0-3).
//     g depends on n and w_o only through the angle a between them and a rotation: b is tabulated once per
//     bake in the normal's frame (n = +z, w_o in the x-z plane) at kGdmGlossyLobeAngles angles a in [0, pi]
//     (a 64-node Gauss-Legendre rule in cos over the upper hemisphere times 256 azimuths: the cosine's kink
//     at the horizon lies on the rule's edge), interpolated linearly in a, turned about n to w_o's azimuth
//     (exact: cos(m psi), sin(m psi)) and rotated into the tangent frame (ShRotation, exact). The table's
//     linear interpolation costs about 1e-3 relative on G at s = 8 (against M times gdmPhongLobeSh's
//     direct projection); the quadrature itself matches a brute-force projection to 1e-3 for s <= 32.
//   The SH truncation: M b = integral of Y_k V g~ with g~ the band-3 projection of the lobe, not the lobe
//   itself. With nothing occluding, band-limited lighting and a lobe that lies above the horizon this loses
//   nothing (sum_k L_k G_k = integral of L g~ = integral of L g). V cuts the band-limited lobe, whose tail
//   g~ - g leaks across the shadowing edges (and the horizon): the error is the integral of L V (g~ - g). A
//   band-3 lobe is broad: s around 8 or below is what it can hold; sharper lobes blur. Measured on a flat
//   slab under a constant sky (s = 8): -5.5%, +2.9%, -4.6% at views 6, 39 and 84 degrees from the normal.
//   GdmGlossyMethod::DirectSum computes G_k = sum over the direction samples of Y_k V f_s max(n . w, 0)
//   dOmega_t instead (no truncation: +1.4%, +0.1%, +1.0% there, the 16 x 32 rule's error on the lobe; a
//   lobe evaluation per visible direction and view, 10 to 20 times the bake's cost). On the weave both
//   measure the same error against the path tracer (the voxel grid dominates it: the lobe turns with twice
//   the normal's error).
// View directions: the upper half of the GDM's own direction grid, rows t < floor(Ntheta / 2) (theta centres
// (t + .5) pi / Ntheta < pi / 2) times the Nphi azimuths: 8 x 32 = 256 views at the default 16 x 32.
// Lookup: trilinear in the voxels as gdmRtvTransferAt, bilinear in (theta, phi) between the view centres
// (phi wrapping, theta clamped to the first and last row's centres: views beyond the last row, towards the
// horizon, read the last row). Midway between view centres the bilinear lookup is off by up to 2.8% of G on
// a flat slab at s = 8 (the 11.25 degree view steps move r by twice that, about the lobe's width).
//
// Accuracy against pathTraceGdm's glossy term (the weave, overcast sky, s = 8, 45 degree view;
// tests/gdm/test_gdm_rtv_glossy.cpp and bench/bench_gdm_rtv_glossy.cpp): relative RMSE over the surface hits
// 33%, 26%, 19% at 16, 32, 64 voxels across (diffuse with 0 bounces + glossy with specular 0.5: 24%, 18%,
// 13%); rank 4 changes it by under 1%. The voxel grid dominates (normals from the distance volume, and the
// visibility of voxel centres up to half a voxel off the surface); the glossy term is more sensitive to both
// than the diffuse one.
//
// Storage (the paper's layout): per coefficient k (16) a matrix with one row per voxel (x, y, z in §8
// order, inside voxels as zero rows) and one column per view (t * Nphi + s); compressed per coefficient by
// SVD, A_k ~ W_k E_k, W_k = U S (voxels x rank), E_k = V^T (rank x views), from the views x views Gram matrix
// in double (Eigen's SelfAdjointEigenSolver), rank 4 by default as the paper.
//
// Thread safety: pure functions of their arguments; the bake and the compression run in parallel
// (strata::parallelFor).
#pragma once

#include "strata/environment/spherical_harmonics.h"
#include "strata/gdm/gdm.h"
#include "strata/gdm/gdm_rtv.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/image/image.h"
#include "strata/scene/camera.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace strata {

// Angles a (between n and w_o) of the lobe table, uniformly over [0, pi].
inline constexpr int kGdmGlossyLobeAngles = 513;

// How the bake computes G (see the SH truncation above).
enum class GdmGlossyMethod {
    ShadowedMatrix,  // G = M b, Sloan et al. 2002 (the default)
    DirectSum,       // G_k = sum over the direction samples of Y_k V f_s max(n . w, 0) dOmega_t
};

struct GdmGlossyOptions {
    GdmGlossyMethod method = GdmGlossyMethod::ShadowedMatrix;
    double shininess = 8.0;  // Phong exponent s, [0, kMaxShininess]. Default 8 (see the SH truncation above).
    static constexpr double kMaxShininess = 64.0;
};

// The uncompressed glossy RTV.
struct GdmGlossyRtv {
    GdmDims dims;            // the GDM's: nx, ny, nz address the voxels, ntheta, nphi the views
    double height = 0.25;    // H, tile widths
    double shininess = 8.0;  // s
    // G per unit specular, coefficient-major: transfer[(k * voxelCount + voxel) * viewCount + view].
    std::vector<float> transfer;
    std::vector<float> distance;  // the signed distance per voxel (the lookup's inside test)

    int viewRows() const { return dims.ntheta / 2; }
    std::size_t viewCount() const { return std::size_t(viewRows()) * std::size_t(dims.nphi); }
    std::size_t bytes() const { return (transfer.size() + distance.size()) * sizeof(float); }
};

// Unit view direction of view (t, s): gdmDirection(dims, t, s), t < dims.ntheta / 2.
glm::dvec3 gdmGlossyView(const GdmDims& dims, int t, int s);

// Bakes the glossy RTV of `gdm` (raw values) with the signed distance volume `distance` of the same solid
// on the same voxel grid (bakeGdmDistance). Throws Error(InvalidInput) for a GDM whose value count does
// not match its dims, Ntheta < 2 (no view row), a distance volume of the wrong size, or a shininess outside
// [0, kMaxShininess] (the message names the value).
GdmGlossyRtv bakeGdmGlossyRtv(const Gdm& gdm, const std::vector<float>& distance,
                              const GdmGlossyOptions& options = {});

// b(n, w_o): the SH projection of the unshadowed lobe f_s(w, w_o) max(n . w, 0) (per unit specular) for a
// unit normal n and view w_o, by direct quadrature (the table's rule, without the table). Throws as the bake
// for the shininess.
ShVector gdmPhongLobeSh(double shininess, const glm::dvec3& normal, const glm::dvec3& view);

// The shadowed transfer matrix M(p) of voxel (i, j, k) (row-major 16 x 16, M[k * 16 + j]): the sum over
// the direction samples of Y_k Y_j V dOmega. Zero inside the solid. Throws as the bake for a bad GDM or
// voxel index.
std::vector<double> gdmShadowedTransferMatrix(const Gdm& gdm, int i, int j, int k);

// G(point, view) per unit specular: trilinear in the voxels (inside corners left out), bilinear in the view
// (above). `view` is the unit direction from the surface towards the eye in the tangent frame (normalised
// here; its w component clamped to >= 0 by the view-row clamp).
ShVector gdmGlossyTransferAt(const GdmGlossyRtv& rtv, const glm::dvec3& point, const glm::dvec3& view);

// Glossy radiance leaving `point` towards `view` for lighting `lighting` (SH of the incident radiance in
// the tangent frame) and specular coefficient `specular`: specular * sum_k G_k L_k per channel (white).
glm::dvec3 gdmGlossyRadiance(const GdmGlossyRtv& rtv, const glm::dvec3& point, const glm::dvec3& view,
                             const ShColor& lighting, double specular);

// The compressed glossy RTV (see Storage above).
struct GdmGlossyRtvSvd {
    GdmDims dims;
    double height = 0.25;
    double shininess = 8.0;
    int rank = 0;
    std::size_t viewCount = 0;
    // W_k: weights[(k * voxelCount + voxel) * rank + r].
    std::vector<float> weights;
    // E_k: basis[(k * rank + r) * viewCount + view].
    std::vector<float> basis;
    // All viewCount singular values of each A_k, descending: singularValues[k * viewCount + n].
    std::vector<double> singularValues;
    std::vector<float> distance;

    // The rank-`rank` glossy RTV, W_k E_k per coefficient.
    GdmGlossyRtv reconstruct() const;
    // sqrt(sum_k sum_{n >= rank} s_kn^2 / sum_k sum_n s_kn^2): the relative Frobenius error of the whole
    // compressed RTV (all 16 matrices) against the uncompressed one; 0 when it is 0.
    double relativeError() const;
    std::size_t bytes() const { return (weights.size() + basis.size() + distance.size()) * sizeof(float); }
};

// Throws Error(InvalidInput) for a rank outside [1, viewCount] or an RTV whose sizes do not match its dims.
GdmGlossyRtvSvd compressGdmGlossyRtv(const GdmGlossyRtv& rtv, int rank = 4);

// compressGdmGlossyRtv(bakeGdmGlossyRtv(gdm, distance, options), rank), equal to it float for float, without
// the uncompressed RTV (16 x voxels x views floats: 1 GiB at 64 x 64 x 16 voxels x 256 views): the voxels
// are baked in chunks of 2048 (all 16 coefficients: 32 MiB at 256 views) twice, once for the Gram matrices
// (16 x views x views doubles) and once for the weights, so it costs two bakes. Throws as the two.
GdmGlossyRtvSvd bakeCompressedGdmGlossyRtv(const Gdm& gdm, const std::vector<float>& distance,
                                           const GdmGlossyOptions& options = {}, int rank = 4);

// The lookups of the compressed form, directly from W and E (what a shader does; equal to the lookups of
// reconstruct() up to float rounding).
ShVector gdmGlossyTransferAt(const GdmGlossyRtvSvd& svd, const glm::dvec3& point, const glm::dvec3& view);
glm::dvec3 gdmGlossyRadiance(const GdmGlossyRtvSvd& svd, const glm::dvec3& point, const glm::dvec3& view,
                             const ShColor& lighting, double specular);

// The §8 scene's glossy term: for every pixel where `hits` (rendered with `camera` at the hits' size) has a
// hit, gdmGlossyRadiance at its hit (u, v, w H) towards the eye (-pixelRayDirection); 0 elsewhere. Add
// shadeGdmSceneRtv's diffuse term for the whole radiance. 3 channels. Pixels run in parallel. Throws
// Error(InvalidInput) for a specular that is not finite and >= 0.
Image shadeGdmSceneGlossy(const GdmSceneImages& hits, const GdmGlossyRtv& rtv, const Camera& camera,
                          const ShColor& lighting, double specular);
Image shadeGdmSceneGlossy(const GdmSceneImages& hits, const GdmGlossyRtvSvd& svd, const Camera& camera,
                          const ShColor& lighting, double specular);

}  // namespace strata
