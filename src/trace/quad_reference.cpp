// The exact reference renderer of the verification scene (include/strata/trace/quad_reference.h,
// docs/trace.md).
#include "strata/trace/quad_reference.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace strata {

namespace {

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string formatPoint(const glm::dvec3& p) {
    return "(" + formatNumber(p.x) + ", " + formatNumber(p.y) + ", " + formatNumber(p.z) + ")";
}

void validateOptions(const QuadReferenceOptions& options, const glm::dvec3& eye) {
    if (options.light && !finite(*options.light)) {
        throw Error(ErrorKind::InvalidInput,
                    "quad reference: light position must be finite, got " + formatPoint(*options.light));
    }
    if (options.sphere) {
        const ReferenceSphere& sphere = *options.sphere;
        if (!finite(sphere.centre)) {
            throw Error(ErrorKind::InvalidInput,
                        "quad reference: sphere centre must be finite, got " + formatPoint(sphere.centre));
        }
        if (!(std::isfinite(sphere.radius) && sphere.radius > 0.0)) {
            throw Error(
                ErrorKind::InvalidInput,
                "quad reference: sphere radius must be finite and > 0, got " + formatNumber(sphere.radius));
        }
        const double eyeDistance = glm::length(eye - sphere.centre);
        if (!(eyeDistance > sphere.radius)) {
            throw Error(ErrorKind::InvalidInput, "quad reference: the eye " + formatPoint(eye) +
                                                     " is inside or on the sphere (centre " +
                                                     formatPoint(sphere.centre) + ", radius " +
                                                     formatNumber(sphere.radius) + ")");
        }
    }
}

// u in [0, 1) as a float in [0, 1): a u within half a float ulp of 1 would round to 1.0f.
float toUnitInterval(double u) {
    return std::min(static_cast<float>(u), std::nextafter(1.0f, 0.0f));
}

// The relief part of the scene: the ray's first relief hit if it enters the quad's top face.
std::optional<HeightFieldTracer::Hit> reliefHit(const HeightFieldTracer& tracer, const glm::dvec3& eye,
                                                const glm::dvec3& direction) {
    // Entering the top face needs a start strictly above it and a downward ray; this also excludes rays
    // parallel to the quad (direction.z == 0), which never cross it.
    if (!(eye.z > 0.0 && direction.z < 0.0)) return std::nullopt;
    const double tEntry = -eye.z / direction.z;
    const double x = eye.x + tEntry * direction.x;
    const double y = eye.y + tEntry * direction.y;
    if (!(x >= 0.0 && x <= 1.0 && y >= 0.0 && y <= 1.0)) return std::nullopt;
    // From the eye with tMin = tEntry (rather than from the rounded entry point): the tracer's semantics
    // are exact for an origin above the relief, and nothing before the entry can count (a map with d < 0
    // would reach above z = 0 there).
    return tracer.firstHit(eye, direction, tEntry);
}

// direction: unit. Options validated by the caller.
QuadReferenceSample trace(const HeightFieldTracer& tracer, const glm::dvec3& eye, const glm::dvec3& direction,
                          const QuadReferenceOptions& options) {
    QuadReferenceSample sample;
    const std::optional<HeightFieldTracer::Hit> relief = reliefHit(tracer, eye, direction);
    const std::optional<double> sphere =
        options.sphere ? raySphereDistance(eye, direction, *options.sphere) : std::nullopt;

    // The sphere wins only when strictly nearer: a tie (touching the relief) shows the relief.
    if (sphere && (!relief || *sphere < relief->t)) {
        sample.object = QuadReferenceObject::Sphere;
        sample.distance = *sphere;
        sample.point = eye + *sphere * direction;
        return sample;
    }
    if (!relief) return sample;

    sample.object = QuadReferenceObject::Relief;
    sample.distance = relief->t;
    sample.point = relief->point;
    sample.u = relief->u;
    sample.v = relief->v;
    sample.depth = relief->depth;
    if (options.light) {
        const glm::dvec3 toLight = *options.light - relief->point;
        // A light exactly at the hit has nothing between it and the hit.
        sample.lit =
            toLight == glm::dvec3(0.0) || !tracer.occludedFromSurface(relief->u, relief->v, toLight, 1.0);
    }
    return sample;
}

}  // namespace

