// strata-view: the parts without a window (orbit camera, the edited material and its JSON, the cached bake
// stages against the library's own composition, the GDM view (with and without an environment) and its
// worker), and the viewer end to end: `--screenshot` under xvfb-run against `strata render` of the same
// scene (relief, GDM, GDM with an environment), and the documented exit codes.
//
// The end-to-end tests need the built viewer (STRATA_BUILD_VIEWER) and, for the window, xvfb-run
// (scripts/install-deps.sh installs it); without them they skip.
#include "gl_test_support.h"
#include "test_support.h"

#include "gdm_view.h"
#include "material_bake.h"
#include "material_document.h"
#include "material_pipeline.h"
#include "orbit_camera.h"

#include "strata/core/error.h"
#include "strata/environment/environment.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_path_trace.h"
#include "strata/gdm/gdm_rtv.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gl/context.h"
#include "strata/gl/gdm_picture.h"
#include "strata/gl/gl_error.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/image/image_io.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/scene/scene.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>

namespace fs = std::filesystem;

namespace strata::view {
namespace {

// --- the orbit camera -----------------------------------------------------------------------------------

TEST(ViewerOrbitCamera, StartsAtTheGivenCamera) {
    // The viewer starts from frameCamera, as `strata render` does; the orbit must give that camera back
    // (up to rounding) or the first frame would not be the CLI's picture.
    const Camera framed =
        frameCamera({glm::vec3(-0.95f, -0.64f, 0.0f), glm::vec3(1.09f, 0.64f, 1.0f)}, 4.0 / 3.0);
    const Camera camera = OrbitCamera(framed).camera();
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(camera.eye[i], framed.eye[i], 1e-12);
        EXPECT_NEAR(camera.target[i], framed.target[i], 1e-12);
    }
    EXPECT_EQ(camera.fovYDegrees, framed.fovYDegrees);
}

TEST(ViewerOrbitCamera, OrbitKeepsTheDistanceAndZoomScalesIt) {
    Camera start;
    start.eye = {0.0, -2.0, 0.0};
    start.target = {0.0, 0.0, 0.0};
    OrbitCamera orbit(start);
    orbit.orbit(90.0, 0.0);  // a quarter turn about +z: from -y to +x
    Camera camera = orbit.camera();
    EXPECT_NEAR(camera.eye.x, 2.0, 1e-12);
    EXPECT_NEAR(camera.eye.y, 0.0, 1e-12);
    orbit.orbit(0.0, 500.0);  // pitch stops short of the pole, so the view never becomes parallel to up
    EXPECT_EQ(orbit.pitchDegrees(), OrbitCamera::kMaxPitchDegrees);
    EXPECT_NEAR(glm::length(orbit.camera().eye - orbit.target()), 2.0, 1e-12);
    orbit.zoom(0.5);
    EXPECT_NEAR(glm::length(orbit.camera().eye - orbit.target()), 1.0, 1e-12);
    orbit.zoom(-1.0);  // ignored
    EXPECT_NEAR(orbit.distance(), 1.0, 1e-12);
}

TEST(ViewerOrbitCamera, PanMovesTargetAndEyeTogetherInThePicturePlane) {
    Camera start;
    start.eye = {0.0, -2.0, 0.0};
    start.target = {0.0, 0.0, 0.0};
    start.fovYDegrees = 90.0;  // the view spans 2 * tan(45) * 2 = 4 units vertically at the target
    OrbitCamera orbit(start);
    orbit.pan(0.25, 0.0);  // a quarter of the picture height to the right (+x seen from -y)
    EXPECT_NEAR(orbit.target().x, 1.0, 1e-12);
    EXPECT_NEAR(orbit.camera().eye.x, 1.0, 1e-12);
    orbit.pan(0.0, 0.5);  // half the height up (+z)
    EXPECT_NEAR(orbit.target().z, 2.0, 1e-12);
}

// --- the edited material --------------------------------------------------------------------------------

Material twoPatternMaterial() {
    Material material = openMaterial("shaped-fabric");
    return material;
}

TEST(ViewerMaterial, BuiltinsOpenAsTheirLayers) {
    const Material fabric = openMaterial("shaped-fabric");
    ASSERT_EQ(fabric.layers.size(), 2u);
    EXPECT_EQ(*fabric.layers[0].pattern, "base");
    EXPECT_EQ(*fabric.layers[1].pattern, "fabric");
    EXPECT_EQ(fabric.layers[1].tiling, 8.0);
    EXPECT_EQ(fabric.layers[1].weightDepth, 0.3);
    EXPECT_EQ(fabric.compose.colorFrom, 1);
    const Material bricks = openMaterial("stone-bricks");
    ASSERT_EQ(bricks.layers.size(), 1u);
    EXPECT_EQ(bricks.layers[0].patternParams.size, 512);
    try {
        openMaterial("no-such-material");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
        EXPECT_NE(std::string(e.what()).find("no-such-material"), std::string::npos) << e.what();
    }
}

TEST(ViewerMaterial, LayerEditsKeepTheColourOnItsLayer) {
    Material material = twoPatternMaterial();  // colour from layer 1 (fabric)
    addLayer(material, patternLayer("metal"));
    EXPECT_EQ(material.compose.colorFrom, 1);
    moveLayer(material, 1, 2);  // fabric to the end
    EXPECT_EQ(*material.layers[2].pattern, "fabric");
    EXPECT_EQ(material.compose.colorFrom, 2);
    moveLayer(material, 2, 0);  // fabric to the front
    EXPECT_EQ(*material.layers[0].pattern, "fabric");
    EXPECT_EQ(material.compose.colorFrom, 0);
    removeLayer(material, 1);  // base: colour stays with fabric at 0
    EXPECT_EQ(material.compose.colorFrom, 0);
    removeLayer(material, 0);  // fabric itself: the first layer with colour (metal) takes over
    ASSERT_EQ(material.layers.size(), 1u);
    EXPECT_EQ(*material.layers[0].pattern, "metal");
    EXPECT_EQ(material.compose.colorFrom, 0);
}

TEST(ViewerMaterial, SavedJsonReadsBackAsTheSameMaterial) {
    test::ScratchDir dir("viewer-json");
    fs::create_directories(dir / "maps");
    Image depth(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) depth.at(x, y) = static_cast<float>((x * 7 + y * 3) % 64) / 63.0f;
    writePng(dir / "maps" / "d.png", depth);

    Material material = twoPatternMaterial();
    material.layers[1].patternParams.seed = 7;
    material.layers[1].weightNormal = 0.45;
    MaterialLayer files = fileLayer(dir / "maps" / "d.png", true, {}, {});
    files.tiling = 2.5;
    files.fileDepthScale = 0.05;
    addLayer(material, files);
    material.compose.normals = NormalMode::Consistent;
    material.ao = MetaAoMode::Multiply;
    material.aoParams.directions = 24;

    const fs::path saved = dir / "out" / "edited.json";  // another directory: paths must be rewritten
    saveMaterial(material, saved);
    const nlohmann::json document = nlohmann::json::parse(std::ifstream(saved));
    EXPECT_EQ(document["layers"][2]["height"], "../maps/d.png");  // relative to the saved file

    const Material back = readMaterial(saved);
    ASSERT_EQ(back.layers.size(), 3u);
    EXPECT_EQ(back.layers[1].patternParams.seed, 7u);
    EXPECT_EQ(back.layers[1].weightNormal, 0.45);
    EXPECT_EQ(back.layers[1].tiling, 8.0);
    ASSERT_TRUE(back.layers[2].heightFile.has_value());
    EXPECT_EQ(fs::canonical(*back.layers[2].heightFile), fs::canonical(dir / "maps" / "d.png"));
    EXPECT_EQ(back.layers[2].tiling, 2.5);
    EXPECT_EQ(*back.layers[2].fileDepthScale, 0.05);
    EXPECT_EQ(back.compose.normals, NormalMode::Consistent);
    EXPECT_EQ(back.compose.colorFrom, 1);
    ASSERT_TRUE(back.ao.has_value());
    EXPECT_EQ(*back.ao, MetaAoMode::Multiply);
    EXPECT_EQ(back.aoParams.directions, 24);
    // Saving over a layer's file is refused: an input is never overwritten.
    try {
        saveMaterial(material, dir / "maps" / "d.png");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
    }
}

// --- the bake stages against the library ----------------------------------------------------------------

// A small two-layer material (64^2 base + 64^2 fabric at tiling 4) that composes in milliseconds.
Material smallMaterial() {
    Material material;
    material.compose.resolution = 64;
    material.layers.push_back(patternLayer("base", 64));
    material.layers.push_back(patternLayer("fabric", 64));
    material.layers[1].tiling = 4.0;
    material.layers[1].weightDepth = 0.3;
    material.layers[1].weightNormal = 0.3;
    material.compose.colorFrom = 1;
    return material;
}

TEST(ViewerBake, CachedBakesEqualTheLibrarysComposition) {
    // Whatever the caches skip, a bake must give exactly what composeMaterial (what `strata compose` and
    // `strata render` run) gives for the same material.
    MaterialBaker baker;
    BakeRequest request;
    request.material = smallMaterial();
    request.resolution = 64;
    request.renderDepthScale = request.material.compose.depthScale;

    BakeResult first = baker.bake(request);
    EXPECT_EQ(first.layersLoaded, 2);
    EXPECT_TRUE(first.composed);
    ReliefTexture expected = composeMaterial(request.material);
    EXPECT_EQ(test::maxAbsDiff(first.texture.depth, expected.depth), 0.0);
    EXPECT_EQ(test::maxAbsDiff(first.texture.normal, expected.normal), 0.0);
    EXPECT_EQ(test::maxAbsDiff(first.texture.ao, expected.ao), 0.0);
    EXPECT_EQ(first.aoDepthScale, request.material.compose.depthScale);

    // A weight change: no layer is loaded again, and the result is the fresh composition's.
    request.material.layers[1].weightDepth = 0.6;
    BakeResult second = baker.bake(request);
    EXPECT_EQ(second.layersLoaded, 0);
    EXPECT_TRUE(second.composed);
    expected = composeMaterial(request.material);
    EXPECT_EQ(test::maxAbsDiff(second.texture.depth, expected.depth), 0.0);
    EXPECT_EQ(test::maxAbsDiff(second.texture.ao, expected.ao), 0.0);

    // A new seed loads that layer only.
    request.material.layers[1].patternParams.seed = 2;
    EXPECT_EQ(baker.bake(request).layersLoaded, 1);

    // Another render depth scale with the exact rescale: no composition, the AO re-baked at that S as
    // `strata render` does it (aoForRender).
    request.renderDepthScale = 0.16;
    request.aoRescale = AoRescale::Exact;
    BakeResult rescaled = baker.bake(request);
    EXPECT_FALSE(rescaled.composed);
    EXPECT_EQ(rescaled.layersLoaded, 0);
    expected = composeMaterial(request.material);
    double aoScale = 0.0;
    const Image exactAo = aoForRender(expected, 0.16, AoRescale::Exact, &aoScale);
    EXPECT_EQ(rescaled.aoDepthScale, 0.16);
    EXPECT_EQ(test::maxAbsDiff(rescaled.texture.ao, exactAo), 0.0);
    // With the paper's rescale the map stays the one baked at the material's S (the shader rescales it).
    request.aoRescale = AoRescale::Paper;
    BakeResult paper = baker.bake(request);
    EXPECT_EQ(paper.aoDepthScale, request.material.compose.depthScale);
    EXPECT_EQ(test::maxAbsDiff(paper.texture.ao, expected.ao), 0.0);
}

TEST(ViewerBake, FailureNamesTheLayerAndTheNextBakeRecovers) {
    MaterialBaker baker;
    BakeRequest request;
    request.material = smallMaterial();
    request.resolution = 64;
    baker.bake(request);
    request.material.layers[0].weightDepth = 0.0;
    request.material.layers[1].weightDepth = 0.0;
    try {
        baker.bake(request);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
    }
    request.material.layers[0].weightDepth = 1.0;
    const BakeResult after = baker.bake(request);
    EXPECT_EQ(after.layersLoaded, 0);  // the failed bake kept the loaded layers
    EXPECT_EQ(test::maxAbsDiff(after.texture.depth, composeMaterial(request.material).depth), 0.0);
}

// --- the CPU -> GPU pipeline, live and baked -------------------------------------------------------------

// The pipeline tests need a current GL context (MaterialPipeline uploads on the calling thread): the suite's
// one headless context (gl_test_support.h); the tests skip where none can be made.
#define SKIP_WITHOUT_GL()                                             \
    do {                                                              \
        std::string whyNot;                                           \
        if (test::sharedGlContext(&whyNot) == nullptr)                \
            GTEST_SKIP() << "no OpenGL 4.5 core context: " << whyNot; \
    } while (false)

BakeRequest liveRequest(std::optional<MetaAoMode> ao) {
    BakeRequest request;
    request.material = smallMaterial();
    request.material.ao = ao;
    request.resolution = 64;
    request.renderDepthScale = request.material.compose.depthScale;
    request.meta = MetaPath::Live;
    return request;
}

// A 64x64 picture of the quad seen from above at an angle, 1 sample.
Image renderQuad(gl::ReliefRenderer& renderer, const gl::GpuMesh& mesh, const gl::GpuMaterial& material) {
    gl::RenderRequest request;
    request.objects.push_back({&mesh, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
    request.camera.eye = {0.0, -0.8, 1.2};
    request.camera.target = {0.0, 0.0, 0.0};
    request.camera.fovYDegrees = 40.0;
    request.lighting.lightPosition = {1.0, -1.0, 2.0};
    request.picture.width = 64;
    request.picture.height = 64;
    request.picture.samples = 1;
    return renderer.render(request);
}

TEST(ViewerPipeline, LiveWeightChangesAreUniformsAndStructuralChangesUpload) {
    SKIP_WITHOUT_GL();
    MaterialPipeline pipeline;
    BakeRequest request = liveRequest(MetaAoMode::Multiply);
    const gl::GpuMaterial* gpu = pipeline.updateAndWait(request);
    ASSERT_NE(gpu, nullptr);
    ASSERT_TRUE(gpu->isLive());
    ASSERT_EQ(gpu->layers().size(), 2u);
    EXPECT_EQ(gpu->liveAo(), MetaAoMode::Multiply);
    EXPECT_EQ(pipeline.uploads(), 1);
    EXPECT_EQ(pipeline.lastBake().layersLoaded, 2);
    EXPECT_FALSE(pipeline.lastBake().composed);  // the live path composes nothing for per-layer AO
    const int jobs = pipeline.jobsStarted();

    // Weights and tiling: the same GPU material, changed at once; no job, no upload, no composition.
    request.material.layers[1].weightDepth = 0.6;
    request.material.layers[1].weightNormal = 0.1;
    request.material.layers[1].tiling = 5.5;
    request.material.layers[0].weightDepth = 0.8;
    EXPECT_EQ(pipeline.update(request), gpu);
    EXPECT_FALSE(pipeline.busy());
    EXPECT_EQ(pipeline.jobsStarted(), jobs);
    EXPECT_EQ(pipeline.uploads(), 1);
    EXPECT_EQ(pipeline.layerUpdates(), 1);
    EXPECT_EQ(gpu->layers()[1].weightDepth, 0.6);
    EXPECT_EQ(gpu->layers()[1].weightNormal, 0.1);
    EXPECT_EQ(gpu->layers()[1].tiling, 5.5);
    EXPECT_EQ(gpu->layers()[0].weightDepth, 0.8);
    EXPECT_EQ(pipeline.updateAndWait(request), gpu);  // nothing left to do
    EXPECT_EQ(pipeline.jobsStarted(), jobs);

    // Weights that leave no normal (paper normals): refused with the reason, the material keeps the last
    // valid ones; the next valid state applies again. (With per-layer AO a depth weight that reaches 0 is a
    // structural change: that layer had no AO map baked.)
    BakeRequest zero = request;
    zero.material.layers[0].weightNormal = 0.0;
    zero.material.layers[1].weightNormal = 0.0;
    EXPECT_EQ(pipeline.update(zero), gpu);
    EXPECT_EQ(pipeline.jobsStarted(), jobs);
    EXPECT_NE(pipeline.error().find("sum to 0"), std::string::npos) << pipeline.error();
    EXPECT_EQ(gpu->layers()[1].weightNormal, 0.1);
    BakeRequest moved = request;
    moved.material.layers[0].weightDepth = 0.5;
    pipeline.update(moved);
    EXPECT_TRUE(pipeline.error().empty()) << pipeline.error();
    EXPECT_EQ(gpu->layers()[0].weightDepth, 0.5);

    // A structural change (a new seed) loads that layer and uploads again, with the current weights.
    request.material.layers[1].patternParams.seed = 9;
    const gl::GpuMaterial* reloaded = pipeline.updateAndWait(request);
    ASSERT_NE(reloaded, nullptr);
    EXPECT_EQ(pipeline.uploads(), 2);
    EXPECT_EQ(pipeline.jobsStarted(), jobs + 1);
    EXPECT_EQ(pipeline.lastBake().layersLoaded, 1);
    EXPECT_EQ(reloaded->layers()[1].tiling, 5.5);
    EXPECT_EQ(reloaded->layers()[1].weightDepth, 0.6);
    // So do a new layer, a reorder and the normal mode.
    addLayer(request.material, patternLayer("scales", 64));
    EXPECT_EQ(pipeline.updateAndWait(request)->layers().size(), 3u);
    EXPECT_EQ(pipeline.uploads(), 3);
    moveLayer(request.material, 2, 0);
    EXPECT_EQ(*request.material.layers[0].pattern, "scales");
    pipeline.updateAndWait(request);
    EXPECT_EQ(pipeline.uploads(), 4);
    EXPECT_EQ(pipeline.lastBake().layersLoaded, 0);  // reordered, not reloaded
    request.material.compose.normals = NormalMode::Consistent;
    EXPECT_EQ(pipeline.updateAndWait(request)->normalMode(), NormalMode::Consistent);
    EXPECT_EQ(pipeline.uploads(), 5);

    // Back to baked: composed and uploaded as one texture.
    request.meta = MetaPath::Baked;
    const gl::GpuMaterial* baked = pipeline.updateAndWait(request);
    EXPECT_FALSE(baked->isLive());
    EXPECT_TRUE(pipeline.lastBake().composed);
    EXPECT_EQ(pipeline.uploads(), 6);
    EXPECT_NO_THROW(gl::checkGl("the pipeline test"));
}

TEST(ViewerPipeline, LiveWeightChangeDrawsTheFreshUploadsPicture) {
    // What setLayer leaves on the GPU must draw exactly what a fresh upload of the new weights draws.
    SKIP_WITHOUT_GL();
    MaterialPipeline pipeline;
    BakeRequest request = liveRequest(std::nullopt);
    const gl::GpuMaterial* gpu = pipeline.updateAndWait(request);
    ASSERT_NE(gpu, nullptr);
    request.material.layers[1].weightDepth = 0.7;
    request.material.layers[1].tiling = 3.0;
    ASSERT_EQ(pipeline.update(request), gpu);

    MaterialBaker baker;
    BakeResult report;
    const std::vector<CompositionLayer> layers = baker.layers(request, report);
    const gl::GpuMaterial fresh =
        gl::uploadLiveMaterial(layers, request.material.compose, std::nullopt, request.material.aoParams);
    gl::ReliefRenderer renderer;
    const gl::GpuMesh quad = gl::uploadMesh(makeBuiltinMesh("quad"));
    const Image edited = renderQuad(renderer, quad, *gpu);
    const Image expected = renderQuad(renderer, quad, fresh);
    EXPECT_EQ(test::maxAbsDiff(edited, expected), 0.0);
    EXPECT_GT(test::maxAbsDiff(
                  edited, renderQuad(renderer, quad, *pipeline.updateAndWait(liveRequest(std::nullopt)))),
              0.0)
        << "the weights should change the picture";
}

TEST(ViewerPipeline, LiveExactAoIsRebakedInTheBackground) {
    SKIP_WITHOUT_GL();
    MaterialPipeline pipeline;
    BakeRequest request = liveRequest(MetaAoMode::Exact);
    const gl::GpuMaterial* gpu = pipeline.updateAndWait(request);
    ASSERT_NE(gpu, nullptr);
    ASSERT_TRUE(gpu->isLive());
    EXPECT_EQ(gpu->liveAo(), MetaAoMode::Exact);
    EXPECT_NE(gpu->composedAoTexture(), 0u);  // set before the first frame
    EXPECT_EQ(pipeline.composedAoUpdates(), 1);
    EXPECT_TRUE(pipeline.lastBake().composed);
    const unsigned firstAo = gpu->composedAoTexture();

    // A weight change: the uniforms at once, the composed AO on the worker; the old map until it is done.
    request.material.layers[1].weightDepth = 0.5;
    EXPECT_EQ(pipeline.update(request), gpu);
    EXPECT_EQ(gpu->layers()[1].weightDepth, 0.5);
    EXPECT_TRUE(pipeline.busy());
    EXPECT_EQ(pipeline.activity(), "baking the composed AO");
    EXPECT_EQ(gpu->composedAoTexture(), firstAo);
    EXPECT_EQ(pipeline.updateAndWait(request), gpu);
    EXPECT_EQ(pipeline.uploads(), 1);
    EXPECT_EQ(pipeline.composedAoUpdates(), 2);
    EXPECT_TRUE(pipeline.lastBake().composed);
    EXPECT_EQ(pipeline.lastBake().layersLoaded, 0);

    // S with the exact rescale: the AO at the new S, nothing composed.
    request.renderDepthScale = 0.12;
    pipeline.updateAndWait(request);
    EXPECT_EQ(pipeline.uploads(), 1);
    EXPECT_EQ(pipeline.composedAoUpdates(), 3);
    EXPECT_FALSE(pipeline.lastBake().composed);
    EXPECT_EQ(gpu->aoDepthScale(), 0.12);
    EXPECT_NO_THROW(gl::checkGl("the exact AO test"));
}

// --- the GDM view ---------------------------------------------------------------------------------------

// A tiny weave GDM, as `strata gdm bake --meso weave --size 16x16x4 --dirs 8x16 --keep-raw --rank 4` would
// bake it (the solid meshed at 16 voxels per tile): milliseconds to bake, enough to show threads.
std::shared_ptr<const SceneGdm> tinyWeave() {
    static const std::shared_ptr<const SceneGdm> gdm = [] {
        const Mesostructure meso = makeMesostructure("weave");
        const GdmDims dims{16, 16, 4, 8, 16};
        auto out = std::make_shared<SceneGdm>();
        Gdm raw = bakeGdm(meshMesostructure(meso, 16), dims);
        out->asset.svd = compressGdm(raw, 4);
        out->asset.occupancy = gdmOccupancy(raw);
        out->asset.albedo = mesostructureAlbedo(meso, dims);
        out->asset.raw = std::move(raw);
        out->asset.source = "meso weave";
        out->svd = out->asset.svd;
        out->description = "tiny weave, rank 4";
        return out;
    }();
    return gdm;
}

// tinyWeave lit by the sunset sky (its sun low at one azimuth), as loadSceneGdm lights a scene with "env":
// the RTV (1 bounce, rank 4) baked from the raw GDM, the solid's signed distance and the albedo volume.
std::shared_ptr<const SceneGdm> tinySunsetWeave() {
    static const std::shared_ptr<const SceneGdm> gdm = [] {
        auto out = std::make_shared<SceneGdm>(*tinyWeave());
        const GdmDims& dims = out->asset.svd.dims;
        const std::vector<float> distance =
            bakeGdmDistance(meshMesostructure(makeMesostructure("weave"), 16), dims);
        const GdmRtv rtv = bakeGdmRtv(*out->asset.raw, distance,
                                      gdmVolumeAlbedo(out->asset.albedo, dims.nx, dims.ny, dims.nz));
        out->rtv = compressGdmRtv(rtv, 4);
        const Environment sky = openEnvironment("sky-sunset");
        out->environmentName = sky.name();
        out->environmentSh = sky.sh();
        out->environment = turnEnvironment(sky.sh(), 0.0, 1.0);
        out->description = "tiny weave, rank 4, sky-sunset (RTV rank 4, 1 bounce)";  // loadSceneGdm's form
        return out;
    }();
    return gdm;
}

// A 64x48 frame of the sphere, framed as `strata render --gdm` frames it, 1 sample.
GdmFrame sphereFrame(const SceneGdm& gdm, const Mesh& sphere, const GdmViewSettings& settings) {
    GdmFrame frame;
    frame.settings = settings;
    frame.width = 64;
    frame.height = 48;
    frame.camera =
        frameCamera(gdmFramingBounds(sphere, gdmShell(gdm, sphere, settings).thickness), 64.0 / 48.0);
    frame.lighting = Lighting{};
    frame.mesh = 1;
    return frame;
}

// What `strata render --gdm` draws for the frame: a fresh renderer with the GDM of that rank, the shell and
// the volumes (render_gdm.cpp's steps).
// With an environment, turned and scaled as the frame's settings say (loadSceneGdm's turnEnvironment).
Image freshPicture(const SceneGdm& gdm, const Mesh& mesh, const GdmFrame& frame, const GdmSvd& svd) {
    SceneGdm drawn = gdm;  // a tiny asset: the copy is cheap
    drawn.raw = false;
    drawn.svd = svd;
    if (hasEnvironment(gdm))
        drawn.environment = turnEnvironment(gdm.environmentSh, frame.settings.environmentRotation,
                                            frame.settings.environmentIntensity);
    Scene scene;
    scene.relief.tiling = frame.settings.tiling;
    scene.gdm.shellThickness = frame.settings.shellThickness;
    scene.gdm.lightFrame = frame.settings.lightFrame;
    scene.lighting = frame.lighting;
    gl::GdmRenderer renderer;
    gl::prepareGdmRenderer(renderer, drawn, mesh, scene);
    return gl::renderGdmPicture(renderer, frame.camera, frame.lighting, gdmPictureSettings(frame),
                                frame.settings.technique);
}

// Values that differ by more than 2/255 (more than 8-bit rounding could make), % of all.
double percentApart(const Image& a, const Image& b) {
    int apart = 0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i)
        apart += std::fabs(static_cast<double>(a.pixels()[i] - b.pixels()[i])) > 2.0 / 255.0 ? 1 : 0;
    return 100.0 * apart / static_cast<double>(a.pixels().size());
}

TEST(ViewerGdm, EachChangeUploadsOnlyWhatItChangesAndDrawsStrataRendersPicture) {
    SKIP_WITHOUT_GL();
    const std::shared_ptr<const SceneGdm> gdm = tinyWeave();
    const auto sphere = std::make_shared<const Mesh>(makeBuiltinMesh("sphere"));
    GdmView view(gdm);
    view.setMesh(sphere, 1);
    GdmViewSettings settings;
    settings.rank = 4;
    GdmFrame frame = sphereFrame(*gdm, *sphere, settings);

    const Image first = view.render(frame);
    EXPECT_EQ(view.gdmUploads(), 1);
    EXPECT_EQ(view.shellBuilds(), 1);
    EXPECT_EQ(view.renders(), 1);
    ASSERT_EQ(first.width(), 64);
    ASSERT_EQ(first.height(), 48);
    ASSERT_EQ(first.channels(), 3);
    // The same code path as `strata render --gdm` on the same context: the same picture, exactly.
    EXPECT_EQ(test::maxAbsDiff(first, freshPicture(*gdm, *sphere, frame, gdm->asset.svd)), 0.0);

    // The camera: a picture, nothing uploaded.
    GdmFrame turned = frame;
    turned.camera.eye.x += 0.3;
    view.render(turned);
    EXPECT_EQ(view.gdmUploads(), 1);
    EXPECT_EQ(view.shellBuilds(), 1);
    EXPECT_EQ(view.renders(), 2);

    // The technique: nothing uploaded, another picture. March steps the occupancy instead of reading the
    // GDM: on this 16x16x4 weave the threads' outlines and shading move (measured: 10.9 % of the values
    // more than 2/255 apart). The same frame drawn again is exactly the same picture (0 %, above), so 3 %
    // tells a changed picture from an unchanged one with room either way; it is the bound below too.
    GdmFrame march = frame;
    march.settings.technique = GdmTechnique::March;
    const Image marched = view.render(march);
    EXPECT_EQ(view.gdmUploads(), 1);
    EXPECT_EQ(view.shellBuilds(), 1);
    EXPECT_GT(percentApart(marched, first), 3.0);

    // The rank: the truncated SVD uploaded (no bake), and the shell and volumes again (setGdm forgets them);
    // the picture is the one of a renderer given truncateGdmSvd(svd, 1) outright. Rank 1 loses much of the
    // weave's shape (measured: 11.7 % of the values apart from rank 4's).
    GdmFrame rank1 = frame;
    rank1.settings.rank = 1;
    const Image truncated = view.render(rank1);
    EXPECT_EQ(view.gdmUploads(), 2);
    EXPECT_EQ(view.shellBuilds(), 2);
    EXPECT_EQ(
        test::maxAbsDiff(truncated, freshPicture(*gdm, *sphere, rank1, truncateGdmSvd(gdm->asset.svd, 1))),
        0.0);
    EXPECT_GT(percentApart(truncated, first), 3.0);

    // The raw GDM (the asset keeps it): another upload, another picture (measured: 11.4 % of the values
    // apart from rank 1's, 5.6 % from rank 4's).
    GdmFrame raw = frame;
    raw.settings.rank = kGdmRankRaw;
    const Image rawPicture = view.render(raw);
    EXPECT_EQ(view.gdmUploads(), 3);
    EXPECT_GT(percentApart(rawPicture, truncated), 3.0);

    // Tiling and T: the shell only.
    GdmFrame tiled = raw;
    tiled.settings.tiling = 2.0;
    view.render(tiled);
    tiled.settings.shellThickness = 0.2;
    view.render(tiled);
    EXPECT_EQ(view.gdmUploads(), 3);
    EXPECT_EQ(view.shellBuilds(), 5);

    // A rank the asset lacks: refused with both ranks named; the next frame uploads everything again and
    // draws the first picture exactly.
    GdmFrame tooMany = frame;
    tooMany.settings.rank = 5;
    try {
        view.render(tooMany);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("5"), std::string::npos) << e.what();
    }
    EXPECT_EQ(test::maxAbsDiff(view.render(frame), first), 0.0);
    EXPECT_EQ(view.gdmUploads(), 4);
    // Without an environment: no RTV, no macro transfer, no environment (the ambient term).
    EXPECT_EQ(view.rtvUploads(), 0);
    EXPECT_EQ(view.macroTransferBakes(), 0);
    EXPECT_EQ(view.environmentUploads(), 0);
    EXPECT_NO_THROW(gl::checkGl("the GDM view test"));
}

TEST(ViewerGdm, TurningTheEnvironmentUploadsItAloneAndAShellChangeBakesTheMacroTransferAgain) {
    SKIP_WITHOUT_GL();
    const std::shared_ptr<const SceneGdm> gdm = tinySunsetWeave();
    ASSERT_TRUE(hasEnvironment(*gdm));
    // The GDM panel's lines: the source without the rank and the environment, which it shows itself.
    const GdmDescription description = describeGdm(*gdm);
    EXPECT_EQ(description.source, "tiny weave");
    EXPECT_EQ(description.environment, "sky-sunset");
    EXPECT_EQ(description.rtvRank, 4);
    EXPECT_GT(description.rtvMiB, 0.0);
    EXPECT_EQ(describeGdm(*tinyWeave()).environment, "");
    const auto sphere = std::make_shared<const Mesh>(makeBuiltinMesh("sphere"));
    GdmView view(gdm);
    view.setMesh(sphere, 1);
    GdmViewSettings settings;
    settings.rank = 4;
    GdmFrame frame = sphereFrame(*gdm, *sphere, settings);
    // The environment alone lights it (it replaces the ambient term; the point light is off).
    frame.lighting.lightColor = glm::dvec3(0.0);
    const auto expectCounts = [&](int gdmUploads, int shellBuilds, int rtvUploads, int bakes,
                                  int transferUploads, int environmentUploads) {
        EXPECT_EQ(view.gdmUploads(), gdmUploads);
        EXPECT_EQ(view.shellBuilds(), shellBuilds);
        EXPECT_EQ(view.rtvUploads(), rtvUploads);
        EXPECT_EQ(view.macroTransferBakes(), bakes);
        EXPECT_EQ(view.macroTransferUploads(), transferUploads);
        EXPECT_EQ(view.environmentUploads(), environmentUploads);
    };

    // The first picture uploads everything, and is `strata render --gdm --env`'s (prepareGdmRenderer).
    const Image first = view.render(frame);
    expectCounts(1, 1, 1, 1, 1, 1);
    EXPECT_EQ(test::maxAbsDiff(first, freshPicture(*gdm, *sphere, frame, gdm->asset.svd)), 0.0);

    // The camera: nothing uploaded.
    GdmFrame moved = frame;
    moved.camera.eye.x += 0.3;
    view.render(moved);
    expectCounts(1, 1, 1, 1, 1, 1);

    // The rotation: the environment alone. The sunset's sun moves round the sphere: another picture
    // (measured: 9.9 % of the values more than 2/255 apart; 3 % as in the test above), strata render's
    // with env_rotation 120.
    GdmFrame turned = frame;
    turned.settings.environmentRotation = 120.0;
    const Image turnedPicture = view.render(turned);
    expectCounts(1, 1, 1, 1, 1, 2);
    EXPECT_GT(percentApart(turnedPicture, first), 3.0);
    EXPECT_EQ(test::maxAbsDiff(turnedPicture, freshPicture(*gdm, *sphere, turned, gdm->asset.svd)), 0.0);
    // A whole turn more: the same picture (the SH rotation by 480 degrees is the one by 120 to rounding;
    // measured: exactly the same on llvmpipe).
    GdmFrame whole = turned;
    whole.settings.environmentRotation = 480.0;
    const Image wholePicture = view.render(whole);
    expectCounts(1, 1, 1, 1, 1, 3);
    EXPECT_LE(test::maxAbsDiff(wholePicture, turnedPicture), 1e-4);
    // The intensity: the environment alone, a brighter picture.
    GdmFrame brighter = turned;
    brighter.settings.environmentIntensity = 2.0;
    const Image brighterPicture = view.render(brighter);
    expectCounts(1, 1, 1, 1, 1, 4);
    EXPECT_GT(percentApart(brighterPicture, turnedPicture), 3.0);
    EXPECT_EQ(test::maxAbsDiff(brighterPicture, freshPicture(*gdm, *sphere, brighter, gdm->asset.svd)), 0.0);

    // The tiling with the default T (H times the tile's world length: it follows the tiling): the shell,
    // the macro transfer baked again from the new top of the shell, the environment set again (setMesh
    // forgets both); the RTV stays.
    GdmFrame tiled = brighter;
    tiled.settings.tiling = 2.0;
    const Image tiledPicture = view.render(tiled);
    expectCounts(1, 2, 1, 2, 2, 5);
    EXPECT_EQ(test::maxAbsDiff(tiledPicture, freshPicture(*gdm, *sphere, tiled, gdm->asset.svd)), 0.0);
    // A thickness of its own: another T, another bake.
    tiled.settings.shellThickness = 0.2;
    view.render(tiled);
    expectCounts(1, 3, 1, 3, 3, 6);
    // The tiling at that T: the shell, but the macro transfer of the same mesh and T is uploaded as baked.
    tiled.settings.tiling = 3.0;
    const Image retiled = view.render(tiled);
    expectCounts(1, 4, 1, 3, 4, 7);
    EXPECT_EQ(test::maxAbsDiff(retiled, freshPicture(*gdm, *sphere, tiled, gdm->asset.svd)), 0.0);

    // The rank: the GDM, and the RTV again (setGdm forgets it), the shell and the macro transfer as baked.
    GdmFrame rank2 = tiled;
    rank2.settings.rank = 2;
    const Image truncated = view.render(rank2);
    expectCounts(2, 5, 2, 3, 5, 8);
    EXPECT_EQ(
        test::maxAbsDiff(truncated, freshPicture(*gdm, *sphere, rank2, truncateGdmSvd(gdm->asset.svd, 2))),
        0.0);

    // A new mesh: the shell and a bake for it.
    const auto torus = std::make_shared<const Mesh>(makeBuiltinMesh("torus"));
    view.setMesh(torus, 2);
    GdmFrame onTorus = rank2;
    onTorus.mesh = 2;
    const Image torusPicture = view.render(onTorus);
    expectCounts(2, 6, 2, 4, 6, 9);
    EXPECT_EQ(test::maxAbsDiff(torusPicture,
                               freshPicture(*gdm, *torus, onTorus, truncateGdmSvd(gdm->asset.svd, 2))),
              0.0);

    // A failure (a rank the asset lacks) uploads everything again next time, the bake kept (same mesh, T).
    GdmFrame tooMany = onTorus;
    tooMany.settings.rank = 5;
    EXPECT_THROW(view.render(tooMany), Error);
    EXPECT_EQ(test::maxAbsDiff(view.render(onTorus), torusPicture), 0.0);
    expectCounts(3, 7, 3, 4, 7, 10);
    EXPECT_NO_THROW(gl::checkGl("the GDM environment test"));
}

TEST(ViewerGdm, TheWorkerDrawsOnItsOwnContextAndReportsFailures) {
    SKIP_WITHOUT_GL();
    const std::shared_ptr<const SceneGdm> gdm = tinyWeave();
    const auto sphere = std::make_shared<const Mesh>(makeBuiltinMesh("sphere"));
    GdmViewSettings settings;
    settings.rank = 4;
    const GdmFrame frame = sphereFrame(*gdm, *sphere, settings);
    GdmView direct(gdm);
    direct.setMesh(sphere, 1);
    const Image expected = direct.render(frame);

    // The worker's context: another headless one, made and destroyed on the worker's thread (the viewer's
    // is a hidden window's).
    std::unique_ptr<gl::HeadlessContext> context;
    {
        GdmWorker worker(
            gdm, [&context] { context = gl::HeadlessContext::create(); }, [&context] { context.reset(); });
        const std::uint64_t job = worker.submit(frame, sphere);
        const GdmPicture picture = worker.wait(job);
        EXPECT_EQ(picture.job, job);
        ASSERT_FALSE(picture.error);
        EXPECT_TRUE(sameFrame(picture.frame, frame));
        EXPECT_EQ(test::maxAbsDiff(picture.image, expected), 0.0);  // the same renderer on the same driver
        EXPECT_FALSE(worker.take().has_value());                    // wait() took it

        GdmFrame bad = frame;
        bad.settings.rank = 9;
        const GdmPicture failed = worker.wait(worker.submit(bad, sphere));
        ASSERT_TRUE(failed.error);
        try {
            std::rethrow_exception(failed.error);
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        }
        EXPECT_TRUE(failed.image.pixels().empty());
    }
    EXPECT_EQ(context, nullptr);  // released on the worker's thread when it stopped
    // The test's own context is still current on this thread.
    EXPECT_NO_THROW(direct.render(frame));
    EXPECT_NO_THROW(gl::checkGl("the GDM worker test"));
}

// --- end to end -----------------------------------------------------------------------------------------

test::CommandResult runShell(const std::string& command) {
    FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    if (pipe == nullptr) return {-1, "popen failed"};
    std::string output;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe)) output += buffer.data();
    const int status = ::pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

