// Internal to the gdm module: writing the GDM scene renderers' pictures (GdmSceneImages, gdm_trace.h), shared
// by the flat scene's renderers (gdm_trace.cpp) and the curved-base reference (gdm_mesh_reference.cpp).
#pragma once

#include "strata/core/error.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/scene/camera.h"

#include "periodic_scene.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace strata::detail {

// What every renderer of the scene refuses, each naming `what`: a camera validateCamera refuses, a picture
// size validateGdmPicture refuses, a shell height that is not finite and > 0, a mesh checkMesh refuses.
inline void checkGdmSceneInput(const SolidMesh& solid, const Camera& camera, int width, int height,
                               const std::string& what) {
    validateCamera(camera);
    validateGdmPicture(width, height);
    if (!(std::isfinite(solid.height) && solid.height > 0.0))
        throw Error(ErrorKind::InvalidInput,
                    what + ": shell height " + formatNumber(solid.height) + " is not finite and > 0");
    checkMesh(solid, what);
}

// All zero: no hit anywhere.
inline GdmSceneImages blankGdmImages(int width, int height) {
    return {Image(width, height, 4), Image(width, height, 1), Image(width, height, 1)};
}

// One hit at `point` of the isotropic texture frame (u, v, w H), as gdm_trace.h's outputs hold it: u, v
// modulo 1 in [0, 1) (a value within half a float ulp of 1 stored as the float below 1), w = z / H clamped to
// [0, 1].
inline void writeGdmHit(GdmSceneImages& images, int i, int j, const glm::dvec3& point, double height,
                        bool lit) {
    const auto unitFloat = [](double x) {
        const float f = float(x - std::floor(x));
        return f >= 1.0f ? std::nextafter(1.0f, 0.0f) : f;
    };
    images.uvw.at(i, j, 0) = unitFloat(point.x);
    images.uvw.at(i, j, 1) = unitFloat(point.y);
    images.uvw.at(i, j, 2) = float(std::clamp(point.z / height, 0.0, 1.0));
    images.uvw.at(i, j, 3) = 1.0f;
    images.mask.at(i, j) = 1.0f;
    images.shadow.at(i, j) = lit ? 1.0f : 0.0f;
}

}  // namespace strata::detail
