// Meta-relief composition (paper Eq. 1 and 2) against exact expectations on tiny literal inputs.
#include "test_support.h"

#include "strata/compose/compose.h"
#include "strata/core/error.h"
#include "strata/image/image_ops.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

// A deterministic, non-smooth layer: every texel differs, so any misplaced sample shows.
ReliefTexture noiseLayer(int size, unsigned seed) {
    ReliefTexture texture;
    texture.depth = Image(size, size, 1);
    unsigned state = seed * 2654435761u + 1u;
    for (float& value : texture.depth.pixels()) {
        state = state * 1664525u + 1013904223u;
        value = static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
    }
    texture.normal = normalsFromDepth(texture.depth, texture.depthScale);
    texture.color = Image(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c)
                texture.color.at(x, y, c) = texture.depth.at(x, y) * (0.3f + 0.3f * static_cast<float>(c));
    return texture;
}

// A smooth periodic layer from an analytic function of (u, v) at texel centres.
template <typename F>
ReliefTexture analyticLayer(int size, F depthOf) {
    ReliefTexture texture;
    texture.depth = Image(size, size, 1);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            texture.depth.at(x, y) =
                static_cast<float>(depthOf(texture.depth.texelU(x), texture.depth.texelV(y)));
    texture.normal = normalsFromDepth(texture.depth, texture.depthScale);
    return texture;
}

CompositionLayer layerOf(ReliefTexture texture, double tiling, double wd, double wn) {
    return {std::move(texture), tiling, wd, wn, ""};
}

// Largest jump between horizontally or vertically adjacent texels, over the interior and across
// the wrap-around border separately. A seam shows as a border jump above every interior jump.
struct Jumps {
    double interior = 0.0;
    double border = 0.0;
};
Jumps jumps(const Image& image) {
    Jumps result;
    const int w = image.width();
    const int h = image.height();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double right = std::fabs(image.at(x, y) - image.atWrapped(x + 1, y));
            const double down = std::fabs(image.at(x, y) - image.atWrapped(x, y + 1));
            (x + 1 == w ? result.border : result.interior) =
                std::max(x + 1 == w ? result.border : result.interior, right);
            (y + 1 == h ? result.border : result.interior) =
                std::max(y + 1 == h ? result.border : result.interior, down);
        }
    return result;
}

TEST(Compose, OneLayerWithUnitWeightsReproducesItsInputsExactly) {
    const ReliefTexture input = noiseLayer(32, 7);
    const std::vector<CompositionLayer> layers{layerOf(input, 1.0, 1.0, 1.0)};
    ComposeParams params;
    params.colorFrom = 0;
    const Composition result = compose(layers, params);
    EXPECT_EQ(result.texture.depth, input.depth);
    EXPECT_EQ(result.texture.normal, input.normal);
    EXPECT_EQ(result.texture.color, input.color);
    EXPECT_TRUE(result.warnings.empty());
    EXPECT_TRUE(result.texture.ao.empty());
}

TEST(Compose, ScalingAllWeightsByKChangesNothing) {
    const std::vector<CompositionLayer> base{layerOf(noiseLayer(32, 1), 1.0, 1.0, 0.5),
                                             layerOf(noiseLayer(16, 2), 2.0, 0.3, 0.7),
                                             layerOf(noiseLayer(8, 3), 3.0, 0.2, 0.1)};
    std::vector<CompositionLayer> scaled = base;
    for (auto& layer : scaled) {
        layer.weightDepth *= 3.7;
        layer.weightNormal *= 3.7;
    }
    ComposeParams params;
    params.resolution = 48;
    for (const NormalMode mode : {NormalMode::Paper, NormalMode::Consistent}) {
        params.normals = mode;
        const Composition a = compose(base, params);
        const Composition b = compose(scaled, params);
        // w / sum(w) is computed in double and rounded to float: scaling may move it by one float ulp
        // (6e-8 relative), so values in [0, 1] agree to well below 1e-6.
        EXPECT_LE(test::maxAbsDiff(a.texture.depth, b.texture.depth), 1e-6);
        EXPECT_LE(test::maxAbsDiff(a.texture.normal, b.texture.normal), 1e-6);
    }
}

TEST(Compose, TilingTwoAtTwiceTheResolutionIsTheLayerSampledAtTwiceUv) {
    const ReliefTexture input = noiseLayer(16, 3);
    const std::vector<CompositionLayer> layers{layerOf(input, 2.0, 1.0, 1.0)};
    ComposeParams params;
    params.resolution = 32;
    params.colorFrom = -1;
    const Composition result = compose(layers, params);
    double worst = 0.0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const double u = result.texture.depth.texelU(x);
            const double v = result.texture.depth.texelV(y);
            worst = std::max(worst, static_cast<double>(std::fabs(result.texture.depth.at(x, y) -
                                                                  input.depth.sample(2.0 * u, 2.0 * v))));
        }
    // Both are the same bilinear formula at the same point; only float rounding may differ.
    EXPECT_LE(worst, 1e-6);
}