std::string quoted(const fs::path& path) {
    return "'" + path.string() + "'";
}

std::string viewer() {
    return quoted(STRATA_VIEW_PATH);
}

#define SKIP_WITHOUT_VIEWER()                  \
    if (std::string(STRATA_VIEW_PATH).empty()) \
    GTEST_SKIP() << "strata-view is not built (STRATA_BUILD_VIEWER=OFF)"

// The viewer with no display at all: the input errors come first, then the missing display.
test::CommandResult runWithoutDisplay(const std::string& args) {
    return runShell("env -u DISPLAY -u WAYLAND_DISPLAY " + viewer() + " " + args);
}

TEST(ViewerCli, ExitCodesWithoutADisplay) {
    SKIP_WITHOUT_VIEWER();
    test::ScratchDir dir("viewer-exit");
    // 5 and a hint when there is no display.
    test::CommandResult run = runWithoutDisplay("stone-bricks --screenshot " + quoted(dir / "a.png"));
    EXPECT_EQ(run.exitCode, 5) << run.output;
    EXPECT_NE(run.output.find("xvfb-run"), std::string::npos) << run.output;
    // 1: a malformed --size.
    run = runWithoutDisplay("--size 256by192");
    EXPECT_EQ(run.exitCode, 1) << run.output;
    EXPECT_NE(run.output.find("--size"), std::string::npos) << run.output;
    // 2: a material that does not exist.
    run = runWithoutDisplay(quoted(dir / "missing.json"));
    EXPECT_EQ(run.exitCode, 2) << run.output;
    // 3: a bad material key, named with its file.
    test::writeBytes(dir / "bad.json", R"({"layers": [{"pattern": "base", "weight_depth": -0.3}]})");
    run = runWithoutDisplay(quoted(dir / "bad.json"));
    EXPECT_EQ(run.exitCode, 3) << run.output;
    EXPECT_NE(run.output.find("bad.json: layers[0].weight_depth"), std::string::npos) << run.output;
    // 2: a screenshot that would overwrite an input (a layer's depth map); the file is left alone.
    Image depth(64, 64, 1, 0.5f);
    writePng(dir / "d.png", depth);
    test::writeBytes(dir / "m.json", R"({"layers": [{"depth": "d.png"}]})");
    const auto before = fs::file_size(dir / "d.png");
    run = runWithoutDisplay(quoted(dir / "m.json") + " --screenshot " + quoted(dir / "d.png"));
    EXPECT_EQ(run.exitCode, 2) << run.output;
    EXPECT_EQ(fs::file_size(dir / "d.png"), before);
    // 5: a screenshot format other than PNG.
    run = runWithoutDisplay("stone-bricks --screenshot " + quoted(dir / "a.jpg"));
    EXPECT_EQ(run.exitCode, 5) << run.output;
    // 1: a malformed --max-memory, named as `strata` names it.
    run = runWithoutDisplay("--max-memory 12X");
    EXPECT_EQ(run.exitCode, 1) << run.output;
    EXPECT_NE(run.output.find("strata-view: error: --max-memory '12X': unknown suffix"), std::string::npos)
        << run.output;
    EXPECT_EQ(test::countEntries(dir.path()), 3);  // bad.json, d.png, m.json: nothing was written
}

