// The viewer's orbit camera: a point on a sphere around a target, in strata's world (right-handed, +z up).
// It produces a strata::Camera (scene/camera.h), so the window shows what `strata render` would with the
// same camera.
#pragma once

#include "strata/mesh/mesh.h"
#include "strata/scene/camera.h"

#include <glm/vec3.hpp>

namespace strata::view {

class OrbitCamera {
public:
    // Starts at `camera` (usually frameCamera of the mesh's bounds, as `strata render` frames a scene
    // without a camera). Its up vector is taken as +z.
    explicit OrbitCamera(const Camera& camera = {});

    // The camera this orbit describes. Right after construction it is `camera` up to rounding (1e-15).
    Camera camera() const;

    // Turns the eye around the target: yaw about +z, pitch towards +z. Degrees. Pitch stays within
    // +-kMaxPitchDegrees so that the view direction never becomes parallel to up.
    void orbit(double yawDegrees, double pitchDegrees);
    // Moves eye and target together in the picture plane by (dx, dy) fractions of the picture height at
    // the target's distance (a drag of the whole height moves the target by what the view spans there).
    void pan(double dx, double dy);
    // Multiplies the eye's distance from the target by `factor` (> 0), within [kMinDistance, kMaxDistance].
    void zoom(double factor);

    const glm::dvec3& target() const { return mTarget; }
    double distance() const { return mDistance; }
    double yawDegrees() const { return mYaw; }
    double pitchDegrees() const { return mPitch; }
    double fovYDegrees() const { return mFovY; }

    static constexpr double kMaxPitchDegrees = 89.0;
    static constexpr double kMinDistance = 1e-3;
    static constexpr double kMaxDistance = 1e4;

private:
    glm::dvec3 mTarget{0.0};
    double mDistance = 1.0;
    double mYaw = 0.0;    // degrees, the eye's azimuth about +z from +x, seen from the target
    double mPitch = 0.0;  // degrees, the eye's elevation above the target's horizontal plane
    double mFovY = 45.0;
};

}  // namespace strata::view