std::optional<double> raySphereDistance(const glm::dvec3& eye, const glm::dvec3& unitDirection,
                                        const ReferenceSphere& sphere) {
    // |e + t w|^2 = r^2 with e = eye - centre, |w| = 1:  t^2 + 2 b t + c = 0,  b = e.w,  c = |e|^2 - r^2.
    const glm::dvec3 e = eye - sphere.centre;
    const double b = glm::dot(e, unitDirection);
    const double c = glm::dot(e, e) - sphere.radius * sphere.radius;
    STRATA_CHECK_GT(c, 0.0);  // eye outside the sphere (validated by the callers)
    // With c > 0 both roots have the sign of -b: b >= 0 puts the sphere behind the eye.
    if (b >= 0.0) return std::nullopt;
    // The discriminant b^2 - c cancels catastrophically for a distant eye; written as r^2 - |l|^2 with l
    // the centre's offset from the line (l = e - b w) it keeps its precision (Haines et al., "Precision
    // Improvements for Ray/Sphere Intersection", Ray Tracing Gems, ch. 7).
    const double offset = glm::length(e - b * unitDirection);
    const double discriminant = (sphere.radius - offset) * (sphere.radius + offset);
    if (discriminant < 0.0) return std::nullopt;
    // Nearer root -b - sqrt(D) written as c / (-b + sqrt(D)): no cancellation for grazing rays.
    return c / (-b + std::sqrt(discriminant));
}

QuadReferenceSample traceQuadReference(const HeightFieldTracer& tracer, const glm::dvec3& eye,
                                       const glm::dvec3& direction, const QuadReferenceOptions& options) {
    if (!finite(eye))
        throw Error(ErrorKind::InvalidInput, "quad reference: eye must be finite, got " + formatPoint(eye));
    const double length = glm::length(direction);
    if (!finite(direction) || !(length > 0.0) || !std::isfinite(length)) {
        throw Error(
            ErrorKind::InvalidInput,
            "quad reference: ray direction must be finite and non-zero, got " + formatPoint(direction));
    }
    validateOptions(options, eye);
    return trace(tracer, eye, direction / length, options);
}

QuadReferenceImages renderQuadReference(const HeightFieldTracer& tracer, const Camera& camera, int width,
                                        int height, const QuadReferenceOptions& options) {
    if (width < 1 || width > Image::kMaxDimension || height < 1 || height > Image::kMaxDimension) {
        throw Error(ErrorKind::InvalidInput, "quad reference: picture size must be in [1, " +
                                                 std::to_string(Image::kMaxDimension) + "] per side, got " +
                                                 std::to_string(width) + " x " + std::to_string(height));
    }
    validateCamera(camera, "quad reference camera");
    validateOptions(options, camera.eye);

    QuadReferenceImages images{Image(width, height, 3), Image(width, height, 1), Image(width, height, 1),
                               Image(width, height, 1), Image(width, height, 1)};
    parallelFor(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 direction = pixelRayDirection(camera, width, height, x + 0.5, y + 0.5);
            const QuadReferenceSample sample = trace(tracer, camera.eye, direction, options);
            images.object.at(x, y) = static_cast<float>(static_cast<int>(sample.object));
            images.distance.at(x, y) = static_cast<float>(sample.distance);
            if (sample.object != QuadReferenceObject::Relief) continue;  // the zero fill stands
            images.uv.at(x, y, 0) = toUnitInterval(sample.u);
            images.uv.at(x, y, 1) = toUnitInterval(sample.v);
            images.uv.at(x, y, 2) = 1.0f;
            images.depth.at(x, y) = static_cast<float>(sample.depth);
            images.shadow.at(x, y) = sample.lit ? 1.0f : 0.0f;
        }
    });
    return images;
}

}  // namespace strata
