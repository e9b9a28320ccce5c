#include "strata/gdm/gdm_trace.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include "periodic_scene.h"
#include "scene_hit.h"
#include "scene_images.h"
#include "shared/gdm_lookup.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace strata {
namespace {

using namespace detail;

constexpr double kInf = std::numeric_limits<double>::infinity();
// The shadow ray starts this far off the surface (tile widths), so that it does not meet the face it
// leaves; far below a voxel (1 / 64) and far above float rounding at unit scale.
constexpr double kShadowOffset = 1e-5;
// The emulation's shadow lookup (gdm_trace.h): backed off this many voxels (H / Nz) towards the eye, and
// ignoring the corners whose value is below this many voxels (inside the solid or touching it). Chosen on
// the sphere of test_gdm_trace.cpp (all of it lit): without either, 99% of its lit pixels read as
// shadowed at 32 x 32 x 8 voxels; with both, 2%.
constexpr double kShadowBackoffVoxels = 1.0;
constexpr double kShadowDropVoxels = 0.5;

// --- The emulation's GDM lookup -------------------------------------------------------------------------

// d(T, V) of gdm_trace.h: shaders/shared/gdm_lookup.h, the GL renderer's own, in float as the shader
// computes it, reading `value` (a substituted value per voxel and direction).
struct Lookup {
    double distance = kInf;  // kInf on an exit
    bool exit = true;
};

template <class Value>
class EmulatedLookup final : public shared::GdmLookup {
public:
    EmulatedLookup(const GdmDims& dims, double height, double tolerance, GdmDirectionLookup directions,
                   const Value& value)
        : mValue(value) {
        mParams.voxels = shared::ivec3(dims.nx, dims.ny, dims.nz);
        mParams.directions = shared::ivec2(dims.ntheta, dims.nphi);
        mParams.height = float(height);
        mParams.tolerance = float(tolerance);
        mParams.bilinear = directions == GdmDirectionLookup::Bilinear;
    }
    float gdmValue(int i, int j, int k, int t, int s) override { return mValue(mParams, i, j, k, t, s); }
    Lookup operator()(const glm::dvec3& point, const glm::dvec3& direction, double dropBelow = -1.0) {
        const glm::vec2 d = gdmLookup(mParams, glm::vec3(point), glm::vec3(direction), float(dropBelow));
        if (d.y > 0.5f) return {};
        return {double(d.x), false};
    }

private:
    shared::GdmLookupParams mParams{};
    const Value& mValue;
};

template <class Value>
GdmSceneImages emulate(const GdmDims& dims, double shell, double tolerance, const Value& value,
                       const Camera& camera, const glm::dvec3& light, int width, int height,
                       GdmDirectionLookup directions) {
    validateCamera(camera);
    validateGdmPicture(width, height);
    GdmSceneImages images = detail::blankGdmImages(width, height);
    const double voxel = shell / dims.nz;
    parallelFor(0, height, [&](int j) {
        EmulatedLookup<Value> lookup(dims, shell, tolerance, directions, value);
        for (int i = 0; i < width; ++i) {
            const glm::dvec3 direction = pixelRayDirection(camera, width, height, i + 0.5, j + 0.5);
            const BoxPassage box = passBox(camera.eye, direction, shell);
            if (!box.seen) continue;
            // Signed distance to the diagonal plane x = y (prism A: >= 0) changes at this rate along the ray.
            const double diagonalRate = direction.x - direction.y;
            double tIn = box.tIn;
            glm::dvec3 in = camera.eye + tIn * direction;
            bool prismA = (in.x - in.y) > 0.0 || ((in.x - in.y) == 0.0 && diagonalRate >= 0.0);
            // At most two prisms: the ray crosses the diagonal plane once.
            for (int crossing = 0; crossing < 2; ++crossing) {
                double tOut = box.tOut;
                bool throughDiagonal = false;
                if (prismA ? diagonalRate < 0.0 : diagonalRate > 0.0) {
                    const double tDiagonal = tIn - (in.x - in.y) / diagonalRate;
                    if (tDiagonal < tOut) {
                        tOut = std::max(tDiagonal, tIn);
                        throughDiagonal = true;
                    }
                }
                const double dt = tOut - tIn;  // |T_out - T_in|: the direction is a unit vector
                const Lookup hit = lookup(in, direction);
                if (!hit.exit && hit.distance < dt) {
                    const glm::dvec3 point = in + hit.distance * direction;
                    const glm::dvec3 back = point - kShadowBackoffVoxels * voxel * direction;
                    const glm::dvec3 toLight = glm::normalize(light - point);
                    const bool lit = lookup(back, toLight, kShadowDropVoxels * voxel).exit;
                    detail::writeGdmHit(images, i, j, point, shell, lit);
                    break;
                }
                if (!throughDiagonal) break;
                tIn = tOut;
                in = camera.eye + tIn * direction;
                prismA = !prismA;
            }
        }
    });
    return images;
}

}  // namespace

