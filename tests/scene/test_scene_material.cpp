// A scene's material made ready for the renderer (strata/scene/scene_material.h): the kind chosen, the AO
// baked for the render, and the same maps a front end would make by hand with the lower-level calls.
#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/occlusion/meta_relief_ao.h"
#include "strata/relief/patterns.h"
#include "strata/scene/material.h"
#include "strata/scene/scene_material.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

namespace strata {
namespace {

namespace fs = std::filesystem;

// Two small pattern layers, so that every bake here takes milliseconds.
void writeTwoLayerMaterial(const fs::path& path, const std::string& ao) {
    std::ofstream(path) << R"({ "resolution": 64, "depth_scale": 0.08, "ao": ")" << ao << R"(",
        "layers": [ { "pattern": "stone-bricks", "size": 64, "seed": 3 },
                    { "pattern": "fabric", "size": 64, "seed": 5, "tiling": 2,
                      "weight_depth": 0.5, "weight_normal": 0.5 } ] })";
}

bool contains(const std::vector<fs::path>& paths, const fs::path& path) {
    return std::find(paths.begin(), paths.end(), path) != paths.end();
}

TEST(SceneMaterial, KindFollowsTheMetaPathAndTechnique) {
    Scene scene;
    EXPECT_EQ(sceneMaterialKind(scene), MaterialKind::Baked);
    scene.meta = MetaPath::Live;
    EXPECT_EQ(sceneMaterialKind(scene), MaterialKind::Live);
    // Dual-depth needs a dual-depth texture: the built-in material is not one, so it is drawn baked.
    scene.meta = MetaPath::Baked;
    scene.relief.technique = Technique::DualDepth;
    EXPECT_EQ(sceneMaterialKind(scene), MaterialKind::Baked);
}

TEST(SceneMaterial, DepthMapIsBakedWithoutAo) {
    const test::ScratchDir dir("scene_material_depth");
    Image depth(8, 8, 1);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) depth.at(x, y) = static_cast<float>((x + y) % 4) / 4.0f;
    writePng(dir / "d.png", depth, {PngBitDepth::Sixteen, false});
    Scene scene;
    scene.depthMap = dir / "d.png";
    scene.relief.depthScale = 0.1;
    const SceneMaterial material = prepareSceneMaterial(scene);
    EXPECT_EQ(material.kind, MaterialKind::Baked);
    EXPECT_EQ(material.depthScale, 0.1);
    EXPECT_TRUE(material.texture.ao.empty());
    // The depth as read back from 16 bits: within half a step of 1/65535.
    EXPECT_LE(test::maxAbsDiff(material.texture.depth, depth), 0.5 / 65535.0 + 1e-9);
    EXPECT_EQ(material.texture.normal.channels(), 3);
    EXPECT_TRUE(contains(sceneInputs(scene), dir / "d.png"));
}

TEST(SceneMaterial, BakedAoIsRebakedAtTheRendersDepthScale) {
    Scene scene;
    scene.material = "stone-bricks";
    scene.relief.depthScale = 0.12;  // the pattern's own S differs
    scene.relief.aoRescale = AoRescale::Exact;
    const SceneMaterial material = prepareSceneMaterial(scene);
    ASSERT_EQ(material.kind, MaterialKind::Baked);
    ASSERT_NE(material.texture.depthScale, 0.12);
    EXPECT_EQ(material.aoDepthScale, 0.12);
    AoParams params;
    params.depthScale = 0.12;
    // The same bake as aoForRender's: bit for bit.
    EXPECT_EQ(test::maxAbsDiff(material.texture.ao, bakeAo(material.texture.depth, params)), 0.0);

    // Paper rescale: the map stays as baked, valid at the texture's own S (the shader rescales it).
    scene.relief.aoRescale = AoRescale::Paper;
    const SceneMaterial paper = prepareSceneMaterial(scene);
    EXPECT_EQ(paper.aoDepthScale, paper.texture.depthScale);
}

TEST(SceneMaterial, LiveLayersCarryTheirOwnAoMaps) {
    const test::ScratchDir dir("scene_material_live");
    writeTwoLayerMaterial(dir / "m.json", "multiply");
    Scene scene;
    scene.material = (dir / "m.json").string();
    scene.meta = MetaPath::Live;
    const SceneMaterial material = prepareSceneMaterial(scene);
    ASSERT_EQ(material.kind, MaterialKind::Live);
    ASSERT_EQ(material.layers.size(), 2u);
    EXPECT_EQ(material.liveAo, MetaAoMode::Multiply);
    EXPECT_EQ(material.depthScale, 0.08);
    EXPECT_TRUE(material.composedAo.empty());
    // Each layer's map is bakeAo at the layer's share of the depth (metaReliefLayerAoParams), bit for bit.
    const auto params = metaReliefLayerAoParams(material.layers, material.compose, material.aoParams);
    ASSERT_EQ(material.layerAo.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        ASSERT_TRUE(params[i].has_value());
        EXPECT_EQ(test::maxAbsDiff(material.layerAo[i], bakeAo(material.layers[i].texture.depth, *params[i])),
                  0.0);
    }
    // The material JSON is an input, and so is the scene's own source when it has one.
    EXPECT_TRUE(contains(sceneInputs(scene), dir / "m.json"));

    // With the scene's AO off there is nothing to bake.
    scene.relief.ao = false;
    const SceneMaterial off = prepareSceneMaterial(scene);
    EXPECT_FALSE(off.liveAo.has_value());
    EXPECT_TRUE(off.layerAo.empty());
}

TEST(SceneMaterial, LiveExactAoIsTheComposedDepthsAtTheRightScale) {
    const test::ScratchDir dir("scene_material_exact");
    writeTwoLayerMaterial(dir / "m.json", "exact");
    Scene scene;
    scene.material = (dir / "m.json").string();
    scene.meta = MetaPath::Live;
    scene.relief.depthScale = 0.1;
    scene.relief.aoRescale = AoRescale::Exact;
    const SceneMaterial exact = prepareSceneMaterial(scene);
    EXPECT_TRUE(exact.layerAo.empty());
    ASSERT_FALSE(exact.composedAo.empty());
    EXPECT_EQ(exact.composedAoDepthScale, 0.1);  // re-baked at the render's S
    AoParams params = exact.aoParams;
    params.depthScale = 0.1;
    const Composition composition = compose(exact.layers, exact.compose);
    EXPECT_EQ(test::maxAbsDiff(exact.composedAo, bakeAo(composition.texture.depth, params)), 0.0);

    scene.relief.aoRescale = AoRescale::Paper;  // baked at the material's S, rescaled by the shader
    EXPECT_EQ(prepareSceneMaterial(scene).composedAoDepthScale, 0.08);
}

TEST(SceneMaterial, LiveNeedsLayers) {
    Scene scene;
    scene.material = "stone-bricks";  // a pattern has no layers
    scene.meta = MetaPath::Live;
    EXPECT_THROW(prepareSceneMaterial(scene), Error);
}

}  // namespace
}  // namespace strata
