#include "strata/scene/scene_material.h"

#include "strata/core/error.h"
#include "strata/relief/texture_set.h"
#include "strata/scene/material.h"

namespace strata {

namespace fs = std::filesystem;

namespace {

void say(const SceneProgress& progress, const std::string& message) {
    if (progress) progress(message);
}

}  // namespace

const char* toString(MaterialKind kind) {
    switch (kind) {
        case MaterialKind::Baked:
            return "baked";
        case MaterialKind::Live:
            return "live";
        case MaterialKind::DualDepth:
            return "dual-depth";
    }
    return "?";
}

MaterialKind sceneMaterialKind(const Scene& scene) {
    if (scene.meta == MetaPath::Live) return MaterialKind::Live;
    if (scene.relief.technique == Technique::DualDepth && scene.depthMap.empty() &&
        isDualDepth(scene.material))
        return MaterialKind::DualDepth;
    return MaterialKind::Baked;
}

std::vector<Image> liveLayerAo(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                               std::optional<MetaAoMode> ao, const AoParams& aoParams) {
    if (ao != MetaAoMode::Multiply && ao != MetaAoMode::Min) return {};
    const std::vector<std::optional<AoParams>> params = metaReliefLayerAoParams(layers, compose, aoParams);
    std::vector<Image> maps;
    maps.reserve(layers.size());
    for (std::size_t i = 0; i < layers.size(); ++i)
        maps.push_back(params[i] ? bakeAo(layers[i].texture.depth, *params[i]) : Image());
    return maps;
}

Image composedAoForRender(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                          const AoParams& aoParams, double renderDepthScale, AoRescale rescale,
                          double* aoDepthScale, const SceneProgress& progress) {
    AoParams params = aoParams;
    params.depthScale = rescale == AoRescale::Exact ? renderDepthScale : compose.depthScale;
    say(progress, "ambient occlusion of the composed depth at S = " + formatNumber(params.depthScale));
    const Composition composition = strata::compose(layers, compose);
    *aoDepthScale = params.depthScale;
    return bakeAo(composition.texture.depth, params);
}

SceneMaterial prepareSceneMaterial(const Scene& scene, std::vector<std::string>* notes,
                                   const SceneProgress& progress) {
    SceneMaterial result;
    result.kind = sceneMaterialKind(scene);
    switch (result.kind) {
        case MaterialKind::Live: {
            // The layers go to the GPU as they are; only the AO needs baking here.
            const Material material = loadSceneLayeredMaterial(scene);
            say(progress, "layers of " + material.source.string());
            result.layers = loadLayers(material, notes);
            result.compose = material.compose;
            result.aoParams = material.aoParams;
            result.liveAo = scene.relief.ao ? material.ao : std::nullopt;
            result.depthScale = scene.relief.depthScale.value_or(material.compose.depthScale);
            if (result.liveAo == MetaAoMode::Multiply || result.liveAo == MetaAoMode::Min)
                say(progress, "ambient occlusion of each layer");
            result.layerAo = liveLayerAo(result.layers, result.compose, result.liveAo, result.aoParams);
            if (result.liveAo == MetaAoMode::Exact) {
                result.composedAo =
                    composedAoForRender(result.layers, result.compose, result.aoParams, result.depthScale,
                                        scene.relief.aoRescale, &result.composedAoDepthScale, progress);
            }
            break;
        }
        case MaterialKind::DualDepth:
            result.dual = readDualDepth(scene.material);
            result.depthScale = scene.relief.depthScale.value_or(result.dual.depthScale);
            break;
        case MaterialKind::Baked:
            result.texture = loadSceneMaterial(scene, notes, progress);
            result.depthScale = renderDepthScale(scene, result.texture);
            result.aoDepthScale = result.texture.depthScale;
            if (scene.relief.ao && !result.texture.ao.empty()) {
                if (scene.relief.aoRescale == AoRescale::Exact &&
                    result.depthScale != result.texture.depthScale)
                    say(progress,
                        "ambient occlusion at S = " + formatNumber(result.depthScale) + " (exact rescale)");
                result.texture.ao = aoForRender(result.texture, result.depthScale, scene.relief.aoRescale,
                                                &result.aoDepthScale);
            }
            break;
    }
    return result;
}

std::vector<fs::path> sceneInputs(const Scene& scene) {
    std::vector<fs::path> inputs;
    if (fs::exists(scene.mesh)) inputs.push_back(scene.mesh);
    if (!scene.depthMap.empty()) inputs.push_back(scene.depthMap);
    if (fs::exists(scene.material) && scene.depthMap.empty()) {
        // The material and every file it reads: a texture set's (or dual-depth texture's) maps, a material
        // JSON's layer files.
        const fs::path material(scene.material);
        const fs::path setDir = fs::is_directory(material)            ? material
                                : material.filename() == kSidecarName ? material.parent_path()
                                                                      : fs::path();
        inputs.push_back(material);
        if (!setDir.empty()) {
            for (const auto& entry : fs::directory_iterator(setDir)) inputs.push_back(entry.path());
        } else {
            for (const auto& file : materialInputs(readMaterial(material))) inputs.push_back(file);
        }
    }
    if (!scene.source.empty()) inputs.push_back(scene.source);
    return inputs;
}

}  // namespace strata
