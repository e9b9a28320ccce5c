#include "orbit_camera.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace strata::view {

OrbitCamera::OrbitCamera(const Camera& camera) : mTarget(camera.target), mFovY(camera.fovYDegrees) {
    const glm::dvec3 offset = camera.eye - camera.target;
    mDistance = std::clamp(glm::length(offset), kMinDistance, kMaxDistance);
    mYaw = glm::degrees(std::atan2(offset.y, offset.x));
    mPitch = std::clamp(glm::degrees(std::asin(std::clamp(offset.z / glm::length(offset), -1.0, 1.0))),
                        -kMaxPitchDegrees, kMaxPitchDegrees);
}

Camera OrbitCamera::camera() const {
    const double yaw = glm::radians(mYaw);
    const double pitch = glm::radians(mPitch);
    const glm::dvec3 direction(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                               std::sin(pitch));
    Camera camera;
    camera.target = mTarget;
    camera.eye = mTarget + mDistance * direction;
    camera.up = {0.0, 0.0, 1.0};
    camera.fovYDegrees = mFovY;
    return camera;
}

void OrbitCamera::orbit(double yawDegrees, double pitchDegrees) {
    // Keep yaw in (-180, 180] so that it stays exact to print and to compare after many turns.
    mYaw = std::remainder(mYaw + yawDegrees, 360.0);
    mPitch = std::clamp(mPitch + pitchDegrees, -kMaxPitchDegrees, kMaxPitchDegrees);
}

void OrbitCamera::pan(double dx, double dy) {
    const CameraFrame frame = cameraFrame(camera());
    // The view spans 2 tan(fov / 2) * distance vertically at the target's distance.
    const double span = 2.0 * std::tan(glm::radians(mFovY) * 0.5) * mDistance;
    mTarget += span * (dx * frame.right + dy * frame.up);
}

void OrbitCamera::zoom(double factor) {
    if (!(factor > 0.0) || !std::isfinite(factor)) return;
    mDistance = std::clamp(mDistance * factor, kMinDistance, kMaxDistance);
}

}  // namespace strata::view
