#include "material_document.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/relief/patterns.h"
#include "strata/relief/texture_set.h"
#include "strata/scene/scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata::view {

namespace {

// The main job's material. The library keeps its copy private to src/scene/scene.cpp (loadSceneMaterial
// returns only the composed texture), so the viewer, which needs the layers to edit them, repeats it here;
// both equal examples/shaped_fabric.json. (A strata::builtinMaterial(name) -> Material would remove this.)
constexpr const char* kShapedFabricJson = R"({
  "resolution": 1024, "depth_scale": 0.08, "normals": "paper", "color_from": 1,
  "layers": [
    { "pattern": "base",   "size": 1024, "seed": 1, "tiling": 1.0, "weight_depth": 1.0, "weight_normal": 1.0 },
    { "pattern": "fabric", "size": 512,  "seed": 1, "tiling": 8.0, "weight_depth": 0.3, "weight_normal": 0.3 }
  ]
})";

// A texture set as a one-layer material: its depth, normal and colour files, at its depth scale.
Material textureSetMaterial(const fs::path& path) {
    const fs::path dir = fs::is_directory(path) ? path : path.parent_path();
    const json sidecar = readSidecar(path);  // throws for anything that is not a Strata set
    const std::string where = (dir / kSidecarName).string();
    auto fileOf = [&](const char* key) -> std::optional<fs::path> {
        const auto it = sidecar.find(key);
        if (it == sidecar.end() || it->is_null()) return std::nullopt;
        if (!it->is_object() || !it->contains("file") || !(*it)["file"].is_string())
            throw Error(ErrorKind::InvalidInput, where + ": \"" + key + "\" has no \"file\" string");
        return dir / (*it)["file"].get<std::string>();
    };
    const auto depth = fileOf("depth");
    const auto normal = fileOf("normal");
    if (!depth || !normal)
        throw Error(ErrorKind::InvalidInput, where + ": a texture set needs \"depth\" and \"normal\"");
    const auto scale = sidecar.find("depth_scale");
    if (scale == sidecar.end() || !scale->is_number() || !(scale->get<double>() > 0.0))
        throw Error(ErrorKind::InvalidInput, where + ": \"depth_scale\" is missing or not a positive number");

    Material material;
    material.source = dir / kSidecarName;
    material.compose.depthScale = scale->get<double>();
    MaterialLayer layer = fileLayer(*depth, false, *normal, fileOf("color").value_or(fs::path()));
    layer.name = dir.filename().string();
    layer.fileDepthScale = material.compose.depthScale;
    material.layers.push_back(std::move(layer));
    material.compose.colorFrom = hasColor(material.layers[0]) ? 0 : -1;
    return material;
}

std::string relativePath(const fs::path& file, const fs::path& baseDir) {
    const fs::path absolute = fs::absolute(file).lexically_normal();
    const fs::path base = fs::absolute(baseDir.empty() ? fs::path(".") : baseDir).lexically_normal();
    const fs::path relative = absolute.lexically_proximate(base);
    return relative.generic_string();
}

int firstLayerWithColor(const Material& material) {
    for (std::size_t i = 0; i < material.layers.size(); ++i)
        if (hasColor(material.layers[i])) return static_cast<int>(i);
    return -1;
}

}  // namespace

Material openMaterial(const std::string& nameOrPath) {
    const fs::path path(nameOrPath);
    if (!nameOrPath.empty() && fs::exists(path)) {
        if (fs::is_directory(path) || path.filename() == kSidecarName) return textureSetMaterial(path);
        return readMaterial(path);
    }
    if (nameOrPath == kMainJobMaterial)
        return parseMaterial(json::parse(kShapedFabricJson), "built-in material shaped-fabric");
    if (isPattern(nameOrPath)) {
        Material material;
        material.source = "built-in pattern " + nameOrPath;
        material.layers.push_back(patternLayer(nameOrPath));
        material.compose.colorFrom = 0;
        return material;
    }
    std::string names;
    for (const PatternInfo& info : patternList()) names += ", " + info.name;
    throw Error(ErrorKind::Io, "material '" + nameOrPath + "' is neither a file nor a built-in material (" +
                                   kMainJobMaterial + names + ")");
}

MaterialLayer patternLayer(const std::string& pattern, int size, std::uint32_t seed) {
    MaterialLayer layer;
    layer.pattern = pattern;
    layer.patternParams.size = size;
    layer.patternParams.seed = seed;
    return layer;
}