double meanAbsDiff(const Image& a, const Image& b, int x0, int y0, int x1, int y1) {
    double sum = 0.0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < a.channels(); ++c)
                sum += std::fabs(static_cast<double>(a.at(x, y, c) - b.at(x, y, c)));
    return sum / (static_cast<double>(x1 - x0) * (y1 - y0) * a.channels());
}

// `view` (the viewer's window) against `reference` (`strata render` of the same scene, 1 sample), 256x192.
// They differ in where sRGB is rounded to 8 bits
// (the viewer's shader into the window; the CLI on the CPU, with a +-0.5 LSB dither), and in texture
// filtering: a window's framebuffer and the CLI's framebuffer object give the fine weave slightly
// different derivatives, hence mip levels (texture mapping alone, without any relief search, differs the
// same way). Measured on llvmpipe: mean |difference| 0.57/255, 2.3 % of values off by more than 2/255,
// 8x8 block means within 4.3/255. A light moved by 0.2 (of 4) gives 0.82/255, 10 % and 7.7/255; S = 0.1
// instead of 0.08 gives 1.19/255 and 10.7/255: the bounds below tell those apart. Only when both ran on
// llvmpipe (the viewer always does under Xvfb; `strata render` may use a GPU).
void expectSamePicture(const Image& view, const Image& reference, const std::string& viewerOutput,
                       const std::string& renderOutput) {
    if (viewerOutput.find("llvmpipe") == std::string::npos ||
        renderOutput.find("llvmpipe") == std::string::npos) {
        std::cout << "not comparing with strata render: different OpenGL implementations\n"
                  << viewerOutput << renderOutput;
    } else {
        EXPECT_LT(meanAbsDiff(view, reference, 0, 0, 256, 192), 0.8 / 255.0)
            << "mean |viewer - strata render|";
        int far = 0;
        for (std::size_t i = 0; i < view.pixels().size(); ++i)
            far += std::fabs(static_cast<double>(view.pixels()[i] - reference.pixels()[i])) > 2.5 / 255.0 ? 1
                                                                                                          : 0;
        EXPECT_LT(far, static_cast<int>(view.pixels().size() * 4 / 100)) << "values off by more than 2/255";
        double worstBlock = 0.0;
        for (int y = 0; y < 192; y += 8)
            for (int x = 0; x < 256; x += 8) {
                // |mean(view) - mean(reference)| per channel over an 8x8 block.
                for (int c = 0; c < 3; ++c) {
                    double a = 0.0, b = 0.0;
                    for (int j = 0; j < 8; ++j)
                        for (int i = 0; i < 8; ++i) {
                            a += static_cast<double>(view.at(x + i, y + j, c));
                            b += static_cast<double>(reference.at(x + i, y + j, c));
                        }
                    worstBlock = std::max(worstBlock, std::fabs(a - b) / 64.0);
                }
            }
        EXPECT_LT(worstBlock, 6.0 / 255.0) << "an 8x8 block's mean differs";
    }
}

