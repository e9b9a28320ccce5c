// AO of a meta-relief (meta_relief_ao.h): the exact mode against bakeAo of the composed depth, the
// paper's per-layer combination against single-layer bakes at the derived depth scale and radius.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/occlusion/meta_relief_ao.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

// d = 0.5 + 0.5 sin(2 pi k u) sin(2 pi k v) on an n x n map: k x k bumps per tile, tileable, with
// plenty of occlusion at a steep depth scale.
Image bumps(int n, int k) {
    Image depth(n, n, 1);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            depth.at(x, y) = static_cast<float>(0.5 + 0.5 * std::sin(2.0 * kPi * k * depth.texelU(x)) *
                                                          std::sin(2.0 * kPi * k * depth.texelV(y)));
    return depth;
}

CompositionLayer layer(Image depth, double tiling, double weight, const std::string& label) {
    CompositionLayer result;
    result.texture.depth = std::move(depth);
    result.texture.normal = normalsFromDepth(result.texture.depth, 0.3);
    result.tiling = tiling;
    result.weightDepth = weight;
    result.weightNormal = weight;
    result.label = label;
    return result;
}

double mean(const Image& image) {
    double sum = 0.0;
    for (const float value : image.pixels()) sum += static_cast<double>(value);
    return sum / static_cast<double>(image.pixels().size());
}

ComposeParams composeParams(double depthScale) {
    ComposeParams params;
    params.depthScale = depthScale;
    params.colorFrom = -1;
    return params;
}

TEST(MetaReliefAo, OneLayerAtWeightOneAndTilingOneIsTheSameInEveryMode) {
    const std::vector<CompositionLayer> layers{layer(bumps(32, 2), 1.0, 1.0, "bumps")};
    const ComposeParams compose = composeParams(0.3);
    const Composition composition = strata::compose(layers, compose);
    const AoParams params;
    const Image exact = metaReliefAo(layers, compose, composition, MetaAoMode::Exact, params);
    const Image multiply = metaReliefAo(layers, compose, composition, MetaAoMode::Multiply, params);
    const Image min = metaReliefAo(layers, compose, composition, MetaAoMode::Min, params);
    ASSERT_EQ(exact.width(), 32);
    ASSERT_EQ(multiply.width(), 32);
    // The lone layer's depth is composed bit for bit and baked with S_1 = S, R_1 = R; combineAo then
    // samples its AO at its own texel centres, where the bilinear weights are 0 up to double rounding
    // (~1e-16) times neighbour differences below 1: far below 1e-6.
    EXPECT_LE(test::maxAbsDiff(multiply, exact), 1e-6);
    EXPECT_LE(test::maxAbsDiff(min, exact), 1e-6);
    EXPECT_LT(mean(exact), 0.95);  // the bumps do occlude: the comparison is not of two all-1 maps
}

TEST(MetaReliefAo, TheLayerDepthScaleIsSTimesItsNormalisedWeightTimesItsTiling) {
    const std::vector<CompositionLayer> layers{
        layer(bumps(32, 2), 1.0, 1.0, "bumps"), layer(Image(16, 16, 1, 0.3f), 2.0, 0.5, "flat"),
        layer(bumps(16, 1), 32.0, 1.5, "fine"), layer(bumps(16, 1), 3.0, 0.0, "unweighted")};
    AoParams params;
    params.radius = 0.75;
    const auto perLayer = metaReliefLayerAoParams(layers, composeParams(0.3), params);
    ASSERT_EQ(perLayer.size(), 4u);
    // sum w = 3. S_i = 0.3 * w_i / 3 * t_i; R_i = min(0.75 t_i, 16). Tolerances: a few double roundings.
    ASSERT_TRUE(perLayer[0] && perLayer[1] && perLayer[2]);
    EXPECT_NEAR(perLayer[0]->depthScale, 0.1, 1e-12);
    EXPECT_NEAR(perLayer[0]->radius, 0.75, 1e-12);
    EXPECT_NEAR(perLayer[1]->depthScale, 0.1, 1e-12);  // 0.3 * 0.5 / 3 * 2
    EXPECT_NEAR(perLayer[1]->radius, 1.5, 1e-12);
    EXPECT_NEAR(perLayer[2]->depthScale, 4.8, 1e-12);  // 0.3 * 1.5 / 3 * 32
    EXPECT_EQ(perLayer[2]->radius, 16.0);              // 0.75 * 32 = 24, clamped to AoParams' 16
    EXPECT_FALSE(perLayer[3]);                         // weight 0: skipped, AO 1
    EXPECT_EQ(perLayer[0]->directions, params.directions);
    EXPECT_EQ(perLayer[0]->method, params.method);
}

