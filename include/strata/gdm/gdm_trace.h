// The GDM verification scene (CONVENTIONS §8): its exact CPU reference, and a CPU emulation of the paper's
// per-pixel algorithm (Wang et al. 2004, "Generalized Displacement Maps", Sec. 3.2) on the same scene, with
// the measures that compare the two.
//
// Scene. World space = the tile's isotropic frame: the unit quad x, y in [0, 1] at z = 0, and above it the
// shell box [0, 1]^2 x [0, H] (z = w H). The visible geometry is the periodic solid (the solid mesh's
// integer translates, CONVENTIONS §8) intersected with that box. A ray is seen only where it enters the box
// through its top or one of its four sides (a ray entering through the bottom, or missing the box, is a
// miss). Camera: strata::Camera, one ray per pixel centre (i + 0.5, j + 0.5), pixel (0, 0) top-left, the
// ray of pixelRayDirection. Point light P in world units.
//
// Outputs (GdmSceneImages), what a pixel shows, as float, no antialiasing:
//   uvw: 4 channels (u, v, w, 1) of the first hit, u, v modulo 1 in [0, 1) (a value within half a float
//        ulp of 1 is stored as the float below 1), w = z / H in [0, 1]; (0, 0, 0, 0) where there is no hit.
//   mask: 1 on a hit, else 0.
//   shadow: 1 where the hit is lit by P, else 0 (also 0 where there is no hit).
// Converting to the 16-bit PNGs of §8 (round(value * 65535)) is the caller's job.
//
// Thread safety: pure functions of their arguments; the renderers run their rows in parallel
// (strata::parallelFor).
#pragma once

#include "strata/gdm/gdm.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/solid_mesh.h"
#include "strata/image/image.h"
#include "strata/scene/camera.h"

#include <glm/vec3.hpp>

