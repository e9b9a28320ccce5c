// The pinhole camera of CONVENTIONS §7 and the render settings: the CPU rays and the GL matrices must
// describe the same picture, pixel (0, 0) at the top-left.
#include "strata/core/error.h"
#include "strata/scene/camera.h"
#include "strata/scene/render_settings.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include <cmath>

namespace strata {
namespace {

// Rounding of a handful of double operations on unit vectors.
constexpr double kTight = 1e-12;

TEST(Camera, CentreRayLooksAtTheTarget) {
    Camera camera;
    camera.eye = {0.5, -1.0, 1.2};
    camera.target = {0.5, 0.5, 0.0};
    // Odd sizes: the middle pixel's centre is the picture's centre.
    const glm::dvec3 ray = pixelRayDirection(camera, 33, 17, 16.5, 8.5);
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    EXPECT_NEAR(glm::length(ray - forward), 0.0, kTight);
}

TEST(Camera, TopLeftPixelIsUpAndLeft) {
    Camera camera;
    camera.eye = {0.5, 0.5, 2.0};
    camera.target = {0.5, 0.5, 0.0};  // straight down: up falls back to +y
    const CameraFrame frame = cameraFrame(camera);
    EXPECT_NEAR(glm::length(frame.up - glm::dvec3(0, 1, 0)), 0.0, kTight);
    EXPECT_NEAR(glm::length(frame.right - glm::dvec3(1, 0, 0)), 0.0, kTight);
    const glm::dvec3 ray = pixelRayDirection(camera, 64, 64, 0.5, 0.5);
    EXPECT_LT(ray.x, 0.0);  // left is -x
    EXPECT_GT(ray.y, 0.0);  // top is +y
}

TEST(Camera, RaysAndMatricesAgree) {
    Camera camera;
    camera.eye = {1.7, -0.9, 1.3};
    camera.target = {0.4, 0.6, -0.1};
    camera.fovYDegrees = 37.0;
    const int width = 160, height = 90;
    const glm::dmat4 clip =
        projectionMatrix(camera, static_cast<double>(width) / height, 0.05, 20.0) * viewMatrix(camera);
    for (const auto& [px, py] :
         {std::pair{0.5, 0.5}, {159.5, 0.5}, {80.0, 45.0}, {3.5, 88.5}, {120.25, 10.75}}) {
        const glm::dvec3 point = camera.eye + 2.5 * pixelRayDirection(camera, width, height, px, py);
        const glm::dvec4 c = clip * glm::dvec4(point, 1.0);
        // NDC -> pixel coordinates with row 0 at the top.
        const double x = (c.x / c.w * 0.5 + 0.5) * width;
        const double y = (0.5 - c.y / c.w * 0.5) * height;
        // Double rounding through a 4x4 projection: far below a pixel.
        EXPECT_NEAR(x, px, 1e-9);
        EXPECT_NEAR(y, py, 1e-9);
    }
}

TEST(Camera, BadCamerasAreRejected) {
    Camera camera;
    camera.target = camera.eye;
    EXPECT_THROW(validateCamera(camera), Error);
    camera = Camera{};
    camera.fovYDegrees = 180.0;
    EXPECT_THROW(validateCamera(camera), Error);
    camera.fovYDegrees = std::nan("");
    EXPECT_THROW(validateCamera(camera), Error);
    camera = Camera{};
    camera.eye.x = INFINITY;
    try {
        validateCamera(camera, "--eye");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("--eye"), std::string::npos) << e.what();
    }
}

TEST(RenderSettings, LinearStepsKeepTheStepLengthAlongTheRay) {
    EXPECT_EQ(adaptiveLinearSteps(10, 1.0), 10);
    EXPECT_EQ(adaptiveLinearSteps(10, 0.5), 20);  // 60 degrees: the ray is twice as long
    EXPECT_EQ(adaptiveLinearSteps(10, 0.0), 40);  // capped at 4 N
    EXPECT_EQ(adaptiveLinearSteps(10, 0.2), 40);
    EXPECT_EQ(adaptiveLinearSteps(64, -1.0), 64);  // |cos|: a ray from below counts like one from above
    EXPECT_EQ(adaptiveLinearSteps(64, std::cos(45.0 * M_PI / 180.0)), 91);   // 64 * sqrt(2) = 90.5
    EXPECT_EQ(adaptiveLinearSteps(64, std::cos(75.0 * M_PI / 180.0)), 247);  // 64 / 0.2588 = 247.3
}

TEST(RenderSettings, NamesRoundTripAndUnknownNamesAreErrors) {
    for (Technique t : {Technique::Texture, Technique::Normal, Technique::Parallax, Technique::Relief})
        EXPECT_EQ(parseTechnique(toString(t)), t);
    for (RenderOutput o : {RenderOutput::Shaded, RenderOutput::Uv, RenderOutput::Shadow, RenderOutput::Depth})
        EXPECT_EQ(parseRenderOutput(toString(o)), o);
    for (AoRescale r : {AoRescale::Off, AoRescale::Paper, AoRescale::Exact})
        EXPECT_EQ(parseAoRescale(toString(r)), r);
    EXPECT_THROW(parseTechnique("bump"), Error);
    EXPECT_THROW(parseRenderOutput("normals"), Error);
    EXPECT_THROW(parseAoRescale("approx"), Error);
}

TEST(RenderSettings, RangesAreChecked) {
    ReliefSettings relief;
    relief.linearSteps = 0;
    EXPECT_THROW(validate(relief), Error);
    relief = {};
    relief.depthScale = -0.1;
    EXPECT_THROW(validate(relief), Error);
    relief = {};
    relief.tiling = 0.0;
    EXPECT_THROW(validate(relief), Error);
    PictureSettings picture;
    picture.samples = 0;
    EXPECT_THROW(validate(picture), Error);
    picture = {};
    picture.width = 9000;
    EXPECT_THROW(validate(picture), Error);
    Lighting lighting;
    lighting.shininess = 0.5;
    EXPECT_THROW(validate(lighting), Error);
    EXPECT_NO_THROW(validate(ReliefSettings{}));
    EXPECT_NO_THROW(validate(Lighting{}));
    EXPECT_NO_THROW(validate(PictureSettings{}));
}

}  // namespace
}  // namespace strata
