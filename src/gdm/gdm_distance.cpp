#include "strata/gdm/gdm_distance.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include "periodic_scene.h"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace strata {
namespace {

using namespace detail;

static_assert(kGdmDistanceReach <= kReach, "the periodic scene holds every face within kReach of the tile");

// The closest point to p on the triangle (a, b, c) (Ericson, "Real-Time Collision Detection", 5.1.5).
glm::dvec3 closestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c) {
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
        return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
    const double denominator = 1.0 / (va + vb + vc);
    return a + ab * (vb * denominator) + ac * (vc * denominator);
}

// What the point query's callback reads and keeps: the scene's buffers, the query point in double, and the
// nearest distance so far.
struct NearestFace {
    const float* vertices = nullptr;
    const std::uint32_t* indices = nullptr;
    glm::dvec3 point{0.0};
    double distance = 0.0;
};

bool visitTriangle(RTCPointQueryFunctionArguments* args) {
    auto* nearest = static_cast<NearestFace*>(args->userPtr);
    const std::uint32_t* triangle = nearest->indices + 3 * std::size_t(args->primID);
    glm::dvec3 corners[3];
    for (int c = 0; c < 3; ++c) {
        const float* v = nearest->vertices + 3 * std::size_t(triangle[c]);
        corners[c] = glm::dvec3(v[0], v[1], v[2]);
    }
    const double distance =
        glm::length(nearest->point - closestOnTriangle(nearest->point, corners[0], corners[1], corners[2]));
    if (distance >= nearest->distance) return false;
    nearest->distance = distance;
    // Shrinking the query's radius prunes the rest of the search (Embree's closest-point tutorial).
    args->query->radius = float(distance);
    return true;
}

}  // namespace

std::vector<float> bakeGdmDistance(const SolidMesh& solid, const GdmDims& dims) {
    const std::string what = "GDM distance of " + solid.source;
    validateGdmDims(dims, solid.height, what);
    checkMesh(solid, what);
    std::vector<float> distance(dims.voxelCount(), float(kGdmDistanceReach));
    if (solid.triangles.empty()) return distance;

    EmbreeErrors errors;
    // The bake's scene and inside test (SceneTest::Fast, as bakeGdm's), so that the sign agrees with the
    // bake's occupancy voxel for voxel.
    const PeriodicScene scene = buildScene(solid, what, errors, SceneTest::Fast);
    RTCGeometry geometry = scene.geometry.get();
    const auto* vertices =
        static_cast<const float*>(rtcGetGeometryBufferData(geometry, RTC_BUFFER_TYPE_VERTEX, 0));
    const auto* indices =
        static_cast<const std::uint32_t*>(rtcGetGeometryBufferData(geometry, RTC_BUFFER_TYPE_INDEX, 0));
    if (!vertices || !indices) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    const double height = solid.height;
    const std::int64_t rowCount = std::int64_t(dims.ny) * dims.nz;
    parallelFor(std::int64_t(0), rowCount, [&](std::int64_t row) {
        const int j = int(row % dims.ny);
        const int k = int(row / dims.ny);
        for (int i = 0; i < dims.nx; ++i) {
            const glm::dvec3 centre = gdmVoxelCentre(dims, height, i, j, k);
            NearestFace nearest{vertices, indices, centre, kGdmDistanceReach};
            RTCPointQuery query;
            query.x = float(centre.x);
            query.y = float(centre.y);
            query.z = float(centre.z);
            query.time = 0.0f;
            query.radius = float(kGdmDistanceReach);
            RTCPointQueryContext context;
            rtcInitPointQueryContext(&context);
            rtcPointQuery(scene.scene.get(), &query, &context, visitTriangle, &nearest);
            double value = nearest.distance;
            // Inside: the nearer of the mesh's surface and the slab's cut faces (exact, see the header).
            if (insideSolid(scene, centre)) value = std::max({-value, -centre.z, centre.z - height});
            distance[(std::size_t(k) * std::size_t(dims.ny) + std::size_t(j)) * std::size_t(dims.nx) +
                     std::size_t(i)] = float(value);
        }
    });
    if (rtcGetDeviceError(scene.device.get()) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return distance;
}

}  // namespace strata
