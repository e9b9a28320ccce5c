#include "strata/scene/material.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/image/image_io.h"
#include "strata/image/image_ops.h"
#include "strata/relief/import.h"
#include "strata/relief/relief_texture.h"
#include "strata/relief/texture_set.h"

#include "core/json_reader.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <set>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata {

namespace {

using ObjectReader = detail::JsonObjectReader;

MaterialLayer parseLayer(const json& object, const std::string& where, const std::string& file,
                         const fs::path& baseDir) {
    ObjectReader reader(object, where, file);
    MaterialLayer layer;
    layer.name = reader.string("name").value_or("");
    layer.pattern = reader.string("pattern");

    auto existingFile = [&](const std::string& key) -> std::optional<fs::path> {
        const auto relative = reader.string(key);
        if (!relative) return std::nullopt;
        if (relative->empty()) reader.fail(reader.keyPath(key), "must not be empty");
        const fs::path path = baseDir / *relative;
        try {
            checkReadableFile(path);
        } catch (const Error& e) {
            throw Error(ErrorKind::Io, file + ": " + reader.keyPath(key) + ": " + e.what());
        }
        return path;
    };

    const bool patternLayer = layer.pattern.has_value();
    if (patternLayer) {
        if (!isPattern(*layer.pattern)) {
            std::string known;
            for (const auto& info : patternList()) known += (known.empty() ? "" : ", ") + info.name;
            reader.fail(reader.keyPath("pattern"),
                        "unknown pattern \"" + *layer.pattern + "\" (known: " + known + ")");
        }
        const PatternParams defaults;
        layer.patternParams.size = static_cast<int>(
            reader.integer("size", kMinPatternSize, kMaxPatternSize).value_or(defaults.size));
        layer.patternParams.seed = static_cast<std::uint32_t>(
            reader.integer("seed", 0, std::numeric_limits<std::uint32_t>::max()).value_or(defaults.seed));
        layer.patternParams.depthScale = reader.number("depth_scale").value_or(defaults.depthScale);
        if (!(layer.patternParams.depthScale > 0.0 && layer.patternParams.depthScale <= kMaxReliefDepthScale))
            reader.fail(reader.keyPath("depth_scale"),
                        "must be in (0, 10], got " + formatNumber(layer.patternParams.depthScale));
        for (const char* fileKey : {"depth", "height", "normal", "normal_y", "color"})
            if (reader.has(fileKey))
                reader.fail(reader.keyPath(fileKey), "a layer uses either \"pattern\" or files, not both");
    } else {
        for (const char* patternKey : {"size", "seed"})
            if (reader.has(patternKey))
                reader.fail(reader.keyPath(patternKey), "only a \"pattern\" layer takes this key");
        layer.depthFile = existingFile("depth");
        layer.heightFile = existingFile("height");
        if (layer.depthFile && layer.heightFile)
            reader.fail(where, "give either \"depth\" or \"height\", not both");
        if (!layer.depthFile && !layer.heightFile)
            reader.fail(where, "needs \"pattern\", or a \"depth\" or \"height\" file");
        layer.normalFile = existingFile("normal");
        const std::string normalY = reader.string("normal_y").value_or("up");
        if (normalY != "up" && normalY != "down" && normalY != "auto")
            reader.fail(reader.keyPath("normal_y"),
                        "must be \"up\" (OpenGL), \"down\" (DirectX) or \"auto\", got \"" + normalY + "\"");
        if (reader.has("normal_y") && !layer.normalFile)
            reader.fail(reader.keyPath("normal_y"), "given without \"normal\"");
        layer.normalYDown = normalY == "down";
        layer.normalYAuto = normalY == "auto";
        layer.fileDepthScale = reader.number("depth_scale");
        if (layer.fileDepthScale &&
            !(*layer.fileDepthScale > 0.0 && *layer.fileDepthScale <= kMaxReliefDepthScale))
            reader.fail(reader.keyPath("depth_scale"),
                        "must be in (0, 10], got " + formatNumber(*layer.fileDepthScale));
        layer.colorFile = existingFile("color");
    }

    layer.tiling = reader.number("tiling").value_or(1.0);
    if (!(layer.tiling > 0.0 && layer.tiling <= kMaxLayerTiling))
        reader.fail(reader.keyPath("tiling"), "must be in (0, 4096], got " + formatNumber(layer.tiling));
    layer.weightDepth = reader.number("weight_depth").value_or(1.0);
    if (layer.weightDepth < 0.0)
        reader.fail(reader.keyPath("weight_depth"), "must be >= 0, got " + formatNumber(layer.weightDepth));
    if (layer.weightDepth > kMaxLayerWeight)
        reader.fail(reader.keyPath("weight_depth"), "must be <= 1e6, got " + formatNumber(layer.weightDepth));
    layer.weightNormal = reader.number("weight_normal").value_or(1.0);
    if (layer.weightNormal < 0.0)
        reader.fail(reader.keyPath("weight_normal"), "must be >= 0, got " + formatNumber(layer.weightNormal));
    if (layer.weightNormal > kMaxLayerWeight)
        reader.fail(reader.keyPath("weight_normal"),
                    "must be <= 1e6, got " + formatNumber(layer.weightNormal));
    reader.rejectUnknown();
    return layer;
}

}  // namespace

