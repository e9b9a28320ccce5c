// Scene files: strict parsing with the file and key in every message, defaults that render the main job,
// camera framing, and the material and AO a render uses.
#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/scene/scene.h"

#include "test_support.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <cmath>

namespace strata {
namespace {

using nlohmann::json;

// Parses `text` as the scene "scene.json" and expects Error(InvalidInput) whose message has `part`.
void expectRejected(const std::string& text, const std::string& part) {
    try {
        parseScene(json::parse(text), "scene.json");
        FAIL() << "accepted: " << text;
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput) << e.what();
        EXPECT_NE(std::string(e.what()).find("scene.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
}

TEST(Scene, DefaultsAreTheMainJob) {
    const Scene scene = parseScene(json::object(), "");
    EXPECT_EQ(scene.mesh, "teapot");
    EXPECT_EQ(scene.material, "shaped-fabric");
    EXPECT_FALSE(scene.camera.has_value());
    EXPECT_EQ(scene.relief.technique, Technique::Relief);
    EXPECT_EQ(scene.relief.linearSteps, 10);  // the paper's shader
    EXPECT_EQ(scene.relief.binarySteps, 5);
    EXPECT_EQ(scene.picture.width, 1280);
    EXPECT_EQ(scene.picture.height, 720);
    EXPECT_GT(scene.picture.samples, 1);  // the main job is antialiased
}

TEST(Scene, EveryKeyIsRead) {
    const Scene scene = parseScene(json::parse(R"({
        "mesh": "sphere", "tessellation": 8, "material": "stone-bricks", "technique": "parallax",
        "linear_steps": 64, "binary_steps": 8, "depth_scale": 0.1, "tiling": 3.5,
        "self_shadow": false, "depth_correction": false, "ao": false, "ao_rescale": "paper",
        "camera": { "eye": [1, 2, 3], "target": [0, 0, 0.5], "up": [0, 1, 0], "fov": 50 },
        "light": { "position": [4, 5, 6], "color": [1, 0.9, 0.8], "ambient": 0.1, "specular": 0.2,
                   "shininess": 16 },
        "size": [256, 128], "samples": 1, "output": "uv", "background": [0, 0, 0] })"),
                                   "scene.json");
    EXPECT_EQ(scene.mesh, "sphere");
    EXPECT_EQ(scene.tessellation, 8);
    EXPECT_EQ(scene.material, "stone-bricks");
    EXPECT_EQ(scene.relief.technique, Technique::Parallax);
    EXPECT_EQ(scene.relief.linearSteps, 64);
    EXPECT_EQ(scene.relief.binarySteps, 8);
    EXPECT_EQ(scene.relief.depthScale.value_or(0.0), 0.1);
    EXPECT_EQ(scene.relief.tiling, 3.5);
    EXPECT_FALSE(scene.relief.selfShadow);
    EXPECT_FALSE(scene.relief.depthCorrection);
    EXPECT_FALSE(scene.relief.ao);
    EXPECT_EQ(scene.relief.aoRescale, AoRescale::Paper);
    ASSERT_TRUE(scene.camera.has_value());
    EXPECT_EQ(scene.camera->eye, glm::dvec3(1, 2, 3));
    EXPECT_EQ(scene.camera->up, glm::dvec3(0, 1, 0));
    EXPECT_EQ(scene.camera->fovYDegrees, 50.0);
    EXPECT_EQ(scene.lighting.lightPosition, glm::dvec3(4, 5, 6));
    EXPECT_EQ(scene.lighting.shininess, 16.0);
    EXPECT_EQ(scene.picture.width, 256);
    EXPECT_EQ(scene.picture.height, 128);
    EXPECT_EQ(scene.picture.output, RenderOutput::Uv);
}

TEST(Scene, BadScenesNameTheKey) {
    expectRejected(R"({"techniqe": "relief"})", "techniqe: unknown key");
    expectRejected(R"({"technique": "bump"})", "technique");
    expectRejected(R"({"linear_steps": 0})", "linear_steps");
    expectRejected(R"({"linear_steps": 2.5})", "linear_steps");
    expectRejected(R"({"self_shadow": "yes"})", "self_shadow");
    expectRejected(R"({"camera": {"eye": [1, 2]}})", "camera.eye");
    expectRejected(R"({"camera": {"eye": [0, 0, 0], "target": [0, 0, 0]}})", "same point");
    expectRejected(R"({"camera": {"fov": 0}})", "field of view");
    expectRejected(R"({"light": {"shininess": 0}})", "shininess");
    expectRejected(R"({"light": {"positon": [1, 2, 3]}})", "light.positon: unknown key");
    expectRejected(R"({"size": [0, 100]})", "width");
    expectRejected(R"({"size": "1280x720"})", "size");
    expectRejected(R"({"tiling": -1})", "tiling");
    expectRejected(R"({"depth_scale": 0})", "depth_scale");
    expectRejected(R"([1, 2])", "must be a JSON object");
}

TEST(Scene, GdmKeysMakeAGdmRender) {
    const Scene scene = parseScene(json::parse(R"({"mesh": "torus", "gdm": "chain", "gdm_technique": "refine",
        "gdm_rank": 4, "shell_thickness": 0.05, "tiling": 6, "output": "uvw"})"),
                                   "dir/scene.json");
    EXPECT_EQ(scene.gdm.source, "chain");  // no such file: a built-in name, as it is
    EXPECT_EQ(scene.gdm.technique, GdmTechnique::Refine);
    EXPECT_EQ(scene.gdm.rank, 4);
    EXPECT_EQ(scene.gdm.shellThickness, 0.05);
    EXPECT_EQ(scene.picture.output, RenderOutput::Uvw);
    EXPECT_EQ(
        parseScene(json::parse(R"({"gdm": "weave", "gdm_rank": "raw", "output": "mask"})"), "").gdm.rank,
        kGdmRankRaw);
    // Without "gdm" nothing is a GDM render.
    EXPECT_TRUE(Scene{}.gdm.source.empty());

    expectRejected(R"({"gdm": ""})", "gdm");
    expectRejected(R"({"gdm": "weave", "gdm_rank": 0})", "gdm_rank");
    expectRejected(R"({"gdm": "weave", "gdm_rank": 2.5})", "gdm_rank");
    expectRejected(R"({"gdm": "weave", "gdm_rank": "all"})", "gdm_rank");
    expectRejected(R"({"gdm": "weave", "gdm_technique": "exact"})", "gdm_technique");
    expectRejected(R"({"gdm": "weave", "shell_thickness": -1})", "shell_thickness");
    // The outputs belong to their renderer.
    expectRejected(R"({"gdm": "weave", "output": "uv"})", "relief output");
    expectRejected(R"({"output": "mask"})", "GDM output");
    expectRejected(R"({"gdm_technique": "march"})", "give a gdm");
}

TEST(Scene, EnvKeysLightAGdmRender) {
    const Scene scene = parseScene(json::parse(R"({"gdm": "chain", "env": "sky-clear", "env_rotation": -30,
        "env_intensity": 1.5, "env_bounces": 2, "env_rank": 8, "env_specular": 0.3, "env_shininess": 4})"),
                                   "dir/scene.json");
    EXPECT_EQ(scene.environment.source, "sky-clear");  // no such file: a built-in name, as it is
    EXPECT_EQ(scene.environment.rotation, -30.0);
    EXPECT_EQ(scene.environment.intensity, 1.5);
    EXPECT_EQ(scene.environment.bounces, 2);
    EXPECT_EQ(scene.environment.rank, 8);
    EXPECT_EQ(scene.environment.specular, 0.3);
    EXPECT_EQ(scene.environment.shininess, 4.0);
    // The defaults: no environment; one bounce and the paper's four SVD terms when there is one.
    const EnvironmentSettings defaults = parseScene(json::parse(R"({"gdm": "chain"})"), "").environment;
    EXPECT_TRUE(defaults.source.empty());
    EXPECT_EQ(defaults.bounces, 1);
    EXPECT_EQ(defaults.rank, 4);
    EXPECT_EQ(defaults.specular, 0.0);  // no glossy term unless asked for

