#include "strata/gdm/gdm_bake.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace strata {
namespace {

// The scene holds every translate of the mesh that reaches into the column [-kReach, 1 + kReach]^2 around
// the tile; a ray is traced in it until it leaves that column, then moved back by whole tiles (its origin
// lands half a tile inside) and traced on. A wider column means fewer restarts and more triangles.
constexpr double kReach = 0.5;
// Triangles within this distance of the column are kept too, so that a segment may run a little past the
// column's side (kSegmentOverlap) and still see every face there.
constexpr double kCullMargin = 1e-3;
constexpr double kSegmentOverlap = 1e-5;

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

struct DeviceRelease {
    void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};
struct SceneRelease {
    void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
using DeviceHandle = std::unique_ptr<RTCDeviceTy, DeviceRelease>;
using SceneHandle = std::unique_ptr<RTCSceneTy, SceneRelease>;

// The first message Embree reported, for the Error thrown after the call that failed.
struct EmbreeErrors {
    std::mutex mutex;
    std::string first;
};

void onEmbreeError(void* userPtr, RTCError code, const char* message) {
    auto* errors = static_cast<EmbreeErrors*>(userPtr);
    const std::lock_guard lock(errors->mutex);
    if (errors->first.empty())
        errors->first =
            "Embree error " + std::to_string(int(code)) + (message ? std::string(": ") + message : "");
}

// The periodic solid as one Embree scene (see kReach), with its triangles' outward normals for the
// inside test.
struct PeriodicScene {
    DeviceHandle device;
    SceneHandle scene;
    std::vector<glm::vec3> normals;  // per scene triangle, unnormalised, pointing out of the solid
    float zMin = 0.0f;
    float zMax = 0.0f;
};

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

PeriodicScene buildScene(const SolidMesh& solid, const std::string& what, EmbreeErrors& errors) {
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

    result.scene.reset(rtcNewScene(result.device.get()));
    if (!result.scene) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    // Robust: Embree's watertight triangle test, so that a ray through a shared edge is not lost between
    // the two triangles. The context filter is the inside test's crossing counter.
    rtcSetSceneFlags(result.scene.get(), RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(result.scene.get(), RTC_BUILD_QUALITY_MEDIUM);
    if (!triangles.empty()) {
        RTCGeometry geometry = rtcNewGeometry(result.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        if (!geometry) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
        // Embree reads 16 bytes at the last vertex: one float of padding.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size() + 1));
        auto* indices = static_cast<std::uint32_t*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(std::uint32_t), triangles.size()));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geometry);
            throw Error(ErrorKind::Runtime, what + ": " + errors.first);
        }
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
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(result.scene.get());
    if (rtcGetDeviceError(result.device.get()) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return result;
}

// Distance along `direction` from `origin` to where the ray leaves the column [-kReach, 1 + kReach]^2.
double columnExit(const glm::dvec3& origin, const glm::dvec3& direction) {
    double t = std::numeric_limits<double>::infinity();
    if (direction.x > 0.0) t = std::min(t, (1.0 + kReach - origin.x) / direction.x);
    if (direction.x < 0.0) t = std::min(t, (-kReach - origin.x) / direction.x);
    if (direction.y > 0.0) t = std::min(t, (1.0 + kReach - origin.y) / direction.y);
    if (direction.y < 0.0) t = std::min(t, (-kReach - origin.y) / direction.y);
    return t;
}

// Distance along `direction` from `origin` to where the ray leaves zLo <= z <= zHi.
double slabExit(const glm::dvec3& origin, const glm::dvec3& direction, double zLo, double zHi) {
    if (direction.z > 0.0) return (zHi - origin.z) / direction.z;
    if (direction.z < 0.0) return (zLo - origin.z) / direction.z;
    return std::numeric_limits<double>::infinity();
}

// The point at `t` along the ray, moved by whole tiles so that its u, v lie in [0, 1).
glm::dvec3 wrapped(const glm::dvec3& origin, const glm::dvec3& direction, double t) {
    glm::dvec3 point = origin + t * direction;
    point.x -= std::floor(point.x);
    point.y -= std::floor(point.y);
    return point;
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

bool insideSolid(const PeriodicScene& scene, const glm::dvec3& point) {
    if (point.z < double(scene.zMin) || point.z > double(scene.zMax)) return false;
    int votes = 0;
    for (const auto& ray : kInsideRays)
        if (windingAlong(scene, point, glm::normalize(glm::dvec3(ray[0], ray[1], ray[2]))) >= 1) ++votes;
    return 2 * votes > int(kInsideRays.size());
}

// Beyond the mesh's z range, heading away from it: the ray can meet nothing more.
bool leavesMesh(const PeriodicScene& scene, const glm::dvec3& origin, const glm::dvec3& direction) {
    return (direction.z >= 0.0 && origin.z > double(scene.zMax)) ||
           (direction.z <= 0.0 && origin.z < double(scene.zMin));
}

// One segment of a distance ray: from `origin` until it leaves the slab, the column (see kReach) or has run
// the rest of kGdmBakeMaxTravel. `tColumn` is where it leaves the column, or < 0 where the segment is the
// ray's last.
struct Segment {
    float tFar;
    double tColumn;
};

Segment segment(const glm::dvec3& origin, const glm::dvec3& direction, double height, double travelled) {
    const double tLast = std::min(slabExit(origin, direction, 0.0, height), kGdmBakeMaxTravel - travelled);
    const double tColumn = columnExit(origin, direction);
    if (tLast <= tColumn) return {float(tLast), -1.0};
    return {float(tColumn + kSegmentOverlap), tColumn};
}

// The distance of §8 from `origin` (u, v in [0, 1)) along unit `direction`, the ray having come
// `travelled` already: traced segment by segment, moved back by whole tiles each time it leaves the column,
// until it meets a face (the distance), leaves the slab or the mesh's z range for good, or has run
// kGdmBakeMaxTravel (kGdmMiss).
float distanceAlong(const PeriodicScene& scene, RTCIntersectContext& context, glm::dvec3 origin,
                    const glm::dvec3& direction, double height, double travelled) {
    const glm::vec3 directionF(direction);
    for (;;) {
        if (leavesMesh(scene, origin, direction)) return kGdmMiss;
        const Segment next = segment(origin, direction, height, travelled);
        RTCRayHit rayHit;
        setRay(rayHit, origin, directionF, next.tFar);
        rtcIntersect1(scene.scene.get(), &context, &rayHit);
        if (rayHit.hit.geomID != RTC_INVALID_GEOMETRY_ID) return float(travelled + double(rayHit.ray.tfar));
        if (next.tColumn < 0.0) return kGdmMiss;
        origin = wrapped(origin, direction, next.tColumn);
        travelled += next.tColumn;
    }
}

// The direction samples in packets of 16 neighbours: blocks of 4 x 4 (theta, phi) samples, padded with -1
// where a block runs past the grid.
constexpr int kPacketWidth = 16;
constexpr int kPacketThetas = 4;

std::vector<int> packetOrder(const GdmDims& dims) {
    constexpr int phis = kPacketWidth / kPacketThetas;
    std::vector<int> order;
    for (int t0 = 0; t0 < dims.ntheta; t0 += kPacketThetas)
        for (int s0 = 0; s0 < dims.nphi; s0 += phis)
            for (int lane = 0; lane < kPacketWidth; ++lane) {
                const int t = t0 + lane / phis;
                const int s = s0 + lane % phis;
                order.push_back(t < dims.ntheta && s < dims.nphi ? t * dims.nphi + s : -1);
            }
    return order;
}

// The distances from `origin` along the 16 directions directions[lanes[n]] (lanes[n] < 0: none) into
// values[lanes[n]]. Rays from one point in neighbouring directions visit mostly the same nodes: their first
// segments go to Embree as one packet, and the few that go on past the column continue one by one.
void tracePacket(const PeriodicScene& scene, RTCIntersectContext& context, const glm::dvec3& origin,
                 const int* lanes, const std::vector<glm::dvec3>& directions, double height, float* values) {
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[kPacketWidth];
    double tColumn[kPacketWidth];
    bool any = false;
    for (int n = 0; n < kPacketWidth; ++n) {
        valid[n] = 0;
        if (lanes[n] < 0) continue;
        const glm::dvec3& direction = directions[std::size_t(lanes[n])];
        values[lanes[n]] = kGdmMiss;
        if (leavesMesh(scene, origin, direction)) continue;
        const Segment first = segment(origin, direction, height, 0.0);
        valid[n] = -1;
        any = true;
        tColumn[n] = first.tColumn;
        packet.ray.org_x[n] = float(origin.x);
        packet.ray.org_y[n] = float(origin.y);
        packet.ray.org_z[n] = float(origin.z);
        packet.ray.tnear[n] = 0.0f;
        packet.ray.dir_x[n] = float(direction.x);
        packet.ray.dir_y[n] = float(direction.y);
        packet.ray.dir_z[n] = float(direction.z);
        packet.ray.time[n] = 0.0f;
        packet.ray.tfar[n] = first.tFar;
        packet.ray.mask[n] = ~0u;
        packet.ray.id[n] = 0;
        packet.ray.flags[n] = 0;
        packet.hit.geomID[n] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][n] = RTC_INVALID_GEOMETRY_ID;
    }
    if (!any) return;
    rtcIntersect16(valid, scene.scene.get(), &context, &packet);
    for (int n = 0; n < kPacketWidth; ++n) {
        if (valid[n] == 0) continue;
        if (packet.hit.geomID[n] != RTC_INVALID_GEOMETRY_ID)
            values[lanes[n]] = packet.ray.tfar[n];
        else if (tColumn[n] >= 0.0) {
            const glm::dvec3& direction = directions[std::size_t(lanes[n])];
            values[lanes[n]] = distanceAlong(scene, context, wrapped(origin, direction, tColumn[n]),
                                             direction, height, tColumn[n]);
        }
    }
}

}  // namespace

Gdm bakeGdm(const SolidMesh& solid, const GdmDims& dims, const GdmBakeProgress& progress) {
    const std::string what = "GDM bake of " + solid.source;
    validateGdmDims(dims, solid.height, what);
    checkMesh(solid, what);

    Gdm gdm;
    gdm.dims = dims;
    gdm.height = solid.height;
    gdm.values.assign(dims.valueCount(), kGdmMiss);
    if (solid.triangles.empty()) {
        if (progress) progress(1.0);
        return gdm;
    }

    EmbreeErrors errors;
    const PeriodicScene scene = buildScene(solid, what, errors);
    const double height = solid.height;
    const int directionCount = int(dims.directionCount());
    std::vector<glm::dvec3> directions(static_cast<std::size_t>(directionCount));
    for (int t = 0; t < dims.ntheta; ++t)
        for (int s = 0; s < dims.nphi; ++s)
            directions[std::size_t(t * dims.nphi + s)] = gdmDirection(dims, t, s);
    const std::vector<int> order = packetOrder(dims);

    const std::int64_t rowCount = std::int64_t(dims.ny) * dims.nz;
    std::mutex progressMutex;
    std::int64_t rowsDone = 0;
    parallelFor(std::int64_t(0), rowCount, [&](std::int64_t row) {
        const int j = int(row % dims.ny);
        const int k = int(row / dims.ny);
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int i = 0; i < dims.nx; ++i) {
            const glm::dvec3 centre = gdmVoxelCentre(dims, height, i, j, k);
            float* values = gdm.values.data() + gdm.valueIndex(i, j, k, 0, 0);
            // Inside: 0 in every direction, and no ray cast.
            if (insideSolid(scene, centre)) {
                std::fill_n(values, directionCount, 0.0f);
                continue;
            }
            for (std::size_t first = 0; first < order.size(); first += kPacketWidth)
                tracePacket(scene, context, centre, order.data() + first, directions, height, values);
        }
        if (progress) {
            const std::lock_guard lock(progressMutex);
            ++rowsDone;
            progress(double(rowsDone) / double(rowCount));
        }
    });
    if (rtcGetDeviceError(scene.device.get()) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return gdm;
}

}  // namespace strata