Material parseMaterial(const json& document, const fs::path& source) {
    const std::string file = source.string();
    const fs::path baseDir = source.has_parent_path() ? source.parent_path() : fs::path(".");
    ObjectReader reader(document, "", file);
    Material material;
    material.source = source;
    material.compose.resolution =
        static_cast<int>(reader.integer("resolution", 1, Image::kMaxDimension).value_or(0));
    material.compose.depthScale = reader.number("depth_scale").value_or(kDefaultDepthScale);
    if (!(material.compose.depthScale > 0.0 && material.compose.depthScale <= kMaxReliefDepthScale))
        reader.fail("depth_scale", "must be in (0, 10], got " + formatNumber(material.compose.depthScale));
    if (const auto normals = reader.string("normals")) {
        if (*normals != "paper" && *normals != "consistent")
            reader.fail("normals", "must be \"paper\" or \"consistent\", got \"" + *normals + "\"");
        material.compose.normals = parseNormalMode(*normals);
    }
    reader.string("name");         // free text
    reader.string("description");  // free text

    const json* layers = reader.array("layers");
    if (!layers) reader.fail("layers", "missing: a material needs a \"layers\" array");
    if (layers->empty()) reader.fail("layers", "must hold at least one layer");
    if (layers->size() > kMaxMaterialLayers)
        reader.fail("layers", "at most " + std::to_string(kMaxMaterialLayers) + " layers, got " +
                                  std::to_string(layers->size()));
    for (std::size_t i = 0; i < layers->size(); ++i)
        material.layers.push_back(
            parseLayer((*layers)[i], "layers[" + std::to_string(i) + "]", file, baseDir));

    // color_from: default the first layer that has colour (every pattern has colour).
    int defaultColor = -1;
    for (std::size_t i = 0; i < material.layers.size() && defaultColor < 0; ++i)
        if (material.layers[i].pattern || material.layers[i].colorFile) defaultColor = static_cast<int>(i);
    const auto colorFrom =
        reader.integer("color_from", -1, static_cast<long long>(material.layers.size()) - 1);
    material.compose.colorFrom = colorFrom ? static_cast<int>(*colorFrom) : defaultColor;
    if (material.compose.colorFrom >= 0) {
        const MaterialLayer& chosen = material.layers[material.compose.colorFrom];
        if (!chosen.pattern && !chosen.colorFile)
            reader.fail("color_from",
                        "layers[" + std::to_string(material.compose.colorFrom) + "] has no \"color\" file");
    }

    // Ambient occlusion: the mode, and the bake's method, radius and directions.
    const std::string aoMode = reader.string("ao").value_or("exact");
    if (aoMode == "none") {
        material.ao.reset();
    } else if (aoMode == "exact" || aoMode == "multiply" || aoMode == "min") {
        material.ao = parseMetaAoMode(aoMode);
    } else {
        reader.fail("ao", "must be \"exact\", \"multiply\", \"min\" or \"none\", got \"" + aoMode + "\"");
    }
    if (const auto method = reader.string("ao_method")) {
        if (*method != "sweep" && *method != "paper" && *method != "brute")
            reader.fail("ao_method", "must be \"sweep\", \"paper\" or \"brute\", got \"" + *method + "\"");
        material.aoParams.method = parseAoMethod(*method);
    }
    if (const auto radius = reader.number("ao_radius")) {
        if (!(*radius > 0.0 && *radius <= 16.0))
            reader.fail("ao_radius", "must be in (0, 16] tile widths, got " + formatNumber(*radius));
        material.aoParams.radius = *radius;
    }
    if (const auto directions = reader.integer("ao_directions", 3, 1024))
        material.aoParams.directions = static_cast<int>(*directions);
    if (!material.ao)
        for (const char* key : {"ao_method", "ao_radius", "ao_directions"})
            if (reader.has(key)) reader.fail(key, "given with \"ao\": \"none\" (no AO map is made)");

    reader.rejectUnknown();

    double sumDepth = 0.0;
    double sumNormal = 0.0;
    for (const auto& layer : material.layers) {
        sumDepth += layer.weightDepth;
        sumNormal += layer.weightNormal;
    }
    if (!(sumDepth > 0.0))
        reader.fail("layers", "the weight_depth values sum to 0: at least one must be > 0");
    if (!(sumNormal > 0.0))
        reader.fail("layers", "the weight_normal values sum to 0: at least one must be > 0");
    return material;
}