    expectRejected(R"({"gdm": "weave", "env": ""})", "env");
    expectRejected(R"({"gdm": "weave", "env": "sky-clear", "env_bounces": 9})", "env_bounces");
    expectRejected(R"({"gdm": "weave", "env": "sky-clear", "env_rank": 0})", "env_rank");
    expectRejected(R"({"gdm": "weave", "env": "sky-clear", "env_rank": 49})", "env_rank");
    expectRejected(R"({"gdm": "weave", "env": "sky-clear", "env_intensity": -1})", "env_intensity");
    expectRejected(R"({"gdm": "weave", "env": "sky-clear", "env_specular": -0.1})", "env_specular");
    expectRejected(R"({"gdm": "weave", "env": "sky-clear", "env_shininess": 65})", "env_shininess");
    // The environment lights a GDM render only.
    expectRejected(R"({"env": "sky-clear"})", "give a gdm");
    expectRejected(R"({"env_rotation": 90})", "give a gdm");
}

TEST(Scene, MissingFilesAreIoErrors) {
    try {
        parseScene(json::parse(R"({"depth_map": "no-such-depth.png"})"), "dir/scene.json");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
        EXPECT_NE(std::string(e.what()).find("no-such-depth.png"), std::string::npos) << e.what();
    }
    Scene scene;
    scene.material = "no-such-material";
    try {
        loadSceneMaterial(scene);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
        EXPECT_NE(std::string(e.what()).find("no-such-material"), std::string::npos) << e.what();
    }
    test::ScratchDir dir("scene-bad-json");
    test::writeBytes(dir / "broken.json", "{ \"mesh\": ");
    EXPECT_THROW(readScene(dir / "broken.json"), Error);
}

TEST(Scene, PathsAreRelativeToTheSceneFile) {
    test::ScratchDir dir("scene-paths");
    writePng(dir / "d.png", Image(4, 4, 1, 0.25f));
    const Scene scene = parseScene(json::parse(R"({"depth_map": "d.png"})"), dir / "scene.json");
    EXPECT_EQ(scene.depthMap, dir / "d.png");
    // A depth-map material: normals derived at the render's S, no colour, no AO.
    Scene render = scene;
    render.relief.depthScale = 0.1;
    const ReliefTexture texture = loadSceneMaterial(render);
    EXPECT_EQ(texture.depthScale, 0.1);
    EXPECT_NEAR(texture.depth.at(1, 2), 0.25f, 1.0f / 65535.0f);  // 16-bit quantisation
    EXPECT_TRUE(texture.color.empty());
    EXPECT_TRUE(texture.ao.empty());
    EXPECT_NEAR(texture.normal.at(0, 0, 2), 1.0f, 1e-6f);  // flat: n = +z
}

TEST(Scene, FramedCameraSeesTheWholeBox) {
    Bounds bounds;
    bounds.min = {-1.0f, -0.5f, 0.0f};
    bounds.max = {1.2f, 0.5f, 1.0f};
    const double aspect = 16.0 / 9.0;
    const Camera camera = frameCamera(bounds, aspect, 30.0);
    validateCamera(camera);
    // Every corner projects inside the picture: within the half-angles of the field of view.
    const CameraFrame frame = cameraFrame(camera);
    const double tanY = std::tan(glm::radians(15.0)), tanX = tanY * aspect;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p(corner & 1 ? bounds.max.x : bounds.min.x, corner & 2 ? bounds.max.y : bounds.min.y,
                           corner & 4 ? bounds.max.z : bounds.min.z);
        const glm::dvec3 d = p - camera.eye;
        const double z = glm::dot(d, frame.forward);
        ASSERT_GT(z, 0.0);
        EXPECT_LT(std::abs(glm::dot(d, frame.right)) / z, tanX) << corner;
        EXPECT_LT(std::abs(glm::dot(d, frame.up)) / z, tanY) << corner;
    }
}

