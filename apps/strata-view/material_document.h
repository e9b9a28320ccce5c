// The material the viewer edits: a strata::Material (scene/material.h, the same struct `strata compose`
// reads), how the viewer opens one, the edits its Layers panel makes, and writing it back as JSON.
#pragma once

#include "strata/scene/material.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <string>

namespace strata::view {

// Opens what the viewer was given, like `strata render --material` resolves a name (scene/scene.h):
//   - an existing material JSON: read and validated (readMaterial);
//   - an existing texture set directory or its strata.json: one file layer with the set's depth, normal
//     and colour maps at the set's depth scale (so the set can take more layers); its AO is re-baked;
//   - "shaped-fabric": the main job's material (base + fabric, weights 1.0 / 0.3);
//   - a built-in pattern name: one pattern layer, 512^2, seed 1.
// Throws Error(Io) for a name that is neither (listing the built-ins), and like readMaterial /
// readSidecar for a bad file.
Material openMaterial(const std::string& nameOrPath);

// A pattern layer as `strata pattern NAME --size N --seed K` makes it (tiling 1, weights 1).
MaterialLayer patternLayer(const std::string& pattern, int size = 512, std::uint32_t seed = 1);

// A file layer: `depthOrHeight` read as depth (0 = top) or, with `isHeight`, as height (white = high);
// optional normal map (OpenGL convention) and colour map (empty paths: none). Throws Error(Io) naming the
// file if one does not exist. The maps are read by loadLayers (scene/material.h).
MaterialLayer fileLayer(const std::filesystem::path& depthOrHeight, bool isHeight,
                        const std::filesystem::path& normal, const std::filesystem::path& color);

// Layer edits that keep compose.colorFrom on the same layer (or on the first layer with colour, or -1,
// when its layer is removed). Indices out of range are a bug in the caller (checked).
void addLayer(Material& material, MaterialLayer layer);
void removeLayer(Material& material, int index);
void moveLayer(Material& material, int from, int to);
// Whether a layer has a colour map (every pattern does).
bool hasColor(const MaterialLayer& layer);

// The material as a material JSON document (docs/material.md) that parseMaterial reads back to the same
// Material. File paths are written relative to `baseDir` (the directory of the file it will be saved in)
// where they can be, else absolute.
nlohmann::json materialToJson(const Material& material, const std::filesystem::path& baseDir);

// Writes materialToJson(material, path's directory) to `path` (atomic; creates the directory). Refuses
// (Error(Io)) to overwrite a file the material reads other than its own JSON: saving an edited material
// over the file it was opened from is what an editor's Save does.
void saveMaterial(const Material& material, const std::filesystem::path& path);

}  // namespace strata::view