Material readMaterial(const fs::path& path) {
    return parseMaterial(detail::readJsonFile(path), path);
}

std::string layerLabel(std::size_t index, const MaterialLayer& layer) {
    std::string label = "layers[" + std::to_string(index) + "]";
    if (!layer.name.empty())
        label += " (" + layer.name + ")";
    else if (layer.pattern)
        label += " (" + *layer.pattern + ")";
    return label;
}

void applyLayerSettings(std::size_t index, const MaterialLayer& spec, CompositionLayer& layer) {
    layer.label = layerLabel(index, spec);
    layer.tiling = spec.tiling;
    layer.weightDepth = spec.weightDepth;
    layer.weightNormal = spec.weightNormal;
}

std::vector<CompositionLayer> loadLayers(const Material& material, std::vector<std::string>* notes,
                                         const MetaAoProgress& progress) {
    std::vector<CompositionLayer> layers;
    for (std::size_t i = 0; i < material.layers.size(); ++i) {
        const MaterialLayer& spec = material.layers[i];
        if (progress)
            progress("layer " + std::to_string(i + 1) + "/" + std::to_string(material.layers.size()) + ": " +
                     layerLabel(i, spec));
        CompositionLayer layer;
        applyLayerSettings(i, spec, layer);
        if (spec.pattern) {
            layer.texture = makePattern(*spec.pattern, spec.patternParams);
        } else {
            std::string note;
            layer.texture.depth = spec.depthFile
                                      ? readDepthMap(*spec.depthFile, DepthEncoding::Depth, &note)
                                      : readDepthMap(*spec.heightFile, DepthEncoding::Height, &note);
            if (!note.empty() && notes) notes->push_back(note);
            layer.texture.depthScale = spec.fileDepthScale.value_or(material.compose.depthScale);
            if (spec.normalFile) {
                // Read as stored, checked against the layer's own depth (import.h resolveNormalY), then
                // converted: the same rule as `strata import` and texture sets.
                layer.texture.normal = readNormalMap(*spec.normalFile);
                const NormalY setting = spec.normalYAuto   ? NormalY::Auto
                                        : spec.normalYDown ? NormalY::Down
                                                           : NormalY::Up;
                const NormalYResolution resolved =
                    resolveNormalY(layer.texture.normal, layer.texture.depth, setting, false,
                                   layer.label + " normal " + spec.normalFile->string(),
                                   std::string("set \"normal_y\": \"") +
                                       (setting == NormalY::Up ? "down" : "up") + "\" or \"auto\"");
                if (!resolved.note.empty() && notes) notes->push_back(resolved.note);
                if (resolved.flipY)  // DirectX -> OpenGL: negating y keeps the vector unit length
                    for (int y = 0; y < layer.texture.normal.height(); ++y)
                        for (int x = 0; x < layer.texture.normal.width(); ++x)
                            layer.texture.normal.at(x, y, 1) *= -1.0f;
            } else {
                layer.texture.normal = normalsFromDepth(layer.texture.depth, layer.texture.depthScale);
            }
            if (spec.colorFile) layer.texture.color = toRgb(readImage(*spec.colorFile));
        }
        layers.push_back(std::move(layer));
    }
    return layers;
}

std::vector<fs::path> materialInputs(const Material& material) {
    std::vector<fs::path> inputs{material.source};
    for (const auto& layer : material.layers)
        for (const auto& file : {layer.depthFile, layer.heightFile, layer.normalFile, layer.colorFile})
            if (file) inputs.push_back(*file);
    return inputs;
}

ReliefTexture composeMaterial(const Material& material, std::vector<std::string>* notes,
                              const MetaAoProgress& progress) {
    if (progress) progress("loading " + std::to_string(material.layers.size()) + " layers");
    const std::vector<CompositionLayer> layers = loadLayers(material, notes, progress);
    if (progress) progress("composing");
    Composition composition = compose(layers, material.compose);
    if (notes) notes->insert(notes->end(), composition.warnings.begin(), composition.warnings.end());
    if (material.ao) {
        if (progress) progress(std::string("ambient occlusion (") + toString(*material.ao) + ")");
        composition.texture.ao =
            metaReliefAo(layers, material.compose, composition, *material.ao, material.aoParams, progress);
    }
    return std::move(composition.texture);
}

}  // namespace strata
