#include "strata/gdm/gdm_bake.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include "periodic_scene.h"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace strata {
namespace {

using namespace detail;

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

// The distances from `origin` (outside the solid) along the 16 directions directions[lanes[n]]
// (lanes[n] < 0: none) into values[lanes[n]]. Rays from one point in neighbouring directions visit mostly
// the same nodes, so they go to Embree as one packet, segment by segment: the lanes that leave the column
// without a hit are moved back by whole tiles (periodic_scene.h) and traced on together, until every lane
// has hit or left the slab. A lane whose hit shows that it slipped through a crack of a scene built with
// SceneTest::Fast (a face it leaves the solid through) is traced again in the watertight scene.
void tracePacket(const PeriodicScene& scene, RTCIntersectContext& context, const glm::dvec3& origin,
                 const int* lanes, const std::vector<glm::dvec3>& directions, double height, float* values) {
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[kPacketWidth];
    glm::dvec3 start[kPacketWidth];  // each lane's current segment's origin
    double travelled[kPacketWidth];  // how far each lane's ray has come before that segment
    double tColumn[kPacketWidth];
    const SegmentRange range = segmentRange(scene, height);
    bool any = false;
    for (int n = 0; n < kPacketWidth; ++n) {
        valid[n] = 0;
        if (lanes[n] < 0) continue;
        values[lanes[n]] = kGdmMiss;
        if (leavesMesh(scene, origin, directions[std::size_t(lanes[n])])) continue;
        valid[n] = -1;
        any = true;
        start[n] = origin;
        travelled[n] = 0.0;
    }
    while (any) {
        for (int n = 0; n < kPacketWidth; ++n) {
            if (valid[n] == 0) continue;
            const glm::dvec3& direction = directions[std::size_t(lanes[n])];
            const Segment next = segment(range, start[n], direction, travelled[n]);
            tColumn[n] = next.tColumn;
            packet.ray.org_x[n] = float(start[n].x);
            packet.ray.org_y[n] = float(start[n].y);
            packet.ray.org_z[n] = float(start[n].z);
            packet.ray.tnear[n] = 0.0f;
            packet.ray.dir_x[n] = float(direction.x);
            packet.ray.dir_y[n] = float(direction.y);
            packet.ray.dir_z[n] = float(direction.z);
            packet.ray.time[n] = 0.0f;
            packet.ray.tfar[n] = next.tFar;
            packet.ray.mask[n] = ~0u;
            packet.ray.id[n] = 0;
            packet.ray.flags[n] = 0;
            packet.hit.geomID[n] = RTC_INVALID_GEOMETRY_ID;
            packet.hit.instID[0][n] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, scene.scene.get(), &context, &packet);
        any = false;
        for (int n = 0; n < kPacketWidth; ++n) {
            if (valid[n] == 0) continue;
            const glm::dvec3& direction = directions[std::size_t(lanes[n])];
            if (packet.hit.geomID[n] != RTC_INVALID_GEOMETRY_ID) {
                // Embree's geometry normal Ng points out of the solid as scene.normals do (the triangles
                // are counter-clockwise seen from outside), and needs no lookup.
                const double along = double(packet.hit.Ng_x[n]) * direction.x +
                                     double(packet.hit.Ng_y[n]) * direction.y +
                                     double(packet.hit.Ng_z[n]) * direction.z;
                const bool slipped = !scene.watertight && along >= 0.0;
                values[lanes[n]] =
                    slipped ? distanceAlong(scene, scene.robust(), context, origin, direction, height, 0.0)
                            : float(travelled[n] + double(packet.ray.tfar[n]));
                valid[n] = 0;
            } else if (tColumn[n] < 0.0) {
                valid[n] = 0;  // left the slab: a miss
            } else {
                start[n] = wrapped(start[n], direction, tColumn[n]);
                travelled[n] += tColumn[n];
                if (leavesMesh(scene, start[n], direction))
                    valid[n] = 0;
                else
                    any = true;
            }
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
    if (solid.triangles.empty()) {
        gdm.values.assign(dims.valueCount(), kGdmMiss);
        if (progress) progress(1.0);
        return gdm;
    }

    // The values (134 MB at the paper's size, a page fault every 4 KiB) are allocated on another thread
    // while Embree builds the scene. Every value is written below; the fill only sizes the vector.
    std::future<void> allocated =
        std::async(std::launch::async, [&] { gdm.values.assign(dims.valueCount(), kGdmMiss); });
    EmbreeErrors errors;
    const PeriodicScene scene = buildScene(solid, what, errors, SceneTest::Fast);
    allocated.get();
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
