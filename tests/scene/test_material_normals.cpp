// "normal_y" of a material layer: "auto" resolves against the layer's own depth, and an explicit value
// that the gradient contradicts is refused (resolveNormalY, the same rule as `strata import`).
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/relief/patterns.h"
#include "strata/relief/relief_texture.h"
#include "strata/scene/material.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace strata {
namespace {

using nlohmann::json;

class MaterialNormalY : public ::testing::Test {
protected:
    void SetUp() override {
        PatternParams params;
        params.size = 64;
        pattern = makePattern("mini-bricks", params);
        writePng(dir / "depth.png", pattern.depth);
        Image directX = pattern.normal;
        for (int y = 0; y < directX.height(); ++y)
            for (int x = 0; x < directX.width(); ++x) directX.at(x, y, 1) *= -1.0f;
        writePng(dir / "dx.png", encodeNormals(directX));
    }
    Material material(const std::string& normalY) const {
        return parseMaterial(
            json{{"layers", {{{"depth", "depth.png"}, {"normal", "dx.png"}, {"normal_y", normalY}}}}},
            dir / "material.json");
    }
    test::ScratchDir dir{"material_normal_y"};
    ReliefTexture pattern;
};

TEST_F(MaterialNormalY, AutoDetectsDirectXAndConverts) {
    std::vector<std::string> notes;
    const std::vector<CompositionLayer> layers = loadLayers(material("auto"), &notes);
    ASSERT_EQ(layers.size(), 1u);
    // Back to the pattern's own normals up to 16-bit quantisation (a few 1/65535 steps, renormalised).
    EXPECT_LT(test::maxAbsDiff(layers[0].texture.normal, pattern.normal), 1e-4);
    ASSERT_FALSE(notes.empty());
    EXPECT_NE(notes.back().find("normal_y auto: DirectX (green down)"), std::string::npos) << notes.back();
}

TEST_F(MaterialNormalY, ExplicitUpContradictedIsRefused) {
    try {
        loadLayers(material("up"));
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        const std::string message = e.what();
        EXPECT_EQ(message.rfind("layers[0] normal ", 0), 0u) << message;
        EXPECT_NE(message.find("dx.png: read as up (OpenGL), but its gradient says DirectX (green down)"),
                  std::string::npos)
            << message;
        EXPECT_NE(message.find("; set \"normal_y\": \"down\" or \"auto\""), std::string::npos) << message;
    }
    EXPECT_NO_THROW(loadLayers(material("down")));
}

TEST_F(MaterialNormalY, OtherValuesAreRefused) {
    try {
        material("sideways");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("must be \"up\" (OpenGL), \"down\" (DirectX) or \"auto\", got "
                                             "\"sideways\""),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace strata