Camera gdmSceneView(double degreesFromNormal) {
    const double a = degreesFromNormal * std::numbers::pi / 180.0;
    Camera camera;
    camera.eye = {0.5, 0.5 - 1.6 * std::sin(a), 1.6 * std::cos(a)};
    camera.target = {0.5, 0.5, 0.0};
    camera.fovYDegrees = 45.0;
    return camera;
}

void validateGdmPicture(int width, int height) {
    if (width < 1 || height < 1 || width > Image::kMaxDimension || height > Image::kMaxDimension)
        throw Error(ErrorKind::InvalidInput, "GDM scene: picture size " + std::to_string(width) + " x " +
                                                 std::to_string(height) + " is outside [1, " +
                                                 std::to_string(Image::kMaxDimension) + "]");
}

GdmSceneImages renderGdmReference(const SolidMesh& solid, const Camera& camera, glm::dvec3 light, int width,
                                  int height) {
    const std::string what = "GDM reference of " + solid.source;
    detail::checkGdmSceneInput(solid, camera, width, height, what);
    GdmSceneImages images = detail::blankGdmImages(width, height);
    if (solid.triangles.empty()) return images;
    EmbreeErrors errors;
    const PeriodicScene scene = buildScene(solid, what, errors);
    const double shell = solid.height;
    parallelFor(0, height, [&](int j) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int i = 0; i < width; ++i) {
            const glm::dvec3 direction = pixelRayDirection(camera, width, height, i + 0.5, j + 0.5);
            const SceneHit first = firstSceneHit(scene, context, camera.eye, direction, shell);
            if (!first.hit) continue;
            const glm::dvec3& point = first.point;
            const glm::dvec3& normal = first.normal;
            bool lit = false;
            const glm::dvec3 toLight = light - point;
            if (glm::dot(normal, toLight) > 0.0) {
                glm::dvec3 origin = point + kShadowOffset * normal;
                origin.z = std::clamp(origin.z, 0.0, shell);
                const double reach = glm::length(light - origin);
                const glm::dvec3 shadowDirection = (light - origin) / reach;
                const float blocker =
                    distanceAlong(scene, scene.scene.get(), context, wrapped(origin, shadowDirection, 0.0),
                                  shadowDirection, shell, 0.0);
                lit = double(blocker) >= reach;
            }
            detail::writeGdmHit(images, i, j, point, shell, lit);
        }
    });
    if (rtcGetDeviceError(scene.device.get()) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return images;
}

GdmSceneImages emulateGdm(const Gdm& gdm, const Camera& camera, glm::dvec3 light, int width, int height,
                          GdmDirectionLookup directions) {
    validateGdmDims(gdm.dims, gdm.height, "GDM emulation");
    if (gdm.values.size() != gdm.dims.valueCount())
        throw Error(ErrorKind::InvalidInput, "GDM emulation: " + std::to_string(gdm.values.size()) +
                                                 " values for dims needing " +
                                                 std::to_string(gdm.dims.valueCount()));
    const GdmDims& dims = gdm.dims;
    const double shell = gdm.height;
    // A miss reads as the distance to the slab's boundary, in float as the shader computes it.
    const auto value = [&](const shared::GdmLookupParams& p, int i, int j, int k, int t, int s) {
        const float d = gdm.at(i, j, k, t, s);
        return d == kGdmMiss ? shared::gdmBoundaryDistance(p, k, t) : d;
    };
    return emulate(dims, shell, 1e-4 * shell / dims.nz, value, camera, light, width, height, directions);
}