namespace strata {

// How the emulation's GDM lookup reads the direction (theta, phi) of a query.
enum class GdmDirectionLookup {
    Nearest,   // the nearest direction sample. Default.
    Bilinear,  // bilinear between the 4 sample centres around it (theta clamped, phi wrapping)
};

struct GdmSceneImages {
    Image uvw;     // 4 channels: (u, v, w, hit) as above
    Image mask;    // 1 channel: 1 = hit
    Image shadow;  // 1 channel: 1 = lit
};

// The verification scene's view used by Strata's accuracy tables and `strata gdm trace`'s defaults: towards
// the quad's centre (0.5, 0.5, 0) from `degreesFromNormal` off its normal in the y-z plane, distance 1.6,
// eye (0.5, 0.5 - 1.6 sin a, 1.6 cos a), vertical field of view 45 degrees, up +z.
Camera gdmSceneView(double degreesFromNormal);

// Throws Error(InvalidInput) "GDM scene: picture size W x H is outside [1, Image::kMaxDimension]" for a
// picture the scene renderers (these, and strata::gl's) refuse.
void validateGdmPicture(int width, int height);

// The exact reference, with Embree on the solid mesh (the bake's periodic scene, src/gdm/periodic_scene.h).
// Per pixel: the ray's entry point into the box; if that point lies inside the periodic solid (the bake's
// winding-number test) the ray hits there, on the cut face, whose normal is the box face's outward normal.
// Otherwise the first face of the periodic mesh along the ray before it leaves the box (normal: the face's
// outward normal); none is a miss.
// Shadow, CONVENTIONS §8: lit iff the hit's normal faces P (dot(n, P - X) > 0) and the segment from the hit
// X (moved 1e-5 along n, off the surface) to P meets no face of the periodic solid inside the infinite slab
// 0 <= z <= H (the bake's wrapped ray walk, up to kGdmBakeMaxTravel tile widths).
// width, height in [1, Image::kMaxDimension]. Throws what validateCamera and bakeGdm's mesh checks throw
// (Error(InvalidInput)), and Error(InvalidInput) for a shell height that is not finite and > 0.
GdmSceneImages renderGdmReference(const SolidMesh& solid, const Camera& camera, glm::dvec3 light, int width,
                                  int height);

// The paper's per-pixel algorithm (Sec. 3.2), emulated on the CPU. The quad is two triangles, split along
// its diagonal x = y (prism A: x >= y, prism B: x <= y), each extruded to a prism of height H; the boundary
// prisms' outer fins are the box's sides. Per pixel:
//   - T_in: the ray's entry into the box (the first prism face it meets: the top or a side fin); the prism
//     holding T_in (on the diagonal: the one the ray goes into).
//   - T_out: the nearest of that prism's other faces (ray-plane intersections), dt = |T_out - T_in| in the
//     isotropic frame (= world here), V = (T_out - T_in) / dt.
//   - d = d(T_in, V) from the GDM; d < dt (and d not an exit, below): the hit is T_in + d V. Otherwise, if
//     T_out lies on the diagonal, the ray goes on into the other prism from T_in = T_out; else it is a miss.
// GDM lookup d(T, V) (shaders/shared/gdm_lookup.h, the GL renderer's own code, in float as the shader runs
// it): trilinear in (x, y, z) between the voxel centres (wrapping in u, v, clamped in z, §8);
// in (theta, phi) the nearest direction sample by default (GdmDirectionLookup): bilinear mixes the
// distances of rays that go different ways, which on thin structures turns misses into hits (the chain at
// 45 degrees: 15.8% of pixels disagree on hit / miss with bilinear, 12.6% with nearest; docs/gdm.md).
// Interpolation runs on the substituted values of gdm_svd.h (a raw kGdmMiss counts as
// gdmBoundaryDistance(k, t); the SVD's reconstruct() is already substituted), and the same weights
// interpolate the boundary distance b; the lookup is an exit (dmax) iff d >= b - tolerance, with
// tolerance 1e-4 H / Nz for the raw GDM (only values that are all exits) and svd.exitTolerance for the
// SVD (its exit rule, isGdmExit).
// Shadow: lit iff d(T', L) is an exit (dmax), with L = normalize(P - T), looked up at T' = T - 1 voxel
// (H / Nz) along V (backed off towards the eye), and with the stencil's corners whose value is below half a
// voxel (inside the solid, or touching it) left out of the trilinear mix (the rest renormalised; none left:
// shadowed). Without both, the zeros of the voxels inside the solid next to every hit make almost every hit
// read as shadowed (99% of a lit sphere, test_gdm_trace.cpp). There is no normal, so no facing test. The
// isotropic frame is world space on this flat quad, so L needs no scaling.
// uvw as the reference's. Throws Error(InvalidInput) for a GDM whose value count does not match its dims.
GdmSceneImages emulateGdm(const Gdm& gdm, const Camera& camera, glm::dvec3 light, int width, int height,
                          GdmDirectionLookup directions = GdmDirectionLookup::Nearest);
GdmSceneImages emulateGdm(const GdmSvd& svd, const Camera& camera, glm::dvec3 light, int width, int height,
                          GdmDirectionLookup directions = GdmDirectionLookup::Nearest);

// How well `test` reproduces `reference` (two renders of the same scene and size).
struct GdmSceneAccuracy {
    double voxelLength = 0.0;             // tile widths, the unit of the errors below
    double hitMissDisagreePercent = 0.0;  // % of all pixels where one hits and the other does not
    std::size_t bothHitPixels = 0;
    // Over the pixels where both hit: the distance between the two hit points in the isotropic frame
    // (u, v, w H), u and v differences wrapped into [-0.5, 0.5], in voxels.
    double uvwMeanVoxels = 0.0;
    double uvwP95Voxels = 0.0;
    double uvwP99Voxels = 0.0;
    double shadowAgreePercent = 0.0;  // % of the pixels where both hit whose shadow values agree
};

// Throws Error(InvalidInput) when the images' sizes differ, or voxelLength or shellHeight is not > 0.
GdmSceneAccuracy compareGdmScenes(const GdmSceneImages& reference, const GdmSceneImages& test,
                                  double shellHeight, double voxelLength);

}  // namespace strata
