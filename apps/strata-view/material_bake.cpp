#include "material_bake.h"

#include "material_document.h"

#include "strata/occlusion/meta_relief_ao.h"
#include "strata/scene/scene.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <sstream>

namespace strata::view {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// What a layer's loaded maps depend on (not its weights or tiling, which only compose() uses).
std::string layerKey(const MaterialLayer& layer, double materialDepthScale) {
    std::ostringstream key;
    key.precision(17);
    if (layer.pattern) {
        key << "pattern " << *layer.pattern << " " << layer.patternParams.size << " "
            << layer.patternParams.seed << " " << layer.patternParams.depthScale;
    } else {
        const auto name = [](const std::optional<std::filesystem::path>& file) {
            return file ? file->string() : std::string("-");
        };
        // A file layer without a normal map gets normals derived at its depth scale, which defaults to the
        // material's.
        key << "files " << name(layer.depthFile) << "|" << name(layer.heightFile) << "|"
            << name(layer.normalFile) << "|" << layer.normalYDown << layer.normalYAuto << "|"
            << name(layer.colorFile) << "|" << layer.fileDepthScale.value_or(materialDepthScale);
    }
    return key.str();
}

std::string compositionKey(const BakeRequest& request) {
    Material material = request.material;
    material.compose.resolution = request.resolution;
    return materialToJson(material, "/").dump();
}

double aoScaleFor(const BakeRequest& request) {
    return request.aoRescale == AoRescale::Exact ? request.renderDepthScale
                                                 : request.material.compose.depthScale;
}

}  // namespace

std::string bakeKey(const BakeRequest& request) {
    std::ostringstream key;
    key.precision(17);
    key << compositionKey(request) << " ao at " << aoScaleFor(request);
    return key.str();
}

MaterialBaker::KeepLayers::~KeepLayers() {
    for (std::size_t k = 0; k < layers.size(); ++k) {
        if (layers[k].texture.depth.empty()) continue;
        baker.mLayers.push_back(std::move(layers[k]));
        baker.mLayerKeys.push_back(keys[k]);
    }
}

void MaterialBaker::takeLayers(const Material& material, BakeResult& result,
                               std::vector<CompositionLayer>& layers, std::vector<std::string>& keys) {
    // Layers: reuse what the previous request loaded, load the rest (one layer at a time through the
    // library's loadLayers, so a layer means exactly what it means to `strata compose`). Entries left
    // behind by the previous request that this one does not take are dropped.
    const auto start = std::chrono::steady_clock::now();
    std::vector<CompositionLayer> previous = std::move(mLayers);
    std::vector<std::string> previousKeys = std::move(mLayerKeys);
    mLayers.clear();
    mLayerKeys.clear();
    for (std::size_t i = 0; i < material.layers.size(); ++i) {
        const MaterialLayer& spec = material.layers[i];
        const std::string key = layerKey(spec, material.compose.depthScale);
        CompositionLayer layer;
        bool found = false;
        for (std::size_t j = 0; j < previousKeys.size() && !found; ++j) {
            if (previousKeys[j] == key && !previous[j].texture.depth.empty()) {
                layer = std::move(previous[j]);  // a second copy of the same layer loads its own
                found = true;
            }
        }
        if (!found) {
            Material single;
            single.source = material.source;
            single.compose = material.compose;
            single.layers = {spec};
            layer = std::move(loadLayers(single, &result.notes).front());
            ++result.layersLoaded;
        }
        applyLayerSettings(i, spec, layer);
        layers.push_back(std::move(layer));
        keys.push_back(key);
    }
    result.loadSeconds = secondsSince(start);
}

std::vector<CompositionLayer> MaterialBaker::layers(const BakeRequest& request, BakeResult& report) {
    std::vector<CompositionLayer> layers;
    std::vector<std::string> keys;
    std::vector<CompositionLayer> copy;
    {
        const KeepLayers keep{*this, layers, keys};
        takeLayers(request.material, report, layers, keys);
        copy = layers;  // the cache keeps its own
    }
    return copy;
}

BakeResult MaterialBaker::bake(const BakeRequest& request) {
    const Material& material = request.material;
    BakeResult result;
    std::vector<CompositionLayer> layers;
    std::vector<std::string> keys;
    {
        // Whatever happens below (a layer that fails to load, weights that sum to 0), the layers loaded so
        // far stay cached for the next request.
        const KeepLayers keep{*this, layers, keys};
        takeLayers(material, result, layers, keys);

        // Composition and the material's own AO (what composeMaterial does), when anything they read
        // changed.
        const std::string compKey = compositionKey(request);
        if (compKey != mCompositionKey) {
            mCompositionKey.clear();  // invalid until both steps have succeeded
            mRenderAoKey.clear();
            ComposeParams params = material.compose;
            params.resolution = request.resolution;
            auto start = std::chrono::steady_clock::now();
            composeInto(layers, params, mComposition);
            result.composeSeconds = secondsSince(start);
            result.notes.insert(result.notes.end(), mComposition.warnings.begin(),
                                mComposition.warnings.end());
            start = std::chrono::steady_clock::now();
            mMaterialAo = material.ao
                              ? metaReliefAo(layers, params, mComposition, *material.ao, material.aoParams)
                              : Image();
            result.aoSeconds = secondsSince(start);
            mCompositionKey = compKey;
            result.composed = true;
        }
    }

    result.texture = mComposition.texture;
    result.texture.ao = mMaterialAo;

    // The AO for the render's depth scale (`strata render` does the same: aoForRender).
    const std::string renderKey = bakeKey(request);
    if (renderKey != mRenderAoKey) {
        const auto start = std::chrono::steady_clock::now();
        mRenderAo =
            aoForRender(result.texture, request.renderDepthScale, request.aoRescale, &mRenderAoDepthScale);
        result.aoSeconds += secondsSince(start);
        mRenderAoKey = renderKey;
    }
    result.texture.ao = mRenderAo;
    result.aoDepthScale = mRenderAoDepthScale;
    return result;
}

}  // namespace strata::view
