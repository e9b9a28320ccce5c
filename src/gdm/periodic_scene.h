// The periodic solid of a mesostructure (CONVENTIONS §8) as one Embree scene, and the wrapped ray walk in
// it: the one tracer that the GDM bake (gdm_bake.cpp) and the exact reference of the GDM verification scene
// (gdm_trace.cpp) share. Internal to strata::gdm.
#pragma once

#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/solid_mesh.h"

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace strata::detail {

// The scene holds every translate of the mesh that reaches into the column [-kReach, 1 + kReach]^2 around
// the tile; a ray is traced in it until it leaves that column, then moved back by whole tiles (its origin
// lands kReach inside the tile, so every later segment runs at least 2 kReach) and traced on. A wider
// column means fewer restarts and more triangles (docs/gdm.md: 0.2 bakes fastest).
inline constexpr double kReach = 0.2;
// Triangles within this distance of the column are kept too, so that a segment may run a little past the
// column's side (kSegmentOverlap) and still see every face there.
inline constexpr double kCullMargin = 1e-3;
inline constexpr double kSegmentOverlap = 1e-5;

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

inline void onEmbreeError(void* userPtr, RTCError code, const char* message) {
    auto* errors = static_cast<EmbreeErrors*>(userPtr);
    const std::lock_guard lock(errors->mutex);
    if (errors->first.empty())
        errors->first =
            "Embree error " + std::to_string(int(code)) + (message ? std::string(": ") + message : "");
}

struct GeometryRelease {
    void operator()(RTCGeometry geometry) const { rtcReleaseGeometry(geometry); }
};
using GeometryHandle = std::unique_ptr<RTCGeometryTy, GeometryRelease>;

// How buildScene makes the scene that its rays are cast in.
enum class SceneTest {
    // Embree's watertight triangle test (RTC_SCENE_FLAG_ROBUST): a ray through an edge shared by two
    // triangles meets one of them. The exact reference's.
    Watertight,
    // Embree's faster test, which is not watertight: a ray through a shared edge may slip between the two
    // triangles (a crack). The bake's: the inside test is a majority of 5 rays, so one ray through a crack
    // is outvoted; and a distance ray from outside the solid can only first meet a face that it enters the
    // solid through, so a first hit on a face that it leaves through shows that it slipped through a crack,
    // and the bake traces it again in robust() (gdm_bake.cpp). That check needs every face inside the slab
    // (a ray that slips in must meet a face on its way out), so a mesh that reaches outside
    // 0 <= z <= H (the slab clips it) gets the watertight test anyway.
    Fast,
};

// The periodic solid as an Embree scene (see kReach), with its triangles' outward normals for the inside
// test.
struct PeriodicScene {
    DeviceHandle device;
    GeometryHandle geometry;  // the triangles, attached to `scene` (and to robust())
    SceneHandle scene;        // watertight unless built with SceneTest::Fast
    bool watertight = true;
    std::vector<glm::vec3> normals;  // per scene triangle, unnormalised, pointing out of the solid
    float zMin = 0.0f;
    float zMax = 0.0f;

    // A watertight scene of the same triangles: `scene` itself if it is, else one built on first use
    // (thread-safe). Throws Error(Runtime) if Embree fails to build it.
    RTCScene robust() const;

private:
    struct Lazy {
        std::once_flag once;
        SceneHandle scene;
    };
    std::unique_ptr<Lazy> lazy_ = std::make_unique<Lazy>();
};

// Throws Error(InvalidInput) naming `what` for a position that is not finite or an index out of range.
void checkMesh(const SolidMesh& solid, const std::string& what);

// The scene of every translate of `solid` that reaches into the column (see kReach), with the triangle test
// `test`. Embree's errors go to `errors`, which must outlive the scene. Throws Error(Runtime) if Embree
// fails.
PeriodicScene buildScene(const SolidMesh& solid, const std::string& what, EmbreeErrors& errors,
                         SceneTest test = SceneTest::Watertight);

// Distance along `direction` from `origin` to where the ray leaves the column [-kReach, 1 + kReach]^2.
inline double columnExit(const glm::dvec3& origin, const glm::dvec3& direction) {
    double t = std::numeric_limits<double>::infinity();
    if (direction.x > 0.0) t = std::min(t, (1.0 + kReach - origin.x) / direction.x);
    if (direction.x < 0.0) t = std::min(t, (-kReach - origin.x) / direction.x);
    if (direction.y > 0.0) t = std::min(t, (1.0 + kReach - origin.y) / direction.y);
    if (direction.y < 0.0) t = std::min(t, (-kReach - origin.y) / direction.y);
    return t;
}

// Distance along `direction` from `origin` to where the ray leaves zLo <= z <= zHi.
inline double slabExit(const glm::dvec3& origin, const glm::dvec3& direction, double zLo, double zHi) {
    if (direction.z > 0.0) return (zHi - origin.z) / direction.z;
    if (direction.z < 0.0) return (zLo - origin.z) / direction.z;
    return std::numeric_limits<double>::infinity();
}

// The point at `t` along the ray, moved by whole tiles so that its u, v lie in [0, 1).
inline glm::dvec3 wrapped(const glm::dvec3& origin, const glm::dvec3& direction, double t) {
    glm::dvec3 point = origin + t * direction;
    point.x -= std::floor(point.x);
    point.y -= std::floor(point.y);
    return point;
}

void setRay(RTCRayHit& rayHit, const glm::dvec3& origin, const glm::vec3& direction, double tFar);

// True where `point` lies inside the periodic solid (a majority of 5 winding counts is >= 1, gdm_bake.h).
bool insideSolid(const PeriodicScene& scene, const glm::dvec3& point);

// Beyond the mesh's z range, heading away from it: the ray can meet nothing more.
inline bool leavesMesh(const PeriodicScene& scene, const glm::dvec3& origin, const glm::dvec3& direction) {
    return (direction.z >= 0.0 && origin.z > double(scene.zMax)) ||
           (direction.z <= 0.0 && origin.z < double(scene.zMin));
}

// One segment of a distance ray: from `origin` until it leaves the slab, the column (see kReach) or has run
// the rest of kGdmBakeMaxTravel. `tColumn` is where it leaves the column, or < 0 where the segment is the
// ray's last. The slab is cut down to the mesh's z range (and a margin): no face lies beyond it, so a ray
// that gets there is a miss, and Embree need not walk the rest of it.
struct Segment {
    float tFar;
    double tColumn;
};

// The z range a segment may run in: the slab 0 <= z <= height cut down to the mesh's z range and a margin.
struct SegmentRange {
    double zLo;
    double zHi;
};
inline SegmentRange segmentRange(const PeriodicScene& scene, double height) {
    const double margin = 1e-4 * height;
    return {std::max(0.0, double(scene.zMin) - margin), std::min(height, double(scene.zMax) + margin)};
}

inline Segment segment(const SegmentRange& range, const glm::dvec3& origin, const glm::dvec3& direction,
                       double travelled) {
    const double tLast =
        std::min(slabExit(origin, direction, range.zLo, range.zHi), kGdmBakeMaxTravel - travelled);
    const double tColumn = columnExit(origin, direction);
    if (tLast <= tColumn) return {float(std::max(tLast, 0.0)), -1.0};
    return {float(tColumn + kSegmentOverlap), tColumn};
}
inline Segment segment(const PeriodicScene& scene, const glm::dvec3& origin, const glm::dvec3& direction,
                       double height, double travelled) {
    return segment(segmentRange(scene, height), origin, direction, travelled);
}

// The distance of §8 from `origin` (u, v in [0, 1)) along unit `direction`, the ray having come
// `travelled` already: traced segment by segment, moved back by whole tiles each time it leaves the column,
// until it meets a face (the distance), leaves the slab 0 <= z <= height or the mesh's z range for good, or
// has run kGdmBakeMaxTravel (kGdmMiss). Where it meets a face and `primitive` is given, *primitive is the
// face's index into scene.normals. Cast in `target`: scene.scene, or scene.robust().
float distanceAlong(const PeriodicScene& scene, RTCScene target, RTCIntersectContext& context,
                    glm::dvec3 origin, const glm::dvec3& direction, double height, double travelled,
                    unsigned* primitive = nullptr);

}  // namespace strata::detail
