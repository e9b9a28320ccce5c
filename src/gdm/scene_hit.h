// Internal to strata::gdm: the first hit of a camera ray in the GDM verification scene (CONVENTIONS §8), as
// the exact reference defines it (gdm_trace.h): shared by the reference (gdm_trace.cpp) and the path tracer
// (gdm_path_trace.cpp), so that both see the same geometry. The box passage alone is also the emulation's.
#pragma once

#include "periodic_scene.h"

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>

#include <algorithm>
#include <limits>
#include <utility>

namespace strata::detail {

// The inside test at the box entry point is made this far inside the box, off the face's plane.
inline constexpr double kEntryNudge = 1e-7;

// The ray's passage through the box [0, 1]^2 x [0, H]: entry and exit distances, and the outward normal of
// the face it enters through (zero when it does not enter, or enters through the bottom).
struct BoxPassage {
    double tIn = 0.0;
    double tOut = 0.0;
    glm::dvec3 faceNormal{0.0};
    bool seen = false;  // enters through the top or a side, in front of the eye
};

inline BoxPassage passBox(const glm::dvec3& eye, const glm::dvec3& direction, double height) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    BoxPassage result;
    const double lo[3] = {0.0, 0.0, 0.0};
    const double hi[3] = {1.0, 1.0, height};
    double tIn = -kInf;
    double tOut = kInf;
    int inAxis = -1;
    double inSign = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        const double o = eye[axis];
        const double d = direction[axis];
        if (d == 0.0) {
            if (o < lo[axis] || o > hi[axis]) return result;
            continue;
        }
        double t0 = (lo[axis] - o) / d;
        double t1 = (hi[axis] - o) / d;
        double sign = -1.0;  // entering through the low face: outward normal -axis
        if (t0 > t1) {
            std::swap(t0, t1);
            sign = 1.0;
        }
        if (t0 > tIn) {
            tIn = t0;
            inAxis = axis;
            inSign = sign;
        }
        tOut = std::min(tOut, t1);
    }
    // The eye must be outside the box, the box in front of it, and the entry not through the bottom.
    if (inAxis < 0 || tIn > tOut || tIn < 0.0 || (inAxis == 2 && inSign < 0.0)) return result;
    result.tIn = tIn;
    result.tOut = tOut;
    result.faceNormal[inAxis] = inSign;
    result.seen = true;
    return result;
}

// The first hit of the ray from `eye` along unit `direction` (gdm_trace.h, renderGdmReference): the box
// entry point where it lies inside the periodic solid (the cut face, whose normal is the box face's outward
// normal), else the first face of the periodic mesh before the ray leaves the box (its outward normal).
struct SceneHit {
    bool hit = false;
    bool cutFace = false;  // the entry point, inside the periodic solid
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0};  // unit
};

inline SceneHit firstSceneHit(const PeriodicScene& scene, RTCIntersectContext& context, const glm::dvec3& eye,
                              const glm::dvec3& direction, double height) {
    SceneHit result;
    const BoxPassage box = passBox(eye, direction, height);
    if (!box.seen) return result;
    const glm::dvec3 entry = eye + box.tIn * direction;
    if (insideSolid(scene, entry - kEntryNudge * box.faceNormal)) {
        result = {true, true, entry, box.faceNormal};
        return result;
    }
    // The box lies inside the scene's column: one segment, no wrapping.
    RTCRayHit rayHit;
    setRay(rayHit, entry, glm::vec3(direction), box.tOut - box.tIn);
    rtcIntersect1(scene.scene.get(), &context, &rayHit);
    if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return result;
    result.hit = true;
    result.point = entry + double(rayHit.ray.tfar) * direction;
    result.normal = glm::normalize(glm::dvec3(scene.normals[rayHit.hit.primID]));
    return result;
}

}  // namespace strata::detail