TEST(MetaReliefAo, AFlatSecondLayerLeavesTheFirstLayersAoAtItsScaledDepth) {
    // Weights 1 and 0.5: the bumps enter the composed depth at 2/3 of their depth, so their AO is
    // baked at S_1 = 0.3 * (1 / 1.5) * 1 = 0.2. The flat layer has no horizon: its AO is exactly 1.
    const std::vector<CompositionLayer> layers{layer(bumps(32, 2), 1.0, 1.0, "bumps"),
                                               layer(Image(16, 16, 1, 0.3f), 2.0, 0.5, "flat")};
    const ComposeParams compose = composeParams(0.3);
    const Composition composition = strata::compose(layers, compose);
    ASSERT_EQ(composition.texture.depth.width(), 32);
    const AoParams params;
    int bakes = 0;
    const Image multiply = metaReliefAo(layers, compose, composition, MetaAoMode::Multiply, params,
                                        [&](const std::string&) { ++bakes; });
    EXPECT_EQ(bakes, 2);
    AoParams scaled = params;
    scaled.depthScale = 0.2;
    const Image expected = bakeAo(layers[0].texture.depth, scaled);
    // a * 1 = a, sampled at the bumps' own texel centres (see the first test): exact to ~1e-7.
    EXPECT_LE(test::maxAbsDiff(multiply, expected), 1e-6);
    // And the scale matters: at the full S = 0.3 the same bumps are visibly darker.
    AoParams unscaled = params;
    unscaled.depthScale = 0.3;
    EXPECT_GT(mean(multiply) - mean(bakeAo(layers[0].texture.depth, unscaled)), 0.01);
    // Min of a and 1 is a as well.
    const Image min = metaReliefAo(layers, compose, composition, MetaAoMode::Min, params);
    EXPECT_LE(test::maxAbsDiff(min, expected), 1e-6);
}

TEST(MetaReliefAo, ExactIsTheAoOfTheComposedDepth) {
    const std::vector<CompositionLayer> layers{layer(bumps(32, 1), 1.0, 1.0, "coarse"),
                                               layer(bumps(16, 1), 4.0, 0.3, "fine")};
    const ComposeParams compose = composeParams(0.2);
    const Composition composition = strata::compose(layers, compose);
    AoParams params;
    params.depthScale = 5.0;  // ignored: S is the composition's
    const Image exact = metaReliefAo(layers, compose, composition, MetaAoMode::Exact, params);
    AoParams expectedParams;
    expectedParams.depthScale = 0.2;
    // The same function on the same depth with the same parameters: identical.
    EXPECT_EQ(exact, bakeAo(composition.texture.depth, expectedParams));

    // The paper's combinations approximate it; a product of values in [0, 1] is at most their minimum.
    const Image multiply = metaReliefAo(layers, compose, composition, MetaAoMode::Multiply, params);
    const Image min = metaReliefAo(layers, compose, composition, MetaAoMode::Min, params);
    for (std::size_t i = 0; i < multiply.pixels().size(); ++i)
        ASSERT_LE(multiply.pixels()[i], min.pixels()[i] + 1e-7f) << i;  // float rounding of the product
}

TEST(MetaReliefAo, ModeNamesAndErrors) {
    for (const MetaAoMode mode : {MetaAoMode::Exact, MetaAoMode::Multiply, MetaAoMode::Min})
        EXPECT_EQ(parseMetaAoMode(toString(mode)), mode);
    for (const char* bad : {"none", "Exact", "", "product"}) {
        try {
            (void)parseMetaAoMode(bad);
            FAIL() << bad;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
            const std::string message = e.what();
            EXPECT_NE(message.find("exact, multiply or min"), std::string::npos) << message;
        }
    }
    EXPECT_EQ(metaReliefAoMethodName(MetaAoMode::Exact, AoMethod::Sweep), "sweep");
    EXPECT_EQ(metaReliefAoMethodName(MetaAoMode::Multiply, AoMethod::Sweep), "multiply of per-layer sweep");
    EXPECT_EQ(metaReliefAoMethodName(MetaAoMode::Min, AoMethod::Paper), "min of per-layer paper");
}

TEST(MetaReliefAo, BadInputIsRejectedNamingTheLayer) {
    const ComposeParams compose = composeParams(0.3);
    const AoParams params;
    // S_i above AoParams' 100: 0.3 * 1 * 400 = 120.
    const std::vector<CompositionLayer> steep{layer(bumps(16, 1), 400.0, 1.0, "steep")};
    try {
        (void)metaReliefLayerAoParams(steep, compose, params);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("steep"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("120"), std::string::npos) << e.what();
    }
    const std::vector<CompositionLayer> none{layer(bumps(16, 1), 1.0, 0.0, "zero")};
    EXPECT_THROW((void)metaReliefLayerAoParams(none, compose, params), Error);
    EXPECT_THROW((void)metaReliefLayerAoParams({}, compose, params), Error);
    // A bad AoParams field in a per-layer bake names the layer.
    const std::vector<CompositionLayer> one{layer(bumps(16, 1), 1.0, 1.0, "lone")};
    const Composition composition = strata::compose(one, compose);
    AoParams badDirections;
    badDirections.directions = 2;
    try {
        (void)metaReliefAo(one, compose, composition, MetaAoMode::Multiply, badDirections);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("lone"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("directions"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace strata
