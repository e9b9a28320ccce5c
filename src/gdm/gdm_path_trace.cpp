#include "strata/gdm/gdm_path_trace.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/image/srgb.h"

#include "path_sampling.h"
#include "periodic_scene.h"
#include "scene_hit.h"
#include "scene_images.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

namespace strata {
namespace {

using namespace detail;

// A secondary ray starts this far off its surface along the normal (tile widths), so that it does not meet
// the face it leaves: the reference's shadow offset (gdm_trace.cpp), far below a voxel (1 / 64) and far
// above float rounding at unit scale.
constexpr double kSurfaceOffset = 1e-5;

// The glossy term's own random stream: the seed xor this constant.
constexpr std::uint64_t kGlossyStream = 0x676c6f7373790001ull;

void checkOptions(const GdmPathTraceOptions& options, const std::string& what) {
    checkPathCounts(options.samplesPerPixel, options.bounces, what);
    if (!(std::isfinite(options.specular) && options.specular >= 0.0))
        throw Error(ErrorKind::InvalidInput,
                    what + ": specular " + formatNumber(options.specular) + " is not finite and >= 0");
    if (!(options.shininess >= 0.0 && options.shininess <= GdmPathTraceOptions::kMaxShininess))
        throw Error(ErrorKind::InvalidInput, what + ": shininess " + formatNumber(options.shininess) +
                                                 " is outside [0, " +
                                                 formatNumber(GdmPathTraceOptions::kMaxShininess) + "]");
}

}  // namespace

GdmPathTraceImages pathTraceGdm(const SolidMesh& solid, const GdmAlbedo& albedo,
                                const EnvironmentRadiance& environment, const Camera& camera, int width,
                                int height, const GdmPathTraceOptions& options) {
    const std::string what = "GDM path trace of " + solid.source;
    detail::checkGdmSceneInput(solid, camera, width, height, what);
    if (!albedo) throw Error(ErrorKind::InvalidInput, what + ": no albedo function");
    if (!environment) throw Error(ErrorKind::InvalidInput, what + ": no environment function");
    checkOptions(options, what);

    GdmPathTraceImages images{Image(width, height, 3), Image(width, height, 1)};
    if (solid.triangles.empty()) return images;
    EmbreeErrors errors;
    const PeriodicScene scene = buildScene(solid, what, errors);
    const double shell = solid.height;
    parallelFor(0, height, [&](int j) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int i = 0; i < width; ++i) {
            const glm::dvec3 view = pixelRayDirection(camera, width, height, i + 0.5, j + 0.5);
            const SceneHit first = firstSceneHit(scene, context, camera.eye, view, shell);
            if (!first.hit) continue;
            const glm::dvec3 firstAlbedo = albedo(pathTexturePoint(first.point, shell));
            glm::dvec3 sum(0.0);
            for (int sample = 0; sample < options.samplesPerPixel; ++sample) {
                PathRandom random(options.seed, i, j, sample);
                glm::dvec3 point = first.point;
                glm::dvec3 normal = first.normal;
                glm::dvec3 weight = firstAlbedo;
                for (int bounce = 0;; ++bounce) {
                    const double u1 = random.next();
                    const double u2 = random.next();
                    const glm::dvec3 direction = cosineDirection(normal, u1, u2);
                    glm::dvec3 origin = point + kSurfaceOffset * normal;
                    origin.z = std::clamp(origin.z, 0.0, shell);
                    unsigned primitive = 0;
                    const float distance =
                        distanceAlong(scene, scene.scene.get(), context, wrapped(origin, direction, 0.0),
                                      direction, shell, 0.0, &primitive);
                    if (distance == kGdmMiss) {
                        // Out of the slab (or kGdmBakeMaxTravel inside it): through the top it sees the
                        // environment; through the bottom, or horizontally, it is blocked (the header).
                        if (direction.z > 0.0) sum += weight * environment(direction);
                        break;
                    }
                    if (bounce == options.bounces) break;
                    const glm::dvec3 faceNormal = glm::normalize(glm::dvec3(scene.normals[primitive]));
                    // Met from behind: the ray ran inside the solid (from a cut face); the solid absorbs it.
                    if (glm::dot(faceNormal, direction) >= 0.0) break;
                    point = origin + double(distance) * direction;
                    normal = faceNormal;
                    weight *= albedo(pathTexturePoint(point, shell));
                }
            }
            glm::dvec3 radiance = sum / double(options.samplesPerPixel);
            if (options.specular > 0.0) {
                // The glossy term: the Phong lobe around the mirror of the view about the face normal.
                const glm::dvec3 normal = first.normal, eye = -view;
                const glm::dvec3 mirror = glm::normalize(2.0 * glm::dot(normal, eye) * normal - eye);
                const double scale = options.specular * (options.shininess + 2.0) / (options.shininess + 1.0);
                glm::dvec3 glossy(0.0);
                for (int sample = 0; sample < options.samplesPerPixel; ++sample) {
                    PathRandom random(options.seed ^ kGlossyStream, i, j, sample);
                    const double u1 = random.next();
                    const double u2 = random.next();
                    const glm::dvec3 direction = phongDirection(mirror, options.shininess, u1, u2);
                    const double cosine = glm::dot(normal, direction);
                    if (cosine <= 0.0 || direction.z <= 0.0) continue;
                    glm::dvec3 origin = first.point + kSurfaceOffset * normal;
                    origin.z = std::clamp(origin.z, 0.0, shell);
                    const float distance =
                        distanceAlong(scene, scene.scene.get(), context, wrapped(origin, direction, 0.0),
                                      direction, shell, 0.0, nullptr);
                    if (distance == kGdmMiss) glossy += scale * cosine * environment(direction);
                }
                radiance += glossy / double(options.samplesPerPixel);
            }
            for (int c = 0; c < 3; ++c) images.radiance.at(i, j, c) = float(radiance[c]);
            images.mask.at(i, j) = 1.0f;
        }
    });
    if (rtcGetDeviceError(scene.device.get()) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return images;
}