// A command under `xvfb-run -a`. Two servers starting at once can pick the same display number (ctest runs
// the viewer tests one at a time: RESOURCE_LOCK xvfb in tests/CMakeLists.txt); a server that fails to start
// anyway is retried once. xvfb-run replaces the command's exit status with its own 5 when removing its
// temporary directory fails (a race with the X server's lock files on a busy machine), so the command's
// status is echoed inside the server and read from there.
test::CommandResult runUnderXvfb(const std::string& command) {
    std::string escaped;
    for (const char c : command) escaped += c == '\'' ? std::string("'\\''") : std::string(1, c);
    const std::string marker = "strata-test-exit-status=";
#ifdef __SANITIZE_ADDRESS__
    // Under the asan preset, LeakSanitizer's report at exit would fail every window run: GLFW and Mesa
    // unload X11 and the DRI driver before it, so their leaks have stacks of unknown modules that no
    // suppression matches (and slow unwinding, which would name them, hangs in the driver's threads).
    // Address and undefined-behaviour checks stay on; the viewer's own code also runs in-process above.
    const std::string environment = "ASAN_OPTIONS=detect_leaks=0 ";
#else
    const std::string environment;
#endif
    const std::string wrapped = "xvfb-run -a sh -c '" + environment + escaped + "; echo " + marker + "$?'";
    test::CommandResult run = runShell(wrapped);
    if (run.output.find(marker) == std::string::npos &&
        run.output.find("Xvfb failed to start") != std::string::npos)
        run = runShell(wrapped);
    const std::size_t at = run.output.rfind(marker);
    if (at != std::string::npos) {
        run.exitCode = std::atoi(run.output.c_str() + at + marker.size());
        const std::size_t end = run.output.find('\n', at);
        run.output.erase(at, end == std::string::npos ? std::string::npos : end - at + 1);
    }
    return run;
}

