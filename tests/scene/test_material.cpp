// The material file: strict parsing with errors that name the key, and loading layers.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/relief/patterns.h"
#include "strata/relief/texture_set.h"
#include "strata/scene/material.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace strata {
namespace {

using nlohmann::json;

// The issue's material, with the fabric as files next to the material.
json issueMaterial() {
    return json::parse(R"({ "resolution": 64, "depth_scale": 0.08, "normals": "paper",
      "color_from": 1,
      "layers": [
        { "pattern": "base",   "size": 64, "seed": 1, "tiling": 1.0, "weight_depth": 1.0, "weight_normal": 1.0 },
        { "depth": "fabric_depth.png", "normal": "fabric_normal.png", "color": "fabric.png",
          "tiling": 5.5, "weight_depth": 0.3, "weight_normal": 0.3 } ] })");
}

class MaterialTest : public ::testing::Test {
protected:
    void SetUp() override {
        const ReliefTexture fabric = makePattern("fabric", {64, 1, 0.08});
        writePng(dir / "fabric_depth.png", fabric.depth);
        writePng(dir / "fabric_normal.png", encodeNormals(fabric.normal));
        writePng(dir / "fabric.png", fabric.color, {PngBitDepth::Eight, true});
    }

    std::filesystem::path materialPath() const { return dir / "material.json"; }

    // Expects parseMaterial to throw `kind` with `mention` in the message.
    void expectError(const json& document, ErrorKind kind, const std::string& mention) const {
        try {
            parseMaterial(document, materialPath());
            FAIL() << "expected an error mentioning " << mention;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), kind) << e.what();
            EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
        }
    }

    test::ScratchDir dir{"material"};
};

TEST_F(MaterialTest, TheIssuesExampleParsesAndComposes) {
    const Material material = parseMaterial(issueMaterial(), materialPath());
    ASSERT_EQ(material.layers.size(), 2u);
    EXPECT_EQ(material.compose.resolution, 64);
    EXPECT_EQ(material.compose.colorFrom, 1);
    EXPECT_EQ(*material.layers[0].pattern, "base");
    EXPECT_EQ(*material.layers[1].depthFile, dir / "fabric_depth.png");  // relative to the material file
    EXPECT_DOUBLE_EQ(material.layers[1].tiling, 5.5);
    const std::vector<CompositionLayer> layers = loadLayers(material);
    const Composition result = compose(layers, material.compose);
    EXPECT_EQ(result.texture.depth.width(), 64);
    EXPECT_EQ(result.texture.color.channels(), 3);
    EXPECT_EQ(result.warnings.size(), 1u);  // tiling 5.5 does not tile
}

TEST_F(MaterialTest, APatternLayerEqualsThePatternWithTheSameDefaults) {
    const Material material =
        parseMaterial(json::parse(R"({"layers": [{"pattern": "base", "size": 128}]})"), materialPath());
    const std::vector<CompositionLayer> layers = loadLayers(material);
    PatternParams params;
    params.size = 128;
    const ReliefTexture expected = makePattern("base", params);
    EXPECT_EQ(layers[0].texture.depth, expected.depth);
    EXPECT_EQ(layers[0].texture.normal, expected.normal);
    EXPECT_EQ(layers[0].texture.color, expected.color);
}

TEST_F(MaterialTest, AHeightLayerIsReadAsOneMinusHeight) {
    Image height(64, 64, 1, 0.25f);
    writePng(dir / "h.png", height);
    const Material material =
        parseMaterial(json::parse(R"({"layers": [{"height": "h.png"}]})"), materialPath());
    const auto layers = loadLayers(material);
    EXPECT_NEAR(layers[0].texture.depth.at(3, 3), 0.75f, 1.0 / 65535);  // one 16-bit step
}

TEST_F(MaterialTest, EveryBadKeyIsNamed) {
    json doc = issueMaterial();
    doc["layers"][1]["weigth_depth"] = 0.3;
    expectError(doc, ErrorKind::InvalidInput, "layers[1].weigth_depth: unknown key");

    doc = issueMaterial();
    doc["colour_from"] = 1;
    expectError(doc, ErrorKind::InvalidInput, "colour_from: unknown key");

    doc = issueMaterial();
    doc["layers"][1]["tiling"] = "5.5";
    expectError(doc, ErrorKind::InvalidInput, "layers[1].tiling: must be a number, got string");

    doc = issueMaterial();
    doc["layers"][0]["weight_depth"] = -1.0;
    expectError(doc, ErrorKind::InvalidInput, "layers[0].weight_depth: must be >= 0, got -1");

    doc = issueMaterial();
    doc["layers"][1]["depth"] = "missing.png";
    expectError(doc, ErrorKind::Io, "layers[1].depth: " + (dir / "missing.png").string() + ": no such file");

    doc = issueMaterial();
    doc["layers"][1]["height"] = "fabric_depth.png";
    expectError(doc, ErrorKind::InvalidInput, "either \"depth\" or \"height\"");

    doc = issueMaterial();
    doc["layers"][0]["depth"] = "fabric_depth.png";
    expectError(doc, ErrorKind::InvalidInput, "layers[0].depth: a layer uses either \"pattern\" or files");

    doc = issueMaterial();
    doc["layers"][0]["pattern"] = "tweed";
    expectError(doc, ErrorKind::InvalidInput, "layers[0].pattern: unknown pattern \"tweed\"");

    doc = issueMaterial();
    doc["layers"][0]["size"] = 10;
    expectError(doc, ErrorKind::InvalidInput, "layers[0].size: must be in [64, 4096], got 10");

    doc = issueMaterial();
    doc["color_from"] = 2;
    expectError(doc, ErrorKind::InvalidInput, "color_from: must be in [-1, 1], got 2");

    doc = issueMaterial();
    doc["normals"] = "average";
    expectError(doc, ErrorKind::InvalidInput, "normals: must be \"paper\" or \"consistent\"");

    doc = issueMaterial();
    doc["layers"][0]["weight_depth"] = 0.0;
    doc["layers"][1]["weight_depth"] = 0.0;
    expectError(doc, ErrorKind::InvalidInput, "weight_depth values sum to 0");

    doc = issueMaterial();
    doc["layers"] = json::array();
    expectError(doc, ErrorKind::InvalidInput, "layers: must hold at least one layer");

    expectError(json::array(), ErrorKind::InvalidInput, "must be a JSON object");
}