MaterialLayer fileLayer(const fs::path& depthOrHeight, bool isHeight, const fs::path& normal,
                        const fs::path& color) {
    const auto existing = [](const fs::path& file, const char* what) {
        std::error_code ec;
        if (!fs::is_regular_file(file, ec))
            throw Error(ErrorKind::Io, std::string(what) + ": no such file: " + file.string());
        return file;
    };
    MaterialLayer layer;
    if (isHeight)
        layer.heightFile = existing(depthOrHeight, "height");
    else
        layer.depthFile = existing(depthOrHeight, "depth");
    if (!normal.empty()) layer.normalFile = existing(normal, "normal");
    if (!color.empty()) layer.colorFile = existing(color, "color");
    layer.name = depthOrHeight.stem().string();
    return layer;
}

bool hasColor(const MaterialLayer& layer) {
    return layer.pattern.has_value() || layer.colorFile.has_value();
}

void addLayer(Material& material, MaterialLayer layer) {
    material.layers.push_back(std::move(layer));
    if (material.compose.colorFrom < 0) material.compose.colorFrom = firstLayerWithColor(material);
}

void removeLayer(Material& material, int index) {
    STRATA_CHECK(index >= 0 && index < static_cast<int>(material.layers.size()));
    material.layers.erase(material.layers.begin() + index);
    int& colorFrom = material.compose.colorFrom;
    if (colorFrom == index)
        colorFrom = firstLayerWithColor(material);
    else if (colorFrom > index)
        --colorFrom;
}

void moveLayer(Material& material, int from, int to) {
    const int count = static_cast<int>(material.layers.size());
    STRATA_CHECK(from >= 0 && from < count && to >= 0 && to < count);
    if (from == to) return;
    // Rotate the range so that layer `from` lands at `to` and the others keep their order.
    auto& layers = material.layers;
    if (from < to)
        std::rotate(layers.begin() + from, layers.begin() + from + 1, layers.begin() + to + 1);
    else
        std::rotate(layers.begin() + to, layers.begin() + from, layers.begin() + from + 1);
    int& colorFrom = material.compose.colorFrom;
    if (colorFrom == from)
        colorFrom = to;
    else if (from < to && colorFrom > from && colorFrom <= to)
        --colorFrom;
    else if (to < from && colorFrom >= to && colorFrom < from)
        ++colorFrom;
}

json materialToJson(const Material& material, const fs::path& baseDir) {
    json document = json::object();
    if (material.compose.resolution > 0) document["resolution"] = material.compose.resolution;
    document["depth_scale"] = material.compose.depthScale;
    document["normals"] = toString(material.compose.normals);
    document["color_from"] = material.compose.colorFrom;
    if (material.ao) {
        document["ao"] = toString(*material.ao);
        document["ao_method"] = toString(material.aoParams.method);
        document["ao_radius"] = material.aoParams.radius;
        document["ao_directions"] = material.aoParams.directions;
    } else {
        document["ao"] = "none";
    }
    json layers = json::array();
    for (const MaterialLayer& layer : material.layers) {
        json entry = json::object();
        if (!layer.name.empty()) entry["name"] = layer.name;
        if (layer.pattern) {
            entry["pattern"] = *layer.pattern;
            entry["size"] = layer.patternParams.size;
            entry["seed"] = layer.patternParams.seed;
            entry["depth_scale"] = layer.patternParams.depthScale;
        } else {
            if (layer.depthFile) entry["depth"] = relativePath(*layer.depthFile, baseDir);
            if (layer.heightFile) entry["height"] = relativePath(*layer.heightFile, baseDir);
            if (layer.normalFile) {
                entry["normal"] = relativePath(*layer.normalFile, baseDir);
                entry["normal_y"] = layer.normalYAuto ? "auto" : layer.normalYDown ? "down" : "up";
            }
            if (layer.fileDepthScale) entry["depth_scale"] = *layer.fileDepthScale;
            if (layer.colorFile) entry["color"] = relativePath(*layer.colorFile, baseDir);
        }
        entry["tiling"] = layer.tiling;
        entry["weight_depth"] = layer.weightDepth;
        entry["weight_normal"] = layer.weightNormal;
        layers.push_back(std::move(entry));
    }
    document["layers"] = std::move(layers);
    return document;
}

void saveMaterial(const Material& material, const fs::path& path) {
    if (path.empty()) throw Error(ErrorKind::Io, "save material: no file name given");
    std::vector<fs::path> inputs = materialInputs(material);
    // materialInputs lists the material's own file first: the one input Save may replace, unless it is a
    // texture set's sidecar (the material of an opened set is its strata.json).
    if (!inputs.empty() && inputs.front().filename() != kSidecarName) inputs.erase(inputs.begin());
    refuseToOverwriteInputs(path, inputs);
    try {
        if (path.has_parent_path()) fs::create_directories(path.parent_path());
    } catch (const fs::filesystem_error& e) {
        throw Error(ErrorKind::Io, path.string() + ": cannot create its directory: " + e.what());
    }
    const fs::path baseDir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    writeTextFileAtomic(path, materialToJson(material, baseDir).dump(2) + "\n");
}

}  // namespace strata::view
