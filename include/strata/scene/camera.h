// strata::Camera: the pinhole camera of CONVENTIONS §7, shared by the GL renderer and the CPU reference
// so that both shoot exactly the same rays.
//
// World space is right-handed with +z up. The camera sits at `eye`, looks at `target`, and keeps world
// `up` (default +z) up in the picture. The vertical field of view is `fovYDegrees`. A W x H picture has one
// ray through each pixel centre; pixel (0, 0) is the top-left one, rows go down. OpenGL's framebuffer row 0
// is the bottom row, so a GL read-back is flipped to match (strata::gl does this).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace strata {

struct Camera {
    glm::dvec3 eye{0.5, -1.0, 1.0};    // world units
    glm::dvec3 target{0.5, 0.5, 0.0};  // world units; must differ from eye
    glm::dvec3 up{0.0, 0.0, 1.0};      // world up; if it is parallel to the view direction, +y is used
    double fovYDegrees = 45.0;         // vertical field of view, (0, 180)
};

// Throws Error(InvalidInput) naming `what` (e.g. "--eye", "camera.fov") when eye == target, a value is not
// finite, or the field of view is outside (0, 180).
void validateCamera(const Camera& camera, const char* what = "camera");

// The orthonormal camera frame: right, up (in the picture) and forward (unit, eye -> target).
struct CameraFrame {
    glm::dvec3 right;
    glm::dvec3 up;
    glm::dvec3 forward;
};
CameraFrame cameraFrame(const Camera& camera);

// World -> eye space (OpenGL convention: the camera looks down -z in eye space).
glm::dmat4 viewMatrix(const Camera& camera);
// Eye -> clip space, OpenGL convention (NDC z in [-1, 1]); aspect = width / height.
glm::dmat4 projectionMatrix(const Camera& camera, double aspect, double nearPlane, double farPlane);

// Unit world-space direction of the ray from `eye` through the point (px, py) of a width x height picture,
// in pixel units with (0, 0) the top-left corner: the centre of pixel (i, j) is (i + 0.5, j + 0.5). The same
// ray that projectionMatrix * viewMatrix rasterises at that pixel centre.
glm::dvec3 pixelRayDirection(const Camera& camera, int width, int height, double px, double py);

}  // namespace strata