// Pixels of [x0, x1) x [y0, y1) more than 0.1 from the default background in the sum of their channels.
int pixelsUnlikeTheBackground(const Image& view, int x0, int y0, int x1, int y1) {
    const glm::dvec3 background = PictureSettings{}.background;
    int count = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            double difference = 0.0;
            for (int c = 0; c < 3; ++c)
                difference += std::fabs(static_cast<double>(view.at(x, y, c)) - background[c]);
            count += difference > 0.1 ? 1 : 0;
        }
    return count;
}

// The viewer holds its material's maps under the same budget as `strata`: a 512^2 material does not fit
// 4 MiB, the viewer says so with exit 5, and no screenshot is written.
TEST(ViewerCli, MaxMemoryBoundsTheMaterialsMaps) {
    SKIP_WITHOUT_VIEWER();
    test::ScratchDir dir("viewer-budget");
    const test::CommandResult run = runUnderXvfb(
        viewer() + " --max-memory 4M stone-bricks --size 256x192 --screenshot " + quoted(dir / "a.png"));
    EXPECT_EQ(run.exitCode, 5) << run.output;
    EXPECT_NE(run.output.find("strata-view: error: a 512 x 512 image of"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("more than the memory budget of 4 MiB (--max-memory)"), std::string::npos)
        << run.output;
    EXPECT_FALSE(fs::exists(dir / "a.png"));
}

TEST(ViewerCli, ScreenshotUnderXvfbMatchesStrataRender) {
    SKIP_WITHOUT_VIEWER();
    if (runShell("command -v xvfb-run").exitCode != 0)
        GTEST_SKIP() << "xvfb-run is not installed (scripts/install-deps.sh installs it)";
    test::ScratchDir dir("viewer-screenshot");
    // A small meta-relief (base + fabric, as the main job, at 256^2) that both tools compose the same way:
    // the viewer at --resolution 256, `strata render` at the material's resolution 256.
    test::writeBytes(dir / "m.json", R"({"resolution": 256, "color_from": 1, "layers": [
        {"pattern": "base", "size": 256},
        {"pattern": "fabric", "size": 128, "tiling": 4, "weight_depth": 0.3, "weight_normal": 0.3}]})");
    const std::string common = " --mesh teapot --size 256x192";
    const auto runViewer = [&](const std::string& args) {
        return runUnderXvfb(viewer() + " " + quoted(dir / "m.json") + args);
    };
    const test::CommandResult scene =
        runViewer(common + " --resolution 256 --no-ui --screenshot " + quoted(dir / "view.png"));
    ASSERT_EQ(scene.exitCode, 0) << scene.output;
    const test::CommandResult panels =
        runViewer(common + " --resolution 256 --screenshot " + quoted(dir / "panels.png"));
    ASSERT_EQ(panels.exitCode, 0) << panels.output;
    const test::CommandResult render = test::runCli("render --material " + quoted(dir / "m.json") + common +
                                                    " --samples 1 -o " + quoted(dir / "render.png"));
    if (render.exitCode == 5)
        GTEST_SKIP() << "no headless OpenGL context for strata render: " << render.output;
    ASSERT_EQ(render.exitCode, 0) << render.output;

    const Image view = readImage(dir / "view.png");
    const Image withPanels = readImage(dir / "panels.png");
    const Image reference = readImage(dir / "render.png");
    ASSERT_EQ(view.width(), 256);
    ASSERT_EQ(view.height(), 192);
    ASSERT_EQ(view.channels(), 3);
    ASSERT_EQ(withPanels.width(), 256);
    ASSERT_EQ(reference.width(), 256);
    ASSERT_EQ(reference.height(), 192);

    // Not blank: the corner is the background (0.16, 0.17, 0.19) to within 8-bit rounding, and the centre,
    // where the teapot's body is, is not.
    const glm::dvec3 background = PictureSettings{}.background;
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(static_cast<double>(view.at(2, 2, c)), background[c], 1.0 / 255.0 + 1e-6);
    const int teapot = pixelsUnlikeTheBackground(view, 96, 72, 160, 120);
    EXPECT_GT(teapot, 64 * 48 * 9 / 10) << "the centre of the window should show the teapot";

    // The same picture as `strata render`: both draw with ReliefRenderer, with the same camera (frameCamera
    // of the teapot at 4:3), light, settings and material.
    expectSamePicture(view, reference, scene.output, render.output);

    // The panels draw: the Scene panel covers the top-left corner, which without panels is background.
    EXPECT_GT(meanAbsDiff(withPanels, view, 10, 10, 100, 60), 0.05);
}

