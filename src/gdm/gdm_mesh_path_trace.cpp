#include "strata/gdm/gdm_mesh_path_trace.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include "mesh_reference_scene.h"
#include "path_sampling.h"
#include "periodic_scene.h"
#include "scene_images.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>

namespace strata {
namespace {

using namespace detail;

// A secondary ray starts this many tile lengths (T / H world units) off its surface along the normal: the
// reference's shadow offset, and the flat tracer's 1e-5 tile widths.
constexpr double kSurfaceOffsetTiles = 1e-5;
// With macro occlusion, a vertex this close to the base (tile widths of texture z, twice the offset) whose
// ray heads into the mesh is absorbed: its offset start may lie below the base, where the ray would not
// cross the mesh's triangle.
constexpr double kBaseBand = 2e-5;

void checkOptions(const GdmMeshPathTraceOptions& options, const std::string& what) {
    checkPathCounts(options.samplesPerPixel, options.bounces, what);
    if (!(options.chordTolerance > 0.0 && options.chordTolerance <= 1.0))
        throw Error(ErrorKind::InvalidInput,
                    what + ": chordTolerance " + formatNumber(options.chordTolerance) + " is outside (0, 1]");
}

// One vertex of a path: where it is and what it faces.
struct Vertex {
    glm::dvec3 point;
    glm::dvec3 normal;
    double z;  // texture z, tile widths
    std::uint32_t prism;
};

}  // namespace

GdmPathTraceImages pathTraceGdmMesh(const SolidMesh& solid, const Mesh& mesh, const PrismShellOptions& shell,
                                    const GdmAlbedo& albedo, const EnvironmentRadiance& environment,
                                    const Camera& camera, int width, int height,
                                    const GdmMeshPathTraceOptions& options) {
    const std::string what = "GDM mesh path trace of " + solid.source;
    checkGdmSceneInput(solid, camera, width, height, what);
    if (!albedo) throw Error(ErrorKind::InvalidInput, what + ": no albedo function");
    if (!environment) throw Error(ErrorKind::InvalidInput, what + ": no environment function");
    checkOptions(options, what);

    EmbreeErrors errors;
    GdmMeshReferenceStats stats;
    const WarpedScene warped =
        buildWarpedScene(solid, mesh, shell, options.chordTolerance, what, errors, stats);
    const double H = warped.height;
    const double offset = kSurfaceOffsetTiles * warped.thickness / H;
    constexpr double kFar = std::numeric_limits<double>::infinity();
    // Camera rays: the reference's (default options), whatever the macro occlusion.
    const WarpedRayRule cameraRule;
    WarpedRayRule pathRule;
    pathRule.anySolidFace = true;
    pathRule.baseBlocks = options.macroOcclusion;

    GdmPathTraceImages images{Image(width, height, 3), Image(width, height, 1)};
    parallelFor(0, height, [&](int j) {
        for (int i = 0; i < width; ++i) {
            const glm::dvec3 view = pixelRayDirection(camera, width, height, i + 0.5, j + 0.5);
            const WarpedCrossing first = firstWarpedHit(warped, camera.eye, view, kFar, cameraRule);
            if (!first.found) continue;
            images.mask.at(i, j) = 1.0f;
            // A cut face on a base faces into the mesh, which is opaque and black.
            if (options.macroOcclusion && first.kind == WarpedFaceKind::Base) continue;
            const glm::dvec3 firstAlbedo = albedo(pathTexturePoint(first.texture, H));
            const Vertex start{camera.eye + first.t * view, first.normal, first.texture.z, first.prism};
            glm::dvec3 sum(0.0);
            for (int sample = 0; sample < options.samplesPerPixel; ++sample) {
                PathRandom random(options.seed, i, j, sample);
                Vertex vertex = start;
                glm::dvec3 weight = firstAlbedo;
                for (int bounce = 0;; ++bounce) {
                    const double u1 = random.next();
                    const double u2 = random.next();
                    const glm::dvec3 direction = cosineDirection(vertex.normal, u1, u2);
                    if (options.macroOcclusion && vertex.z <= kBaseBand &&
                        glm::dot(direction, warped.baseNormals[vertex.prism]) <= 0.0)
                        break;
                    const glm::dvec3 origin = vertex.point + offset * vertex.normal;
                    const WarpedCrossing hit = firstWarpedHit(warped, origin, direction, kFar, pathRule);
                    if (!hit.found) {
                        sum += weight * environment(direction);
                        break;
                    }
                    if (bounce == options.bounces) break;
                    // The mesh (macro occlusion) absorbs it; or it ran inside the solid, from a cut face.
                    if (options.macroOcclusion && hit.kind == WarpedFaceKind::Base) break;
                    if (hit.kind == WarpedFaceKind::Solid && glm::dot(hit.normal, direction) >= 0.0) break;
                    vertex = {origin + hit.t * direction, hit.normal, hit.texture.z, hit.prism};
                    weight *= albedo(pathTexturePoint(hit.texture, H));
                }
            }
            const glm::dvec3 radiance = sum / double(options.samplesPerPixel);
            for (int c = 0; c < 3; ++c) images.radiance.at(i, j, c) = float(radiance[c]);
        }
    });
    if (rtcGetDeviceError(warped.periodic.device.get()) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return images;
}

}  // namespace strata
