#include "strata/scene/camera.h"

#include "strata/core/error.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <string>

namespace strata {

namespace {

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

void validateCamera(const Camera& camera, const char* what) {
    const std::string name(what);
    if (!finite(camera.eye) || !finite(camera.target) || !finite(camera.up)) {
        throw Error(ErrorKind::InvalidInput, name + ": eye, target and up must be finite");
    }
    if (camera.eye == camera.target) {
        throw Error(ErrorKind::InvalidInput, name + ": eye and target are the same point");
    }
    if (!(camera.fovYDegrees > 0.0 && camera.fovYDegrees < 180.0)) {
        throw Error(ErrorKind::InvalidInput, name + ": field of view must be in (0, 180) degrees, got " +
                                                 formatNumber(camera.fovYDegrees));
    }
}

CameraFrame cameraFrame(const Camera& camera) {
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    glm::dvec3 up = glm::length(camera.up) > 0.0 ? glm::normalize(camera.up) : glm::dvec3(0.0, 0.0, 1.0);
    // Looking straight along `up`: any perpendicular works; +y keeps a top-down view of the unit quad
    // upright.
    if (std::abs(glm::dot(forward, up)) > 1.0 - 1e-12) up = glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, up));
    return {right, glm::cross(right, forward), forward};
}

glm::dmat4 viewMatrix(const Camera& camera) {
    const CameraFrame frame = cameraFrame(camera);
    return glm::lookAtRH(camera.eye, camera.eye + frame.forward, frame.up);
}

glm::dmat4 projectionMatrix(const Camera& camera, double aspect, double nearPlane, double farPlane) {
    return glm::perspectiveRH_NO(glm::radians(camera.fovYDegrees), aspect, nearPlane, farPlane);
}

glm::dvec3 pixelRayDirection(const Camera& camera, int width, int height, double px, double py) {
    const CameraFrame frame = cameraFrame(camera);
    const double tanHalf = std::tan(glm::radians(camera.fovYDegrees) * 0.5);
    const double aspect = static_cast<double>(width) / height;
    // NDC of the point: x right, y up; pixel rows go down.
    const double ndcX = 2.0 * px / width - 1.0;
    const double ndcY = 1.0 - 2.0 * py / height;
    return glm::normalize(frame.forward + ndcX * tanHalf * aspect * frame.right + ndcY * tanHalf * frame.up);
}

}  // namespace strata