TEST(ViewerCli, LiveScreenshotMatchesStrataRenderLive) {
    // --meta live: the viewer's live pipeline (the layers uploaded as they are, the composed depth's exact
    // AO baked on its worker) against `strata render --meta live` of the same scene.
    SKIP_WITHOUT_VIEWER();
    if (runShell("command -v xvfb-run").exitCode != 0)
        GTEST_SKIP() << "xvfb-run is not installed (scripts/install-deps.sh installs it)";
    test::ScratchDir dir("viewer-live");
    test::writeBytes(dir / "m.json", R"({"resolution": 256, "color_from": 1, "layers": [
        {"pattern": "base", "size": 256},
        {"pattern": "fabric", "size": 128, "tiling": 4, "weight_depth": 0.3, "weight_normal": 0.3}]})");
    const std::string common = " --mesh teapot --size 256x192 --meta live";
    const test::CommandResult scene =
        runUnderXvfb(viewer() + " " + quoted(dir / "m.json") + common +
                     " --resolution 256 --no-ui --screenshot " + quoted(dir / "view.png"));
    ASSERT_EQ(scene.exitCode, 0) << scene.output;
    const test::CommandResult render = test::runCli("render --material " + quoted(dir / "m.json") + common +
                                                    " --samples 1 -o " + quoted(dir / "render.png"));
    if (render.exitCode == 5)
        GTEST_SKIP() << "no headless OpenGL context for strata render: " << render.output;
    ASSERT_EQ(render.exitCode, 0) << render.output;
    const Image view = readImage(dir / "view.png");
    const Image reference = readImage(dir / "render.png");
    ASSERT_EQ(view.width(), 256);
    ASSERT_EQ(view.height(), 192);
    ASSERT_EQ(reference.width(), 256);
    ASSERT_EQ(reference.height(), 192);
    expectSamePicture(view, reference, scene.output, render.output);

    // maxmip cannot draw a live material: exit 3 with the renderer's reason, nothing written (in the window
    // the technique is not offered while live, and the panel shows a render error).
    test::writeBytes(dir / "maxmip.json", R"({"technique": "maxmip"})");
    const test::CommandResult maxmip =
        runUnderXvfb(viewer() + " " + quoted(dir / "m.json") + common + " --scene " +
                     quoted(dir / "maxmip.json") + " --screenshot " + quoted(dir / "maxmip.png"));
    EXPECT_EQ(maxmip.exitCode, 3) << maxmip.output;
    EXPECT_NE(maxmip.output.find("maxmip needs a baked material"), std::string::npos) << maxmip.output;
    EXPECT_FALSE(fs::exists(dir / "maxmip.png"));
}