TEST(Compose, FractionalTilingSamplesAtTilingTimesUv) {
    const ReliefTexture input = noiseLayer(16, 4);
    const std::vector<CompositionLayer> layers{layerOf(input, 5.5, 1.0, 1.0)};
    ComposeParams params;
    params.resolution = 40;
    const Composition result = compose(layers, params);
    double worst = 0.0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x)
            worst = std::max(worst, static_cast<double>(
                                        std::fabs(result.texture.depth.at(x, y) -
                                                  input.depth.sample(5.5 * result.texture.depth.texelU(x),
                                                                     5.5 * result.texture.depth.texelV(y)))));
    EXPECT_LE(worst, 1e-6);  // same formula, float rounding only
    ASSERT_EQ(result.warnings.size(), 1u);
    EXPECT_NE(result.warnings[0].find("5.5"), std::string::npos);
}

TEST(Compose, IntegerTilingsAreSeamlessAndFractionalOnesAreNot) {
    // Smooth periodic layers at different resolutions; cos() makes a cut at the border show as a jump.
    auto wave = [](int a, int b) {
        return [a, b](double u, double v) {
            return 0.5 + 0.5 * std::cos(2 * kPi * a * u) * std::cos(2 * kPi * b * v);
        };
    };
    ComposeParams params;
    params.resolution = 96;
    params.colorFrom = -1;
    const std::vector<CompositionLayer> integer{layerOf(analyticLayer(64, wave(1, 1)), 1.0, 1.0, 1.0),
                                                layerOf(analyticLayer(32, wave(2, 1)), 3.0, 0.5, 0.5),
                                                layerOf(analyticLayer(48, wave(1, 3)), 2.0, 0.25, 0.25)};
    const Jumps seamless = jumps(compose(integer, params).texture.depth);
    // The border is just another pair of neighbours: its jump stays within the interior's.
    EXPECT_LE(seamless.border, seamless.interior * 1.0001);

    std::vector<CompositionLayer> fractional = integer;
    fractional[1].tiling = 2.5;
    const Composition cut = compose(fractional, params);
    const Jumps seam = jumps(cut.texture.depth);
    // Layer 1 becomes 0.5 + 0.5 cos(10 pi u) cos(5 pi v): at the v border cos(5 pi v) goes from -1 to 1,
    // a jump of up to 1 in that layer and 0.5 / 1.75 = 0.29 in the composed depth. The steepest
    // interior step is that layer's cos(10 pi u) at 96 texels: 0.29 * 0.5 * 10 pi / 96 * 2 = 0.09 at most
    // (0.07 measured). A factor of 3 separates a cut from any smooth step with margin.
    EXPECT_GT(seam.border, 3.0 * seam.interior);
    EXPECT_EQ(cut.warnings.size(), 1u);
}

TEST(Compose, PaperNormalsAreTheNormalisedWeightedAverage) {
    auto constantNormals = [](float nx, float ny, float nz) {
        ReliefTexture texture;
        texture.depth = Image(4, 4, 1, 0.5f);
        texture.normal = Image(4, 4, 3);
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                texture.normal.at(x, y, 0) = nx;
                texture.normal.at(x, y, 1) = ny;
                texture.normal.at(x, y, 2) = nz;
            }
        return texture;
    };
    const std::vector<CompositionLayer> layers{layerOf(constantNormals(0.6f, 0.0f, 0.8f), 1.0, 1.0, 1.0),
                                               layerOf(constantNormals(0.0f, 0.6f, 0.8f), 1.0, 1.0, 3.0)};
    ComposeParams params;
    params.colorFrom = -1;
    const Composition result = compose(layers, params);
    // (1 * (0.6, 0, 0.8) + 3 * (0, 0.6, 0.8)) / 4 = (0.15, 0.45, 0.8), then normalised.
    const double length = std::sqrt(0.15 * 0.15 + 0.45 * 0.45 + 0.8 * 0.8);
    EXPECT_NEAR(result.texture.normal.at(2, 1, 0), 0.15 / length, 1e-6);
    EXPECT_NEAR(result.texture.normal.at(2, 1, 1), 0.45 / length, 1e-6);
    EXPECT_NEAR(result.texture.normal.at(2, 1, 2), 0.8 / length, 1e-6);
}

