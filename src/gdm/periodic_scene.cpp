#include "periodic_scene.h"

#include "strata/core/error.h"
#include "strata/gdm/gdm_bake.h"

#include <glm/geometric.hpp>

#include <cstdint>

namespace strata::detail {
namespace {

// The inside test's rays: near vertical (they leave the mesh's z range after a short run), tilted by
// irrational-looking amounts so that the voxel grid's regular positions do not line them up with edges,
// alternately up and down. An odd count, for a majority.
constexpr std::array<std::array<double, 3>, 5> kInsideRays = {{
    {0.0731, 0.0419, 1.0},
    {-0.0557, 0.0683, -1.0},
    {0.0397, -0.0811, 1.0},
    {-0.0613, -0.0347, -1.0},
    {0.0859, -0.0271, -1.0},
}};

}  // namespace

void checkMesh(const SolidMesh& solid, const std::string& what) {
    for (std::size_t p = 0; p < solid.positions.size(); ++p) {
        const glm::vec3& position = solid.positions[p];
        if (!(std::isfinite(position.x) && std::isfinite(position.y) && std::isfinite(position.z)))
            throw Error(ErrorKind::InvalidInput, what + ": position " + std::to_string(p) +
                                                     " is not finite (" + formatNumber(position.x) + ", " +
                                                     formatNumber(position.y) + ", " +
                                                     formatNumber(position.z) + ")");
    }
    for (std::size_t t = 0; t < solid.triangles.size(); ++t)
        for (const std::uint32_t index : solid.triangles[t])
            if (index >= solid.positions.size())
                throw Error(ErrorKind::InvalidInput, what + ": triangle " + std::to_string(t) +
                                                         " refers to position " + std::to_string(index) +
                                                         " of " + std::to_string(solid.positions.size()));
}

PeriodicScene buildScene(const SolidMesh& solid, const std::string& what, EmbreeErrors& errors,
                         SceneTest test) {
    PeriodicScene result;
    result.device.reset(rtcNewDevice(nullptr));
    if (!result.device)
        throw Error(ErrorKind::Runtime, what + ": Embree could not start (error " +
                                            std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(result.device.get(), onEmbreeError, &errors);

    glm::vec3 lo(std::numeric_limits<float>::max());
    glm::vec3 hi(std::numeric_limits<float>::lowest());
    for (const glm::vec3& position : solid.positions) {
        lo = glm::min(lo, position);
        hi = glm::max(hi, position);
    }
    result.zMin = lo.z;
    result.zMax = hi.z;

    // Every translate (i, j) whose triangles can reach into the column, each triangle kept when its
    // bounding box does.
    const double columnLo = -kReach - kCullMargin;
    const double columnHi = 1.0 + kReach + kCullMargin;
    const int iFirst = int(std::floor(columnLo - double(hi.x)));
    const int iLast = int(std::ceil(columnHi - double(lo.x)));
    const int jFirst = int(std::floor(columnLo - double(hi.y)));
    const int jLast = int(std::ceil(columnHi - double(lo.y)));
    std::vector<glm::vec3> positions;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (int j = jFirst; j <= jLast; ++j)
        for (int i = iFirst; i <= iLast; ++i) {
            const glm::vec3 shift(float(i), float(j), 0.0f);
            const auto base = std::uint32_t(positions.size());
            bool any = false;
            for (const auto& triangle : solid.triangles) {
                const glm::vec3 a = solid.positions[triangle[0]] + shift;
                const glm::vec3 b = solid.positions[triangle[1]] + shift;
                const glm::vec3 c = solid.positions[triangle[2]] + shift;
                const glm::vec3 tLo = glm::min(a, glm::min(b, c));
                const glm::vec3 tHi = glm::max(a, glm::max(b, c));
                if (double(tHi.x) < columnLo || double(tLo.x) > columnHi || double(tHi.y) < columnLo ||
                    double(tLo.y) > columnHi)
                    continue;
                triangles.push_back({base + triangle[0], base + triangle[1], base + triangle[2]});
                result.normals.push_back(glm::cross(b - a, c - a));
                any = true;
            }
            if (any)
                for (const glm::vec3& position : solid.positions) positions.push_back(position + shift);
        }

    result.watertight =
        test == SceneTest::Watertight || lo.z < 0.0f || double(hi.z) > solid.height || triangles.empty();
    result.scene.reset(rtcNewScene(result.device.get()));
    if (!result.scene) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    // The context filter is the inside test's crossing counter.
    rtcSetSceneFlags(result.scene.get(), (result.watertight ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
                                             RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(result.scene.get(), RTC_BUILD_QUALITY_MEDIUM);
    if (!triangles.empty()) {
        result.geometry.reset(rtcNewGeometry(result.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
        if (!result.geometry) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
        RTCGeometry geometry = result.geometry.get();
        // Embree reads 16 bytes at the last vertex: one float of padding.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size() + 1));
        auto* indices = static_cast<std::uint32_t*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(std::uint32_t), triangles.size()));
        if (!vertices || !indices) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
        for (std::size_t p = 0; p < positions.size(); ++p) {
            vertices[3 * p + 0] = positions[p].x;
            vertices[3 * p + 1] = positions[p].y;
            vertices[3 * p + 2] = positions[p].z;
        }
        vertices[3 * positions.size() + 0] = vertices[3 * positions.size() + 1] =
            vertices[3 * positions.size() + 2] = 0.0f;
        for (std::size_t t = 0; t < triangles.size(); ++t)
            for (int corner = 0; corner < 3; ++corner) indices[3 * t + corner] = triangles[t][corner];
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(result.scene.get(), geometry);
    }
    rtcCommitScene(result.scene.get());
    if (rtcGetDeviceError(result.device.get()) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return result;
}

RTCScene PeriodicScene::robust() const {
    if (watertight) return scene.get();
    std::call_once(lazy_->once, [&] {
        SceneHandle built(rtcNewScene(device.get()));
        if (!built) return;
        rtcSetSceneFlags(built.get(), RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(built.get(), RTC_BUILD_QUALITY_MEDIUM);
        rtcAttachGeometry(built.get(), geometry.get());
        rtcCommitScene(built.get());
        if (rtcGetDeviceError(device.get()) == RTC_ERROR_NONE) lazy_->scene = std::move(built);
    });
    if (!lazy_->scene) throw Error(ErrorKind::Runtime, "Embree could not build the watertight scene");
    return lazy_->scene.get();
}

void setRay(RTCRayHit& rayHit, const glm::dvec3& origin, const glm::vec3& direction, double tFar) {
    RTCRay& ray = rayHit.ray;
    ray.org_x = float(origin.x);
    ray.org_y = float(origin.y);
    ray.org_z = float(origin.z);
    ray.tnear = 0.0f;
    ray.dir_x = direction.x;
    ray.dir_y = direction.y;
    ray.dir_z = direction.z;
    ray.time = 0.0f;
    ray.tfar = float(tFar);
    ray.mask = ~0u;
    ray.id = 0;
    ray.flags = 0;
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

namespace {

// The inside test's crossing counter: an Embree context filter that counts every face along the segment
// (rejecting each hit, so that traversal goes on) and sums +1 for a face the ray leaves the solid through,
// -1 for one it enters through. Faces at or past `tLimit` belong to the next segment.
struct WindingContext {
    RTCIntersectContext context;  // first: Embree hands the filter a pointer to it
    const PeriodicScene* scene = nullptr;
    float tLimit = 0.0f;
    int winding = 0;
    // A primitive that Embree reports twice (duplicated references) is counted once.
    std::array<unsigned, 64> seen{};
    int seenCount = 0;
};

void countCrossing(const RTCFilterFunctionNArguments* args) {
    auto* winding = reinterpret_cast<WindingContext*>(args->context);
    for (unsigned n = 0; n < args->N; ++n) {
        if (args->valid[n] == 0) continue;
        args->valid[n] = 0;
        if (RTCRayN_tfar(args->ray, args->N, n) >= winding->tLimit) continue;
        const unsigned prim = RTCHitN_primID(args->hit, args->N, n);
        const auto seenEnd = winding->seen.begin() + winding->seenCount;
        if (std::find(winding->seen.begin(), seenEnd, prim) != seenEnd) continue;
        if (winding->seenCount < int(winding->seen.size())) winding->seen[winding->seenCount++] = prim;
        const glm::vec3& normal = winding->scene->normals[prim];
        const float along = normal.x * RTCRayN_dir_x(args->ray, args->N, n) +
                            normal.y * RTCRayN_dir_y(args->ray, args->N, n) +
                            normal.z * RTCRayN_dir_z(args->ray, args->N, n);
        if (along > 0.0f) ++winding->winding;
        if (along < 0.0f) --winding->winding;
    }
}

// The winding number of the periodic mesh at `point`, counted along one ray until it leaves the mesh's z
// range.
int windingAlong(const PeriodicScene& scene, glm::dvec3 origin, const glm::dvec3& direction) {
    const glm::vec3 directionF(direction);
    // Run a little past the mesh's z range, so that a face lying in its top or bottom plane is crossed.
    const double zLo = double(scene.zMin) - 1e-3;
    const double zHi = double(scene.zMax) + 1e-3;
    int total = 0;
    for (double travelled = 0.0; travelled < kGdmBakeMaxTravel;) {
        const double tSlab = slabExit(origin, direction, zLo, zHi);
        const double tColumn = columnExit(origin, direction);
        const double tEnd = std::min(tSlab, tColumn);
        WindingContext context;
        rtcInitIntersectContext(&context.context);
        context.context.filter = countCrossing;
        context.scene = &scene;
        context.tLimit = tSlab <= tColumn ? std::numeric_limits<float>::infinity() : float(tColumn);
        RTCRayHit rayHit;
        setRay(rayHit, origin, directionF, tEnd + kSegmentOverlap);
        rtcIntersect1(scene.scene.get(), &context.context, &rayHit);
        total += context.winding;
        if (tSlab <= tColumn) break;
        origin = wrapped(origin, direction, tColumn);
        travelled += tColumn;
    }
    return total;
}

}  // namespace

bool insideSolid(const PeriodicScene& scene, const glm::dvec3& point) {
    if (point.z < double(scene.zMin) || point.z > double(scene.zMax)) return false;
    // Stops as soon as the majority is settled (3 of 5 either way).
    constexpr int kCount = int(kInsideRays.size());
    int inside = 0, outside = 0;
    for (const auto& ray : kInsideRays) {
        if (windingAlong(scene, point, glm::normalize(glm::dvec3(ray[0], ray[1], ray[2]))) >= 1)
            ++inside;
        else
            ++outside;
        if (2 * inside > kCount) return true;
        if (2 * outside > kCount) return false;
    }
    return false;
}

float distanceAlong(const PeriodicScene& scene, RTCScene target, RTCIntersectContext& context,
                    glm::dvec3 origin, const glm::dvec3& direction, double height, double travelled,
                    unsigned* primitive) {
    const glm::vec3 directionF(direction);
    for (;;) {
        if (leavesMesh(scene, origin, direction)) return kGdmMiss;
        const Segment next = segment(scene, origin, direction, height, travelled);
        RTCRayHit rayHit;
        setRay(rayHit, origin, directionF, next.tFar);
        rtcIntersect1(target, &context, &rayHit);
        if (rayHit.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
            if (primitive) *primitive = rayHit.hit.primID;
            return float(travelled + double(rayHit.ray.tfar));
        }
        if (next.tColumn < 0.0) return kGdmMiss;
        origin = wrapped(origin, direction, next.tColumn);
        travelled += next.tColumn;
    }
}

}  // namespace strata::detail