// A tiny baked asset: `strata gdm bake --meso weave --size 16x16x4 --dirs 8x16` (rank 8, and the raw GDM
// with `keepRaw`), about 0.1 s.
void bakeTinyAsset(const fs::path& dir, bool keepRaw) {
    const test::CommandResult bake =
        test::runCli("gdm bake --meso weave --size 16x16x4 --dirs 8x16" +
                     std::string(keepRaw ? " --keep-raw" : "") + " -o " + quoted(dir));
    ASSERT_EQ(bake.exitCode, 0) << bake.output;
}

TEST(ViewerCli, GdmExitCodesWithoutADisplay) {
    // A bad --gdm is the input's error, found before a window would open (so without a display it is that
    // error, not 5), and nothing is written.
    SKIP_WITHOUT_VIEWER();
    test::ScratchDir dir("viewer-gdm-exit");
    ASSERT_NO_FATAL_FAILURE(bakeTinyAsset(dir / "tiny", true));
    ASSERT_NO_FATAL_FAILURE(bakeTinyAsset(dir / "svd-only", false));
    const std::string shot = " --screenshot " + quoted(dir / "a.png");
    // 3: neither an asset nor a built-in (the message lists the built-ins).
    test::CommandResult run = runWithoutDisplay("--gdm no-such-meso" + shot);
    EXPECT_EQ(run.exitCode, 3) << run.output;
    EXPECT_NE(run.output.find("neither a GDM asset directory nor a built-in mesostructure"),
              std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("weave"), std::string::npos) << run.output;
    // 2: a directory that is not an asset.
    fs::create_directories(dir / "empty");
    run = runWithoutDisplay("--gdm " + quoted(dir / "empty") + shot);
    EXPECT_EQ(run.exitCode, 2) << run.output;
    EXPECT_NE(run.output.find("not a GDM asset directory"), std::string::npos) << run.output;
    // 3: a rank the asset lacks, from the flag and from a scene file.
    run = runWithoutDisplay("--gdm " + quoted(dir / "tiny") + " --gdm-rank 9" + shot);
    EXPECT_EQ(run.exitCode, 3) << run.output;
    EXPECT_NE(run.output.find("gdm_rank 9 is more than the 8 terms"), std::string::npos) << run.output;
    test::writeBytes(dir / "raw.json", R"({"mesh": "sphere", "gdm": "svd-only", "gdm_rank": "raw"})");
    run = runWithoutDisplay("--scene " + quoted(dir / "raw.json") + shot);
    EXPECT_EQ(run.exitCode, 3) << run.output;
    EXPECT_NE(run.output.find("holds no raw GDM"), std::string::npos) << run.output;
    // 1: a GDM with a material, GDM settings without a GDM, a malformed rank.
    run = runWithoutDisplay("stone-bricks --gdm " + quoted(dir / "tiny") + shot);
    EXPECT_EQ(run.exitCode, 1) << run.output;
    run = runWithoutDisplay("--gdm-rank 2" + shot);
    EXPECT_EQ(run.exitCode, 1) << run.output;
    run = runWithoutDisplay("--gdm " + quoted(dir / "tiny") + " --gdm-rank two" + shot);
    EXPECT_EQ(run.exitCode, 1) << run.output;
    // 5: a valid GDM without a display.
    run = runWithoutDisplay("--gdm " + quoted(dir / "tiny") + " --mesh sphere" + shot);
    EXPECT_EQ(run.exitCode, 5) << run.output;
    EXPECT_NE(run.output.find("xvfb-run"), std::string::npos) << run.output;
    // The environment's flags, as strata render's: 1 without a GDM or out of range (naming the flag), 3 for
    // an environment that is neither a built-in sky nor a file.
    run = runWithoutDisplay("--env sky-clear" + shot);
    EXPECT_EQ(run.exitCode, 1) << run.output;
    EXPECT_NE(run.output.find("give --gdm"), std::string::npos) << run.output;
    for (const std::string flag :
         {"--env-rank 0", "--env-rank 49", "--env-bounces 9", "--env-intensity -1", "--env-rotation inf"}) {
        run = runWithoutDisplay("--gdm " + quoted(dir / "tiny") + " --env sky-clear " + flag + shot);
        EXPECT_EQ(run.exitCode, 1) << flag << ": " << run.output;
        EXPECT_NE(run.output.find(flag.substr(0, flag.find(' '))), std::string::npos) << run.output;
    }
    run = runWithoutDisplay("--gdm " + quoted(dir / "tiny") + " --env sky-mars" + shot);
    EXPECT_EQ(run.exitCode, 3) << run.output;
    EXPECT_NE(run.output.find("sky-mars"), std::string::npos) << run.output;
    EXPECT_EQ(test::countEntries(dir.path()), 4);  // tiny, svd-only, empty, raw.json: nothing was written
}

