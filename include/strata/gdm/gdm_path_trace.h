// A CPU path tracer of the GDM verification scene (CONVENTIONS §8) lit by a distant environment: the
// reference for the paper's global illumination (Wang et al. 2004, "Generalized Displacement Maps", Sec. 3.2
// "Global Illumination" and Sec. 4.1: the radiance transfer volume accounts for "the shadowing and
// interreflection of the meso-scale lighting within the mesostructure volume").
//
// Scene and camera: those of renderGdmReference (gdm_trace.h). One camera ray per pixel, through its centre
// (no antialiasing), and the same first hit: the first face of the periodic solid inside the shell box
// [0, 1]^2 x [0, H], or the cut face where the ray enters the box inside the solid. The mask is therefore
// renderGdmReference's mask, pixel for pixel.
//
// Light transport (what the meso-scale transfer contains, and nothing else):
//   - Surfaces: the faces of the periodic solid (every integer translate of the mesh in u, v) inside the
//     infinite slab 0 <= z <= H, Lambertian (BRDF albedo / pi), flat-shaded with the face's outward normal.
//     Albedo: the caller's callable at the hit's texture point (u mod 1, v mod 1, w = z / H), linear RGB in
//     [0, 1] (not checked; a value > 1 adds energy).
//   - The environment: radiance L(direction) arriving from infinitely far away, seen by a ray that leaves
//     the slab through its top z = H (upwards) without meeting the solid. It is not drawn where the camera
//     ray misses (radiance 0 there, mask 0).
//   - Occluders: the periodic solid within the slab, as §8's shadow (the bake's wrapped ray walk). A ray
//     that leaves the slab through its bottom z = 0 is blocked (it contributes nothing): the base plane is
//     not a surface, but below it lies the macro surface, whose own occlusion and interreflection are the
//     macro-scale transfer's job (the paper's bi-scale split, after Sloan et al. 2003), so the meso-scale
//     transfer must not count light from below the base. A ray that runs kGdmBakeMaxTravel tile widths
//     inside the slab without a hit (within about H / kGdmBakeMaxTravel of horizontal) counts as leaving
//     through the side it is heading to: the top (environment) when it rises, the bottom (blocked) when it
//     falls; a perfectly horizontal one is blocked.
//   - A cut face lies inside the periodic solid (the solid goes on beyond the box): its rays start inside
//     the solid. A ray whose first face it meets from behind (leaving the solid) is blocked, so a cut face
//     is lit only through the solid's own gaps (as §8's shadow treats it).
//
// Estimator: per pixel, samplesPerPixel independent paths from the first hit. At each vertex a direction is
// drawn cosine-weighted around the face normal (pdf cos / pi, so a path's weight is the product of the
// albedos along it); a path that escapes to the environment after k interreflections adds
// albedo(x0) ... albedo(xk) L(direction). At most `bounces` interreflections: with 0, the radiance is
// albedo / pi times the irradiance from the unoccluded environment (direct lighting with the
// mesostructure's own shadowing); each further bounce adds the paths with one more interreflection. There
// is no next-event estimation (an environment given as a callable cannot be importance-sampled) and no
// Russian roulette. The outgoing radiance is the same in every direction (Lambertian), so it is the pixel's
// radiance; for a constant environment L and a surface that sees only sky the estimator is exactly
// albedo L, with zero variance.
//
// Optional glossy term (specular > 0; the reference of the glossy RTV, gdm_rtv_glossy.h): at the first
// hit only, a white normalised Phong lobe f_s(w, w_o) = specular (s + 2) / (2 pi) max(w . r, 0)^s, r the
// mirror of the view direction w_o (towards the eye) about the face normal n, s = shininess, lit by the
// environment directly with the solid's shadowing (the same visibility as above; no interreflection in the
// glossy term). Per path one more direction is drawn from the lobe around r, density (s + 1) / (2 pi)
// (w . r)^s, and the estimate specular (s + 2) / (s + 1) max(n . w, 0) L(w) is added where the ray reaches
// the environment. Its numbers come from a stream of their own (the seed xor a constant), so the diffuse
// estimate is the same bit for bit with or without the glossy term, and the glossy term is the difference
// of the two images (up to float rounding). With specular = 0 (the default) nothing is drawn.
//
// Determinism: path s of pixel (i, j) draws its numbers from its own generator (splitmix64 seeded from
// seed, i, j and s), so an image is the same bit for bit for the same inputs and seed, whatever the thread
// count; and a path with b + 1 bounces repeats the path with b bounces and only adds to it, so a pixel's
// radiance never decreases as `bounces` grows (for non-negative albedo and environment).
//
// Thread safety: pure functions of their arguments; the rows run in parallel (strata::parallelFor), so the
// callables must be safe to call from several threads at once.
#pragma once

