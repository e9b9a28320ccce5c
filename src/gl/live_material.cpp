#include "strata/gl/gpu_material.h"

#include "texture_upload.h"

#include "strata/compose/gradient_normals.h"
#include "strata/core/error.h"
#include "strata/gl/gl_error.h"
#include "strata/image/quantize.h"
#include "strata/occlusion/ambient_occlusion.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace strata::gl {

namespace {

[[noreturn]] void invalidLive(const std::string& message) {
    throw Error(ErrorKind::InvalidInput, "uploadLiveMaterial: " + message);
}

std::string liveLayerName(std::span<const CompositionLayer> layers, std::size_t i) {
    const std::string index = "layers[" + std::to_string(i) + "]";
    return layers[i].label.empty() ? index : layers[i].label;
}

}  // namespace

GpuMaterial uploadLiveMaterial(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                               std::optional<MetaAoMode> ao, const AoParams& aoParams) {
    return uploadLiveMaterial(layers, compose, ao, aoParams, {});
}

GpuMaterial uploadLiveMaterial(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                               std::optional<MetaAoMode> ao, const AoParams& aoParams,
                               std::span<const Image> layerAo) {
    if (layers.size() > static_cast<std::size_t>(kMaxLiveLayers)) {
        invalidLive(std::to_string(layers.size()) + " layers; the live path takes at most " +
                    std::to_string(kMaxLiveLayers) + " (bake the material instead)");
    }
    // Validates the depth weights, tilings and depth scale like compose(), and gives each layer's AO bake.
    const std::vector<std::optional<AoParams>> layerAoParams =
        metaReliefLayerAoParams(layers, compose, aoParams);
    if (!layerAo.empty() && layerAo.size() != layers.size())
        invalidLive(std::to_string(layerAo.size()) + " layer AO maps for " + std::to_string(layers.size()) +
                    " layers");
    double sumNormal = 0.0;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const CompositionLayer& layer = layers[i];
        if (!std::isfinite(layer.weightNormal) || layer.weightNormal < 0.0)
            invalidLive(liveLayerName(layers, i) + ": weight_normal must be a finite number >= 0, got " +
                        formatNumber(layer.weightNormal));
        if (layer.texture.depth.empty() || layer.texture.depth.channels() != 1)
            invalidLive(liveLayerName(layers, i) + ": needs a 1-channel depth map");
        if (compose.normals == NormalMode::Paper &&
            (layer.texture.normal.channels() != 3 ||
             layer.texture.normal.width() != layer.texture.depth.width() ||
             layer.texture.normal.height() != layer.texture.depth.height()))
            invalidLive(liveLayerName(layers, i) +
                        ": paper normals need a 3-channel normal map of the depth map's size");
        sumNormal += layer.weightNormal;
    }
    if (compose.normals == NormalMode::Paper && !(sumNormal > 0.0))
        invalidLive("the normal weights (weight_normal) of the layers sum to 0: at least one must be > 0");
    if (compose.colorFrom >= static_cast<int>(layers.size()) ||
        (compose.colorFrom >= 0 && layers[static_cast<std::size_t>(compose.colorFrom)].texture.color.empty()))
        invalidLive("color_from = " + std::to_string(compose.colorFrom) +
                    " names no layer with a colour map");

    GpuMaterial result;
    result.mNormalMode = compose.normals;
    result.mLiveAo = ao;
    result.mColorLayer = compose.colorFrom;
    result.mDepthScale = compose.depthScale;
    result.mAoDepthScale = compose.depthScale;
    result.mHasAo = ao.has_value();
    result.mHasColor = compose.colorFrom >= 0;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const CompositionLayer& layer = layers[i];
        ReliefTexture packed;
        packed.depth = layer.texture.depth;
        packed.depthScale = compose.depthScale;
        GpuLayer gpu;
        // Consistent normals need each layer's depth gradient g: stored as normals derived at a scale S_L
        // of the layer's own (strata/compose/gradient_normals.h), from which the shader recovers g. Paper
        // normals are the layer's own map.
        if (compose.normals == NormalMode::Consistent) {
            GradientNormals normals = gradientNormals(layer.texture.depth);
            gpu.normalScale = normals.scale;
            packed.normal = std::move(normals.normals);
        } else {
            packed.normal = layer.texture.normal;
        }
        if ((ao == MetaAoMode::Multiply || ao == MetaAoMode::Min) && layerAoParams[i]) {
            if (layerAo.empty()) {
                packed.ao = bakeAo(layer.texture.depth, *layerAoParams[i]);
            } else {
                const Image& map = layerAo[i];
                if (map.channels() != 1 || map.width() != layer.texture.depth.width() ||
                    map.height() != layer.texture.depth.height())
                    invalidLive(liveLayerName(layers, i) +
                                ": its AO map is not a 1-channel map of its depth's size");
                packed.ao = map;
            }
            gpu.aoDepthScale = layerAoParams[i]->depthScale;
        }
        gpu.texture = makePackedTexture(packed);
        if (static_cast<int>(i) == compose.colorFrom) gpu.color = makeColorTexture(layer.texture.color);
        gpu.tiling = layer.tiling;
        gpu.weightDepth = layer.weightDepth;
        gpu.weightNormal = layer.weightNormal;
        gpu.width = layer.texture.depth.width();
        gpu.height = layer.texture.depth.height();
        const auto [lowest, highest] =
            std::minmax_element(layer.texture.depth.pixels().begin(), layer.texture.depth.pixels().end());
        gpu.depthMin = toUnorm16(*lowest) / 65535.0;
        gpu.depthMax = toUnorm16(*highest) / 65535.0;
        result.mLayers.push_back(gpu);
    }
    result.mColor = compose.colorFrom >= 0 ? 0 : makeColorTexture(Image());
    result.mWidth = result.mLayers.front().width;
    result.mHeight = result.mLayers.front().height;
    checkGl("uploadLiveMaterial");
    return result;
}

}  // namespace strata::gl
