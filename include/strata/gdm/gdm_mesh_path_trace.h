// A CPU path tracer of a GDM mesostructure on a curved base, lit by a distant environment: the reference for
// bi-scale radiance transfer on meshes (Wang et al. 2004, "Generalized Displacement Maps", Sec. 3.2 "Global
// Illumination": the meso-scale radiance transfer volume, with the macro-scale transfer of Sloan et al.
// 2003 for the base mesh's own shadowing; strata/gdm/macro_transfer.h). It measures the error of the GL
// renderer's 0, 1 and 2 bounces on a mesh, as pathTraceGdm (gdm_path_trace.h) does on the flat scene.
//
// Geometry and primary rays: exactly renderGdmMeshReference's (gdm_mesh_reference.h, default options):
// the periodic solid warped by each prism's map into the prism shell of `mesh` (the shell's height is the
// solid's H; tiling and thickness from `shell`), cut into flat triangles within chordTolerance T of the
// curved faces, traced with Embree. One camera ray per pixel, through its centre, with the same first hit
// (a warped solid face entered, or a cut face where the ray enters the shell inside the solid), so the mask
// is renderGdmMeshReference's mask, pixel for pixel.
//
// Light transport (as pathTraceGdm's, on the mesh):
//   - Surfaces: the warped solid's faces and its cut faces (normal: the shell boundary's outward normal),
//     Lambertian (BRDF albedo / pi), flat-shaded with the flat triangle's world normal. Albedo: the
//     callable at the hit's texture point (u mod 1, v mod 1, w = z / H), u, v tile coordinates
//     (tiling * uv) interpolated on the flat triangle.
//   - Occluders of secondary rays: the warped solid of the whole shell (any prism's; a solid face met from
//     behind, by a ray that started on a cut face and ran inside the solid, absorbs it, as in the flat
//     tracer), and, with macroOcclusion (the default), the base mesh itself as an opaque black surface: a
//     ray that meets one of the mesh's triangles (a prism's base), either way, is absorbed, and so is a ray
//     that leaves a point within 2e-5 tile widths of the base heading into the mesh (its start, offset off
//     the surface, may already lie below the base). This is the bi-scale split's macro-scale occlusion: the
//     GL renderer gets it from the per-vertex macro transfer (V(w) of macro_transfer.h, rays against the
//     mesh's triangles) and its meso-scale transfer counts no light from below the base, so the path
//     tracer's picture is what the product of the two approximates. On the flat quad it is the flat
//     scene's rule that a ray leaving the slab through its bottom is blocked. A cut face on a base (a
//     camera ray that reached the solid from inside the mesh) faces into the mesh: black with
//     macroOcclusion. With macroOcclusion = false the base mesh is transparent to secondary rays (camera
//     rays never stop at it, either way: the mask does not depend on the option).
//   - The environment: a secondary ray that meets nothing sees environment(direction), world space, any
//     direction (also below the horizon: on a closed mesh with macroOcclusion no ray leaving the shell
//     downwards escapes without meeting the mesh, on an open one it may). Not drawn where the camera ray
//     misses (radiance 0, mask 0).
//   - Unlike the flat scene, nothing repeats outside the shell: a ray that leaves the shell (through its
//     top, or a rim fin of an open mesh) and does not come back into it escapes. On the quad at tiling 1
//     the flat scene's infinite periodic slab has neighbouring tiles where the shell of one quad has none,
//     and its side faces are cut faces inside the solid where the quad's rim fins are open to the
//     environment: the two agree where paths leave through the top (tests/gdm/test_gdm_mesh_path_trace.cpp).
//
// Estimator, bounces, determinism: pathTraceGdm's. Per pixel, samplesPerPixel paths from the first hit; at
// each vertex a cosine-weighted direction around the face normal (so a path's weight is the product of the
// albedos), drawn from the same generator as pathTraceGdm's (splitmix64 from seed, pixel and sample); a
// secondary ray starts 1e-5 tile lengths (T / H world units) off its surface along the normal, the
// reference's shadow offset. bounces = 0: direct light from the environment with the solid's and the
// mesh's shadowing; each further bounce adds the paths with one more interreflection. No next-event
// estimation, no Russian roulette; the image is the same bit for bit for the same inputs, whatever the
// thread count, and never decreases per pixel as `bounces` grows, or when macroOcclusion is turned off (a
// path is the same or is cut short).
//
// Thread safety: a pure function of its arguments; rows run in parallel (strata::parallelFor), so the
// callables must be safe to call from several threads at once.
#pragma once

#include "strata/gdm/gdm_path_trace.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gdm/solid_mesh.h"
#include "strata/mesh/mesh.h"
#include "strata/scene/camera.h"

#include <cstdint>

namespace strata {

struct GdmMeshPathTraceOptions {
    int samplesPerPixel = 16;  // paths per pixel, [1, GdmPathTraceOptions::kMaxSamplesPerPixel]. Default 16.
    int bounces = 0;           // interreflections per path, [0, GdmPathTraceOptions::kMaxBounces]. Default 0.
    std::uint64_t seed = 0;    // any value; the same seed gives the same image. Default 0.
    // The base mesh is an opaque black occluder of secondary rays (true, default) or transparent (false).
    bool macroOcclusion = true;
    // The warped faces' flat-triangle tolerance, fraction of T, (0, 1] (GdmMeshReferenceOptions). Default
    // 1e-3, the reference's, so that the mask is its mask.
    double chordTolerance = 1e-3;
};

// Renders `solid` (its height is H) on the prism shell of `mesh` (shell.tiling, shell.thickness; the
// shell's height is H) seen by `camera` at width x height, lit by `environment`, with surface albedo
// `albedo` (above). Throws Error(InvalidInput) for what renderGdmMeshReference refuses (camera, picture
// size, solid, mesh), an empty callable, or options out of range (the message names the option and its
// value), and Error(Runtime) if Embree fails.
GdmPathTraceImages pathTraceGdmMesh(const SolidMesh& solid, const Mesh& mesh, const PrismShellOptions& shell,
                                    const GdmAlbedo& albedo, const EnvironmentRadiance& environment,
                                    const Camera& camera, int width, int height,
                                    const GdmMeshPathTraceOptions& options = {});

}  // namespace strata