TEST(Compose, ConsistentNormalsIncludeTheTilingSteepening) {
    // d(u) = 0.5 + 0.5 sin(2 pi u) tiled twice: D(u) = d(2u), dD/du = 2 pi cos(4 pi u), at S = 0.05.
    const int size = 256;
    const double s = 0.05;
    const ReliefTexture layer =
        analyticLayer(size, [](double u, double) { return 0.5 + 0.5 * std::sin(2 * kPi * u); });
    const std::vector<CompositionLayer> layers{layerOf(layer, 2.0, 1.0, 1.0)};
    ComposeParams params;
    params.resolution = size;
    params.depthScale = s;
    params.normals = NormalMode::Consistent;
    params.colorFrom = -1;
    const Composition result = compose(layers, params);
    double worstAngle = 0.0;
    for (int x = 0; x < size; ++x) {
        const double u = result.texture.normal.texelU(x);
        const double slope = s * 2 * kPi * std::cos(4 * kPi * u);
        const double nx = slope / std::sqrt(slope * slope + 1);
        const double nz = 1 / std::sqrt(slope * slope + 1);
        const double dot = nx * static_cast<double>(result.texture.normal.at(x, 7, 0)) +
                           nz * static_cast<double>(result.texture.normal.at(x, 7, 2));
        worstAngle = std::max(worstAngle, std::acos(std::min(1.0, dot)) * 180 / kPi);
    }
    // Central differences on the layer (256 texels per period) have relative slope error
    // (2 pi / 256)^2 / 6 = 1e-4, plus bilinear interpolation of the gradient between texel centres
    // (half-texel positions at tiling 2): far below 0.05 degrees at slopes of at most 0.31.
    EXPECT_LT(worstAngle, 0.05);

    // Paper mode keeps the layer's own (un-steepened) normals: the maximum slope is half as large.
    params.normals = NormalMode::Paper;
    const Composition paper = compose(layers, params);
    float maxPaper = 0.0f;
    float maxConsistent = 0.0f;
    for (int x = 0; x < size; ++x) {
        maxPaper = std::max(maxPaper, std::fabs(paper.texture.normal.at(x, 7, 0)));
        maxConsistent = std::max(maxConsistent, std::fabs(result.texture.normal.at(x, 7, 0)));
    }
    // Layer normals were made at its own S = 0.08: max slope 0.08 * pi = 0.251; consistent: 0.05 * 2 * 2pi *
    // 0.5 = 0.314.
    EXPECT_NEAR(maxPaper, 0.251 / std::sqrt(1 + 0.251 * 0.251), 2e-3);
    EXPECT_NEAR(maxConsistent, 0.314 / std::sqrt(1 + 0.314 * 0.314), 2e-3);
}

TEST(Compose, OutputResolutionDefaultsToTheLargestLayer) {
    const std::vector<CompositionLayer> layers{layerOf(noiseLayer(8, 1), 1.0, 1.0, 1.0),
                                               layerOf(noiseLayer(24, 2), 3.0, 1.0, 1.0)};
    ComposeParams params;
    params.colorFrom = -1;
    EXPECT_EQ(compose(layers, params).texture.depth.width(), 24);
}

void expectInvalid(const std::vector<CompositionLayer>& layers, const ComposeParams& params,
                   const std::string& mention) {
    try {
        compose(layers, params);
        FAIL() << "expected an error mentioning " << mention;
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
}

TEST(Compose, BadParametersAreClearErrors) {
    std::vector<CompositionLayer> layers{layerOf(noiseLayer(8, 1), 1.0, 1.0, 1.0),
                                         layerOf(noiseLayer(8, 2), 2.0, 1.0, 1.0)};
    layers[1].label = "layers[1] (fabric)";
    ComposeParams params;
    params.colorFrom = -1;
    expectInvalid({}, params, "at least one layer");

    auto bad = layers;
    bad[1].weightDepth = -0.3;
    expectInvalid(bad, params, "layers[1] (fabric): weight_depth must be >= 0, got -0.3");
    bad = layers;
    bad[1].weightNormal = std::nan("");
    expectInvalid(bad, params, "weight_normal must be a finite number");
    bad = layers;
    bad[0].weightDepth = bad[1].weightDepth = 0.0;
    expectInvalid(bad, params, "sum to 0");
    bad = layers;
    bad[1].tiling = 0.0;
    expectInvalid(bad, params, "tiling must be a number > 0");
    bad = layers;
    bad[0].texture.normal = Image();
    expectInvalid(bad, params, "needs the layer's normal map");

    ComposeParams badParams = params;
    badParams.colorFrom = 5;
    expectInvalid(layers, badParams, "color_from");
    badParams = params;
    badParams.depthScale = 0.0;
    expectInvalid(layers, badParams, "depth_scale");
    badParams = params;
    badParams.resolution = Image::kMaxDimension + 1;
    expectInvalid(layers, badParams, "resolution");
}

TEST(Compose, AngleBetweenMeasuresDegrees) {
    Image a(1, 1, 3);
    Image b(1, 1, 3);
    a.at(0, 0, 2) = 1.0f;
    b.at(0, 0, 0) = static_cast<float>(std::sin(kPi / 6));
    b.at(0, 0, 2) = static_cast<float>(std::cos(kPi / 6));
    EXPECT_NEAR(angleBetween(a, b).meanDegrees, 30.0, 1e-4);
}

}  // namespace
}  // namespace strata