// Reads an 8-bit screenshot and a 16-bit `strata render` picture of the same scene: with the same float
// picture, each 8-bit value is round(v * 255) and each 16-bit one round(v * 65535), so they can differ by
// at most half an 8-bit step plus half a 16-bit one. Only when both ran on llvmpipe (another driver may
// rasterise differently).
void expectSameGdmPicture(const Image& view, const Image& reference, const std::string& viewerOutput,
                          const std::string& renderOutput) {
    if (viewerOutput.find("llvmpipe") == std::string::npos ||
        renderOutput.find("llvmpipe") == std::string::npos) {
        std::cout << "not comparing with strata render: different OpenGL implementations\n"
                  << viewerOutput << renderOutput;
        return;
    }
    EXPECT_LE(test::maxAbsDiff(view, reference), 0.5 / 255.0 + 0.5 / 65535.0 + 1e-6)
        << "the viewer's window should hold strata render's picture, rounded to 8 bits";
}

TEST(ViewerCli, GdmScreenshotUnderXvfbMatchesStrataRender) {
    SKIP_WITHOUT_VIEWER();
    if (runShell("command -v xvfb-run").exitCode != 0)
        GTEST_SKIP() << "xvfb-run is not installed (scripts/install-deps.sh installs it)";
    test::ScratchDir dir("viewer-gdm");
    ASSERT_NO_FATAL_FAILURE(bakeTinyAsset(dir / "tiny", true));
    // No camera: both frame the shell's bounds at 4:3 (frameCamera).
    const std::string common = " --gdm " + quoted(dir / "tiny") + " --mesh sphere --size 256x192";
    const test::CommandResult scene =
        runUnderXvfb(viewer() + common + " --no-ui --screenshot " + quoted(dir / "view.png"));
    ASSERT_EQ(scene.exitCode, 0) << scene.output;
    EXPECT_NE(scene.output.find("ms per frame after the first"), std::string::npos) << scene.output;
    const test::CommandResult panels =
        runUnderXvfb(viewer() + common + " --screenshot " + quoted(dir / "panels.png"));
    ASSERT_EQ(panels.exitCode, 0) << panels.output;
    const test::CommandResult render =
        test::runCli("render" + common + " --samples 1 --bit-depth 16 -o " + quoted(dir / "render.png"));
    if (render.exitCode == 5)
        GTEST_SKIP() << "no headless OpenGL context for strata render: " << render.output;
    ASSERT_EQ(render.exitCode, 0) << render.output;

    const Image view = readImage(dir / "view.png");
    const Image withPanels = readImage(dir / "panels.png");
    const Image reference = readImage(dir / "render.png");
    ASSERT_EQ(view.width(), 256);
    ASSERT_EQ(view.height(), 192);
    ASSERT_EQ(view.channels(), 3);
    ASSERT_EQ(withPanels.width(), 256);
    ASSERT_EQ(reference.width(), 256);
    ASSERT_EQ(reference.height(), 192);
    ASSERT_EQ(reference.channels(), 3);

    // Not blank: the corner is the background to within 8-bit rounding, and the centre, where the sphere's
    // shell is, is not (the weave's threads in indigo and cream; measured: every pixel of the box more than
    // 0.1 from the background in the sum of its channels but 2 %).
    const glm::dvec3 background = PictureSettings{}.background;
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(static_cast<double>(view.at(2, 2, c)), background[c], 0.5 / 255.0 + 1e-6);
    const int shell = pixelsUnlikeTheBackground(view, 112, 80, 144, 112);
    EXPECT_GT(shell, 32 * 32 * 9 / 10) << "the centre of the window should show the sphere's weave";

    // The same picture as `strata render --gdm`: the same renderer and picture function (gdm_picture.h) with
    // the same camera, light and settings, the window holding its 8-bit rounding.
    expectSameGdmPicture(view, reference, scene.output, render.output);

    // The panels draw: the Scene panel covers the top-left corner, which without panels is background.
    EXPECT_GT(meanAbsDiff(withPanels, view, 10, 10, 100, 60), 0.05);

    // Technique and rank from the command line (the panel's controls set the same settings): march at rank
    // 2 against strata render's, and a picture that differs from the first (measured: 9.4 % of the values
    // more than 2/255 apart; the same settings give the same picture, as above, so 3 % tells them apart).
    const std::string other = " --gdm-technique march --gdm-rank 2";
    const test::CommandResult marched =
        runUnderXvfb(viewer() + common + other + " --no-ui --screenshot " + quoted(dir / "march.png"));
    ASSERT_EQ(marched.exitCode, 0) << marched.output;
    const test::CommandResult renderMarched = test::runCli(
        "render" + common + other + " --samples 1 --bit-depth 16 -o " + quoted(dir / "render-march.png"));
    ASSERT_EQ(renderMarched.exitCode, 0) << renderMarched.output;
    const Image march = readImage(dir / "march.png");
    expectSameGdmPicture(march, readImage(dir / "render-march.png"), marched.output, renderMarched.output);
    EXPECT_GT(percentApart(march, view), 3.0);
}

TEST(ViewerCli, GdmEnvironmentScreenshotUnderXvfbMatchesStrataRender) {
    SKIP_WITHOUT_VIEWER();
    if (runShell("command -v xvfb-run").exitCode != 0)
        GTEST_SKIP() << "xvfb-run is not installed (scripts/install-deps.sh installs it)";
    test::ScratchDir dir("viewer-gdm-env");
    ASSERT_NO_FATAL_FAILURE(bakeTinyAsset(dir / "tiny", true));
    // The viewer reads the environment from a scene file's keys, strata render from its flags: the sunset
    // sky turned by 120 degrees.
    const fs::path scene = dir / "sunset.json";
    test::writeBytes(scene, R"({"mesh": "sphere", "gdm": ")" + (dir / "tiny").string() +
                                R"(", "env": "sky-sunset", "env_rotation": 120})");
    const std::string size = " --size 256x192";
    const test::CommandResult view = runUnderXvfb(viewer() + " --scene " + quoted(scene) + size +
                                                  " --no-ui --screenshot " + quoted(dir / "view.png"));
    ASSERT_EQ(view.exitCode, 0) << view.output;
    const std::string common = " --gdm " + quoted(dir / "tiny") + " --mesh sphere" + size;
    const test::CommandResult render = test::runCli(
        "render" + common + " --env sky-sunset --env-rotation 120 --samples 1 --bit-depth 16 -o " +
        quoted(dir / "render.png"));
    if (render.exitCode == 5)
        GTEST_SKIP() << "no headless OpenGL context for strata render: " << render.output;
    ASSERT_EQ(render.exitCode, 0) << render.output;
    EXPECT_NE(render.output.find("sky-sunset (RTV rank 4, 1 bounce)"), std::string::npos) << render.output;
    const Image picture = readImage(dir / "view.png");
    const Image reference = readImage(dir / "render.png");
    ASSERT_EQ(picture.width(), 256);
    ASSERT_EQ(picture.height(), 192);
    ASSERT_EQ(reference.width(), 256);
    ASSERT_EQ(reference.height(), 192);
    expectSameGdmPicture(picture, reference, view.output, render.output);

    // The flags as the keys, unturned: strata render's picture again, and another one than the scene's
    // (measured: 6.6 % of the values more than 2/255 apart, with the point light on; an unchanged
    // picture is the same to 8-bit rounding, above).
    const std::string sunset = common + " --env sky-sunset --env-rotation 0";
    const test::CommandResult unturned =
        runUnderXvfb(viewer() + sunset + " --no-ui --screenshot " + quoted(dir / "unturned.png"));
    ASSERT_EQ(unturned.exitCode, 0) << unturned.output;
    const test::CommandResult renderUnturned = test::runCli(
        "render" + sunset + " --samples 1 --bit-depth 16 -o " + quoted(dir / "render-unturned.png"));
    ASSERT_EQ(renderUnturned.exitCode, 0) << renderUnturned.output;
    const Image unturnedPicture = readImage(dir / "unturned.png");
    expectSameGdmPicture(unturnedPicture, readImage(dir / "render-unturned.png"), unturned.output,
                         renderUnturned.output);
    EXPECT_GT(percentApart(unturnedPicture, picture), 3.0);

    // The panels draw with the environment's section (the Scene panel covers the top-left corner).
    const test::CommandResult panels =
        runUnderXvfb(viewer() + sunset + " --screenshot " + quoted(dir / "panels.png"));
    ASSERT_EQ(panels.exitCode, 0) << panels.output;
    EXPECT_GT(meanAbsDiff(readImage(dir / "panels.png"), unturnedPicture, 10, 10, 100, 60), 0.05);
}

}  // namespace
}  // namespace strata::view
