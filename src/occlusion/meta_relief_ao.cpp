// AO of a meta-relief: the composed depth's own AO, or the paper's combination of per-layer AO maps
// (Section IV-A). docs/occlusion.md ("Combining layers") derives the per-layer depth scale and radius.
#include "strata/occlusion/meta_relief_ao.h"

#include "strata/core/error.h"

#include <algorithm>
#include <cmath>

namespace strata {

namespace {

[[noreturn]] void invalid(const std::string& message) {
    throw Error(ErrorKind::InvalidInput, "meta-relief ambient occlusion: " + message);
}

std::string layerName(std::span<const CompositionLayer> layers, std::size_t i) {
    return layers[i].label.empty() ? "layer " + std::to_string(i) : layers[i].label;
}

std::string sizeText(const Image& image) {
    return std::to_string(image.width()) + "x" + std::to_string(image.height());
}

// The largest radius AoParams accepts (ambient_occlusion.h: (0, 16]).
constexpr double kMaxRadius = 16.0;
// The largest depth scale AoParams accepts ((0, 100]).
constexpr double kMaxDepthScale = 100.0;

}  // namespace

const char* toString(MetaAoMode mode) {
    switch (mode) {
        case MetaAoMode::Exact:
            return "exact";
        case MetaAoMode::Multiply:
            return "multiply";
        case MetaAoMode::Min:
            return "min";
    }
    return "?";
}

MetaAoMode parseMetaAoMode(const std::string& text) {
    if (text == "exact") return MetaAoMode::Exact;
    if (text == "multiply") return MetaAoMode::Multiply;
    if (text == "min") return MetaAoMode::Min;
    throw Error(ErrorKind::InvalidInput,
                "unknown meta-relief AO mode '" + text + "' (expected exact, multiply or min)");
}

std::vector<std::optional<AoParams>> metaReliefLayerAoParams(std::span<const CompositionLayer> layers,
                                                             const ComposeParams& compose,
                                                             const AoParams& params) {
    if (layers.empty()) invalid("a meta-relief needs at least one layer");
    if (!std::isfinite(compose.depthScale) || compose.depthScale <= 0.0)
        invalid("depth_scale must be a number > 0, got " + formatNumber(compose.depthScale));
    if (!std::isfinite(params.radius) || params.radius <= 0.0 || params.radius > kMaxRadius)
        invalid("radius = " + formatNumber(params.radius) + " is outside (0, 16]");
    // W = sum of all depth weights, exactly as compose() normalises Eq. 2.
    double sumDepth = 0.0;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const CompositionLayer& layer = layers[i];
        if (!std::isfinite(layer.weightDepth) || layer.weightDepth < 0.0)
            invalid(layerName(layers, i) + ": weight_depth must be a finite number >= 0, got " +
                    formatNumber(layer.weightDepth));
        if (!std::isfinite(layer.tiling) || layer.tiling <= 0.0)
            invalid(layerName(layers, i) + ": tiling must be a number > 0, got " +
                    formatNumber(layer.tiling));
        sumDepth += layer.weightDepth;
    }
    if (!(sumDepth > 0.0))
        invalid("the depth weights (weight_depth) of the layers sum to 0: at least one must be > 0");

    std::vector<std::optional<AoParams>> result(layers.size());
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const CompositionLayer& layer = layers[i];
        if (layer.weightDepth == 0.0) continue;  // no relief: AO 1 everywhere
        AoParams layerParams = params;
        layerParams.depthScale = compose.depthScale * (layer.weightDepth / sumDepth) * layer.tiling;
        layerParams.radius = std::min(params.radius * layer.tiling, kMaxRadius);
        if (!(layerParams.depthScale <= kMaxDepthScale))
            invalid(layerName(layers, i) +
                    ": its depth scale S * w / sum w * tiling = " + formatNumber(layerParams.depthScale) +
                    " is above the largest an AO bake takes (100); lower depth_scale or the tiling");
        result[i] = layerParams;
    }
    return result;
}

Image metaReliefAo(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                   const Composition& composition, MetaAoMode mode, const AoParams& params,
                   const MetaAoProgress& progress) {
    const Image& depth = composition.texture.depth;
    if (depth.empty()) invalid("the composition has no depth map");

    if (mode == MetaAoMode::Exact) {
        AoParams exact = params;
        exact.depthScale = compose.depthScale;
        if (progress)
            progress("composed depth: " + sizeText(depth) + ", S = " + formatNumber(exact.depthScale) +
                     ", R = " + formatNumber(exact.radius));
        return bakeAo(depth, exact);
    }

    const std::vector<std::optional<AoParams>> perLayer = metaReliefLayerAoParams(layers, compose, params);
    std::vector<AoLayer> maps;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        if (!perLayer[i]) continue;
        const CompositionLayer& layer = layers[i];
        const std::string name = layerName(layers, i);
        if (layer.texture.depth.empty()) invalid(name + ": has no depth map");
        if (progress)
            progress(name + ": " + sizeText(layer.texture.depth) + ", S = " +
                     formatNumber(perLayer[i]->depthScale) + ", R = " + formatNumber(perLayer[i]->radius));
        AoLayer map;
        try {
            map.ao = bakeAo(layer.texture.depth, *perLayer[i]);
        } catch (const Error& e) {
            throw Error(e.kind(), name + ": " + e.what());
        }
        map.tiling = layer.tiling;
        map.label = name;
        maps.push_back(std::move(map));
    }
    // At least one layer has weight_depth > 0 (checked above), so `maps` is not empty.
    return combineAo(maps, mode == MetaAoMode::Multiply ? AoCombine::Multiply : AoCombine::Min,
                     depth.width());
}

std::string metaReliefAoMethodName(MetaAoMode mode, AoMethod method) {
    if (mode == MetaAoMode::Exact) return toString(method);
    return std::string(toString(mode)) + " of per-layer " + toString(method);
}

}  // namespace strata