GdmAlbedo mesostructureLinearAlbedo(const Mesostructure& meso) {
    return [&meso](const glm::dvec3& p) {
        const glm::dvec3 srgb = meso.sample({p.x, p.y, p.z * meso.height()}).albedo;
        return glm::dvec3(srgbToLinear(srgb.x), srgbToLinear(srgb.y), srgbToLinear(srgb.z));
    };
}

GdmAlbedo gdmVolumeAlbedo(std::vector<std::uint8_t> srgb, int nx, int ny, int nz) {
    if (nx < 1 || ny < 1 || nz < 1)
        throw Error(ErrorKind::InvalidInput, "albedo volume: dimensions " + std::to_string(nx) + " x " +
                                                 std::to_string(ny) + " x " + std::to_string(nz) +
                                                 " are not all >= 1");
    const std::size_t voxels = std::size_t(nx) * std::size_t(ny) * std::size_t(nz);
    if (srgb.size() != 3 * voxels)
        throw Error(ErrorKind::InvalidInput, "albedo volume: " + std::to_string(srgb.size()) + " bytes for " +
                                                 std::to_string(nx) + " x " + std::to_string(ny) + " x " +
                                                 std::to_string(nz) + " RGB voxels (" +
                                                 std::to_string(3 * voxels) + " needed)");
    // Decoded once: trilinear interpolation of linear values (albedo mixes linearly).
    auto linear = std::make_shared<std::vector<glm::dvec3>>(voxels);
    for (std::size_t v = 0; v < voxels; ++v)
        (*linear)[v] = glm::dvec3(srgbToLinear(srgb[3 * v] / 255.0), srgbToLinear(srgb[3 * v + 1] / 255.0),
                                  srgbToLinear(srgb[3 * v + 2] / 255.0));
    return [linear, nx, ny, nz](const glm::dvec3& p) {
        // Continuous voxel coordinates: sample centres at integers (CONVENTIONS §8).
        const double x = p.x * nx - 0.5, y = p.y * ny - 0.5;
        const double z = std::clamp(p.z * nz - 0.5, 0.0, double(nz - 1));
        const double x0 = std::floor(x), y0 = std::floor(y), z0 = std::floor(z);
        const double fx = x - x0, fy = y - y0, fz = z - z0;
        const auto wrap = [](double index, int n) {
            const long long m = static_cast<long long>(index) % n;
            return static_cast<std::size_t>(m < 0 ? m + n : m);
        };
        glm::dvec3 result(0.0);
        for (int corner = 0; corner < 8; ++corner) {
            const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
            const double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy) * (dz ? fz : 1.0 - fz);
            if (w == 0.0) continue;
            const std::size_t i = wrap(x0 + dx, nx), jj = wrap(y0 + dy, ny);
            const std::size_t k =
                std::min(static_cast<std::size_t>(z0) + std::size_t(dz), std::size_t(nz - 1));
            result += w * (*linear)[(k * std::size_t(ny) + jj) * std::size_t(nx) + i];
        }
        return result;
    };
}

}  // namespace strata