TEST(Scene, ExactAoRescaleRebakesAtTheRenderDepthScale) {
    // A 32^2 relief: one deep square pit.
    ReliefTexture texture;
    texture.depth = Image(32, 32, 1, 0.0f);
    for (int y = 12; y < 20; ++y)
        for (int x = 12; x < 20; ++x) texture.depth.at(x, y) = 1.0f;
    texture.depthScale = 0.05;
    AoParams params;
    params.depthScale = 0.05;
    texture.ao = bakeAo(texture.depth, params);
    double aoScale = 0.0;
    // Same S: the map as it is.
    EXPECT_EQ(aoForRender(texture, 0.05, AoRescale::Exact, &aoScale), texture.ao);
    EXPECT_EQ(aoScale, 0.05);
    // Paper and off leave the map alone (the shader rescales for paper).
    EXPECT_EQ(aoForRender(texture, 0.1, AoRescale::Paper, &aoScale), texture.ao);
    EXPECT_EQ(aoScale, 0.05);
    // Exact: a bake at the new S, bit for bit.
    params.depthScale = 0.1;
    EXPECT_EQ(aoForRender(texture, 0.1, AoRescale::Exact, &aoScale), bakeAo(texture.depth, params));
    EXPECT_EQ(aoScale, 0.1);
}

TEST(Scene, TheShippedExampleScenesParse) {
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(STRATA_SOURCE_DIR) /
                                                                 "examples" / "scenes")) {
        if (entry.path().extension() != ".json") continue;
        EXPECT_NO_THROW(readScene(entry.path())) << entry.path();
        ++count;
    }
    EXPECT_GE(count, 3);
}

}  // namespace
}  // namespace strata