#include "strata/gdm/solid_mesh.h"
#include "strata/image/image.h"
#include "strata/scene/camera.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace strata {

class Mesostructure;
struct GdmDims;

// Radiance arriving from the world direction `direction` (unit, +z up: the direction from the surface
// towards the sky), linear RGB, >= 0.
using EnvironmentRadiance = std::function<glm::dvec3(const glm::dvec3& direction)>;
// Diffuse albedo at a texture point (u, v, w): u, v in [0, 1), w in [0, 1] (CONVENTIONS §8), linear RGB in
// [0, 1].
using GdmAlbedo = std::function<glm::dvec3(const glm::dvec3& texturePoint)>;

struct GdmPathTraceOptions {
    int samplesPerPixel = 16;  // paths per pixel, [1, kMaxSamplesPerPixel]. Default 16.
    // Interreflections per path, [0, kMaxBounces]: 0 = the environment seen directly from the first hit,
    // with the mesostructure's shadowing; 1 = plus one interreflection; ... Default 0.
    int bounces = 0;
    std::uint64_t seed = 0;  // any value; the same seed gives the same image. Default 0.
    // The glossy term (above): its coefficient, finite and >= 0 (0: none, the default), and the Phong
    // exponent s, finite and in [0, kMaxShininess] (default 8).
    double specular = 0.0;
    double shininess = 8.0;

    static constexpr int kMaxSamplesPerPixel = 1 << 20;
    static constexpr int kMaxBounces = 64;
    static constexpr double kMaxShininess = 1e4;
};

struct GdmPathTraceImages {
    Image radiance;  // 3 channels: outgoing radiance, linear RGB (float); 0 where there is no hit
    Image mask;      // 1 channel: 1 = hit (as renderGdmReference's mask)
};

// Renders the GDM verification scene of `solid` (its height is H) seen by `camera` at width x height,
// lit by `environment`, with surface albedo `albedo` (see above). Throws Error(InvalidInput) for what
// renderGdmReference refuses (camera, picture size, shell height, mesh), an empty callable, or options out
// of range (the message names the option and its value), and Error(Runtime) if Embree fails.
GdmPathTraceImages pathTraceGdm(const SolidMesh& solid, const GdmAlbedo& albedo,
                                const EnvironmentRadiance& environment, const Camera& camera, int width,
                                int height, const GdmPathTraceOptions& options);

// The albedo of a built-in or procedural mesostructure: Mesostructure::sample((u, v, w * meso.height()))
// .albedo decoded from sRGB to linear. `meso` must outlive the callable.
GdmAlbedo mesostructureLinearAlbedo(const Mesostructure& meso);

// The albedo of an albedo volume (GdmAsset::albedo, mesostructureAlbedo: Nx Ny Nz voxels, RGB sRGB 8-bit,
// §8 order): each voxel decoded to linear, then trilinear between the voxel centres, wrapping in u and v
// and clamped in w (§8). Throws Error(InvalidInput) for a dimension < 1 or a volume whose size is not
// 3 Nx Ny Nz.
GdmAlbedo gdmVolumeAlbedo(std::vector<std::uint8_t> srgb, int nx, int ny, int nz);

}  // namespace strata
