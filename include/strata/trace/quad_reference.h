// The exact CPU reference renderer of the verification scene (CONVENTIONS §7), the ground truth that the GL
// renderer's debug outputs are compared against (render_compare.h).
//
// Scene. World space is right-handed, +z up. The unit quad spans x, y in [0, 1] at z = 0 with uv = (x, y),
// T = +x, B = +y, N = +z, tiling 1, so world units are tile units. Below it lies the relief of the tracer
// (HeightFieldTracer: the bilinear, wrap-around height field z = -S d(u, v), S = tracer.depthScale()),
// repeating beyond the quad's edges. The quad is the only way to see the relief: a ray sees it only if it
// enters the quad's top face, i.e. crosses z = 0 going down (eye.z > 0, direction.z < 0) at a point with
// x, y in [0, 1] (closed). From that entry point it meets the relief at
//     HeightFieldTracer::firstHit(eye, direction, tEntry)
// which may lie under a neighbouring tile (the outputs then take (u, v) modulo 1). A ray from an eye at or
// below z = 0, a ray parallel to the quad or going up, and a ray that crosses z = 0 outside [0, 1]^2 never
// sees the relief, even where it passes through the relief's slab. Optionally an opaque sphere stands in the
// scene (for interpenetration tests); it is visible wherever a ray meets it, inside the quad's footprint or
// not, above z = 0 or below, and it hides the relief where it is nearer along the ray.
//
// Camera: strata::Camera, one ray per pixel centre (i + 0.5, j + 0.5), pixel (0, 0) top-left, the ray of
// pixelRayDirection (the same one the GL renderer rasterises).
//
// Outputs describe what the pixel shows (no antialiasing, no tone mapping). Where the relief is visible
// (object == 1): uv = (u, v, 1) of the hit, depth = d of the hit, shadow = 1 if the hit is lit by the point
// light P, with
//     lit <=> !tracer.occludedFromSurface(u, v, P - hitPoint, 1.0)
// i.e. nothing of the (repeating) relief strictly between the hit and P; the hit point is the unwrapped one,
// so the direction to P is the true one even when the hit lies under a neighbouring tile. The sphere casts
// no shadow (the shadow output is the relief's self-shadowing of CONVENTIONS §7). Where the sphere or
// nothing is visible, uv = (0, 0, 0), depth = 0 and shadow = 0. A relief whose first hit lies more than
// HeightFieldTracer::kMaxTravelTiles of horizontal travel from the entry (rays within about
// atan(S / 64) of grazing) is reported as not hit.
//
// Converting to the 16-bit PNG encoding of §7 (round(value * 65535)) is the caller's job (the CLI).
// Thread safety: pure functions of their arguments; renderQuadReference runs its rows in parallel
// (strata/core/parallel.h).
#pragma once

#include "strata/image/image.h"
#include "strata/scene/camera.h"
#include "strata/trace/heightfield_tracer.h"

#include <glm/vec3.hpp>

#include <optional>

namespace strata {

// An opaque sphere in world (tile) units.
struct ReferenceSphere {
    glm::dvec3 centre{0.0, 0.0, 0.0};  // world units, finite
    double radius = 0.0;               // world units, finite and > 0
};

struct QuadReferenceOptions {
    // Point light P in world units (finite). Without one, the shadow output is 0 everywhere.
    std::optional<glm::dvec3> light;
    // An optional opaque sphere. The eye must lie strictly outside it.
    std::optional<ReferenceSphere> sphere;
};

// What a pixel shows: object 0 = nothing, 1 = the relief, 2 = the sphere.
enum class QuadReferenceObject { Nothing = 0, Relief = 1, Sphere = 2 };

// One ray's result, in double (the images store these values as float).
struct QuadReferenceSample {
    QuadReferenceObject object = QuadReferenceObject::Nothing;
    double distance = 0.0;    // eye to the visible point, world units; 0 when nothing is visible
    glm::dvec3 point{0.0};    // the visible point, world units, unwrapped; (0, 0, 0) when nothing
    double u = 0.0, v = 0.0;  // relief only: the hit's (u, v) in [0, 1) (modulo 1); else 0
    double depth = 0.0;       // relief only: d at the hit; else 0
    bool lit = false;         // relief only: lit by the light (see the header comment); else false
};

struct QuadReferenceImages {
    Image uv;      // 3 channels: (u, v, 1) of the visible relief hit, u, v in [0, 1) (modulo 1, as float: a u
                   // within half a float ulp of 1 is stored as the float below 1); (0, 0, 0) elsewhere
    Image shadow;  // 1 channel: 1 where the visible relief hit is lit by the light, else 0
    Image depth;   // 1 channel: d of the visible relief hit, 0 elsewhere
    Image object;  // 1 channel: 0 = nothing, 1 = relief visible, 2 = sphere visible (nearest along the ray)
    Image distance;  // 1 channel: eye-to-visible-point distance in world units (relief or sphere), 0 for none
};

// Renders the verification scene: one ray per pixel centre, width x height pixels.
// Throws Error(InvalidInput) naming the value for: width or height outside [1, Image::kMaxDimension], an
// invalid camera (validateCamera), a non-finite light, a sphere whose centre is not finite or whose radius
// is not finite and > 0, or an eye inside or on the sphere.
QuadReferenceImages renderQuadReference(const HeightFieldTracer& tracer, const Camera& camera, int width,
                                        int height, const QuadReferenceOptions& options = {});

// The same for one ray from `eye` along `direction` (finite, non-zero, need not be unit; `distance` is in
// world units either way), for tests and for point checks. Throws like renderQuadReference for a non-finite
// eye or direction, a zero direction, and bad options.
QuadReferenceSample traceQuadReference(const HeightFieldTracer& tracer, const glm::dvec3& eye,
                                       const glm::dvec3& direction, const QuadReferenceOptions& options = {});

// The distance along the ray eye + t direction (direction unit) to the nearer intersection with the sphere,
// t > 0; nullopt if the ray misses it (a tangent ray hits). The eye must lie outside the sphere (checked).
std::optional<double> raySphereDistance(const glm::dvec3& eye, const glm::dvec3& unitDirection,
                                        const ReferenceSphere& sphere);

}  // namespace strata