GdmSceneImages emulateGdm(const GdmSvd& svd, const Camera& camera, glm::dvec3 light, int width, int height,
                          GdmDirectionLookup directions) {
    validateGdmDims(svd.dims, svd.height, "GDM emulation");
    if (svd.weights.size() != svd.rows * std::size_t(svd.rank) ||
        svd.eigen.size() != svd.cols * std::size_t(svd.rank))
        throw Error(ErrorKind::InvalidInput,
                    "GDM emulation: SVD maps do not match rank " + std::to_string(svd.rank));
    const auto value = [&](const shared::GdmLookupParams&, int i, int j, int k, int t, int s) {
        return reconstruct(svd, i, j, k, t, s);
    };
    return emulate(svd.dims, svd.height, svd.exitTolerance, value, camera, light, width, height, directions);
}

GdmSceneAccuracy compareGdmScenes(const GdmSceneImages& reference, const GdmSceneImages& test,
                                  double shellHeight, double voxelLength) {
    if (reference.uvw.width() != test.uvw.width() || reference.uvw.height() != test.uvw.height())
        throw Error(ErrorKind::InvalidInput, "GDM scene comparison: the pictures' sizes differ");
    if (!(voxelLength > 0.0) || !(shellHeight > 0.0))
        throw Error(ErrorKind::InvalidInput, "GDM scene comparison: voxel length " +
                                                 formatNumber(voxelLength) + " and shell height " +
                                                 formatNumber(shellHeight) + " must be > 0");
    GdmSceneAccuracy result;
    result.voxelLength = voxelLength;
    const int width = reference.uvw.width();
    const int height = reference.uvw.height();
    std::size_t disagree = 0;
    std::size_t shadowAgree = 0;
    std::vector<double> errors;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            const bool hitRef = reference.mask.at(i, j) > 0.5f;
            const bool hitTest = test.mask.at(i, j) > 0.5f;
            if (hitRef != hitTest) ++disagree;
            if (!(hitRef && hitTest)) continue;
            const auto wrappedDifference = [](double a, double b) {
                const double d = a - b;
                return d - std::round(d);
            };
            const double du = wrappedDifference(reference.uvw.at(i, j, 0), test.uvw.at(i, j, 0));
            const double dv = wrappedDifference(reference.uvw.at(i, j, 1), test.uvw.at(i, j, 1));
            const double dz =
                (double(reference.uvw.at(i, j, 2)) - double(test.uvw.at(i, j, 2))) * shellHeight;
            errors.push_back(std::sqrt(du * du + dv * dv + dz * dz) / voxelLength);
            if ((reference.shadow.at(i, j) > 0.5f) == (test.shadow.at(i, j) > 0.5f)) ++shadowAgree;
        }
    const double pixels = double(width) * double(height);
    result.hitMissDisagreePercent = 100.0 * double(disagree) / pixels;
    result.bothHitPixels = errors.size();
    if (!errors.empty()) {
        double sum = 0.0;
        for (const double e : errors) sum += e;
        result.uvwMeanVoxels = sum / double(errors.size());
        std::sort(errors.begin(), errors.end());
        const auto percentile = [&](double p) {
            const auto index = std::size_t(std::ceil(p * double(errors.size()))) - 1;
            return errors[std::min(index, errors.size() - 1)];
        };
        result.uvwP95Voxels = percentile(0.95);
        result.uvwP99Voxels = percentile(0.99);
        result.shadowAgreePercent = 100.0 * double(shadowAgree) / double(errors.size());
    }
    return result;
}

}  // namespace strata