TEST_F(MaterialTest, TheAoKeysDefaultToTheExactSweep) {
    const Material defaults = parseMaterial(issueMaterial(), materialPath());
    ASSERT_TRUE(defaults.ao.has_value());
    EXPECT_EQ(*defaults.ao, MetaAoMode::Exact);
    EXPECT_EQ(defaults.aoParams.method, AoMethod::Sweep);
    EXPECT_EQ(defaults.aoParams.radius, 1.0);
    EXPECT_EQ(defaults.aoParams.directions, 50);

    json doc = issueMaterial();
    doc["ao"] = "multiply";
    doc["ao_method"] = "paper";
    doc["ao_radius"] = 2.5;
    doc["ao_directions"] = 16;
    const Material chosen = parseMaterial(doc, materialPath());
    EXPECT_EQ(*chosen.ao, MetaAoMode::Multiply);
    EXPECT_EQ(chosen.aoParams.method, AoMethod::Paper);
    EXPECT_EQ(chosen.aoParams.radius, 2.5);
    EXPECT_EQ(chosen.aoParams.directions, 16);

    doc = issueMaterial();
    doc["ao"] = "min";
    EXPECT_EQ(*parseMaterial(doc, materialPath()).ao, MetaAoMode::Min);
    doc["ao"] = "none";
    EXPECT_FALSE(parseMaterial(doc, materialPath()).ao.has_value());
}

TEST_F(MaterialTest, EveryBadAoKeyIsNamed) {
    json doc = issueMaterial();
    doc["ao"] = "product";
    expectError(doc, ErrorKind::InvalidInput,
                "material.json: ao: must be \"exact\", \"multiply\", \"min\" or \"none\", got \"product\"");

    doc = issueMaterial();
    doc["ao"] = true;
    expectError(doc, ErrorKind::InvalidInput, "ao: must be a string, got boolean");

    doc = issueMaterial();
    doc["ao_method"] = "fast";
    expectError(doc, ErrorKind::InvalidInput,
                "ao_method: must be \"sweep\", \"paper\" or \"brute\", got \"fast\"");

    doc = issueMaterial();
    doc["ao_radius"] = 0.0;
    expectError(doc, ErrorKind::InvalidInput, "ao_radius: must be in (0, 16] tile widths, got 0");
    doc["ao_radius"] = 17;
    expectError(doc, ErrorKind::InvalidInput, "ao_radius: must be in (0, 16] tile widths, got 17");

    doc = issueMaterial();
    doc["ao_directions"] = 2;
    expectError(doc, ErrorKind::InvalidInput, "ao_directions: must be in [3, 1024], got 2");
    doc["ao_directions"] = 12.5;
    expectError(doc, ErrorKind::InvalidInput, "ao_directions: must be an integer, got 12.5");

    doc = issueMaterial();
    doc["ao"] = "none";
    doc["ao_radius"] = 2.0;
    expectError(doc, ErrorKind::InvalidInput, "ao_radius: given with \"ao\": \"none\"");

    doc = issueMaterial();
    doc["ao_mode"] = "exact";
    expectError(doc, ErrorKind::InvalidInput, "ao_mode: unknown key");
}

TEST_F(MaterialTest, MalformedJsonIsInvalidInputWithItsPosition) {
    test::writeBytes(materialPath(), "{ \"layers\": [ { \"pattern\": \"base\", } ] }");
    try {
        readMaterial(materialPath());
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("material.json: not valid JSON"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos) << e.what();
    }
}

TEST_F(MaterialTest, InputsListTheMaterialAndItsFiles) {
    const Material material = parseMaterial(issueMaterial(), materialPath());
    const auto inputs = materialInputs(material);
    EXPECT_EQ(inputs.size(), 4u);  // material, depth, normal, colour
}

}  // namespace
}  // namespace strata
