// clang-format off
// The meta-relief material file (JSON): a list of layers and how to combine them.
// docs/material.md documents every key; examples/*.json are working materials.
//
//   {
//     "resolution": 1024, "depth_scale": 0.08, "normals": "paper", "color_from": 1,
//     "layers": [
//       { "pattern": "base", "size": 1024, "seed": 1,
//         "tiling": 1.0, "weight_depth": 1.0, "weight_normal": 1.0 },
//       { "depth": "fabric_depth.png", "normal": "fabric_normal.png", "color": "fabric.png",
//         "tiling": 5.5, "weight_depth": 0.3, "weight_normal": 0.3 }
//     ]
//   }
//
// A layer is either a built-in pattern ("pattern", with "size", "seed", "depth_scale" defaulting to the
// pattern defaults of PatternParams, so the layer equals `strata pattern NAME` with the same flags) or
// files ("depth" or "height", optional "normal" with "normal_y": "up" | "down" | "auto", optional "color").
// Paths are relative to the material file. A file layer without a normal map gets normals derived
// from its depth at the material's depth_scale.
//
// The top-level keys "ao", "ao_method", "ao_radius" and "ao_directions" say how the set's AO map is made
// (Material::ao, Material::aoParams; strata/occlusion/meta_relief_ao.h has the modes).
//
// Parsing is strict: an unknown key, a wrong type, a value out of range, a missing file, both or
// neither of "depth"/"height", or a layer with both "pattern" and files throws Error(InvalidInput)
// (Error(Io) for a missing file) whose message is "<file>: <key path>: <what is wrong>", e.g.
// "shaped.json: layers[1].weight_depth: must be >= 0, got -0.3". Nothing is written for a rejected
// material: callers load everything before writing anything.
// clang-format on
#pragma once

#include "strata/compose/compose.h"
#include "strata/occlusion/meta_relief_ao.h"
#include "strata/relief/patterns.h"

#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata {

struct MaterialLayer {
    std::string name;  // optional label ("name"), used in messages
    // Pattern layer.
    std::optional<std::string> pattern;  // "pattern": a name from patternList()
    PatternParams patternParams;         // "size", "seed", "depth_scale"
    // File layer (paths already resolved against the material's directory).
    std::optional<std::filesystem::path> depthFile;   // "depth": d in [0, 1], 0 = top
    std::optional<std::filesystem::path> heightFile;  // "height": white = high, d = 1 - h
    std::optional<std::filesystem::path> normalFile;  // "normal"
    bool normalYDown = false;                         // "normal_y": "up" (OpenGL, default) | "down" (DirectX)
    bool normalYAuto = false;  // "normal_y": "auto": detected from the layer's depth at load (up if unknown)
    std::optional<double> fileDepthScale;  // "depth_scale": the S the layer's normal map was made for
    std::optional<std::filesystem::path> colorFile;  // "color"
    // Combination (paper Eq. 1, 2).
    double tiling = 1.0;        // "tiling": > 0
    double weightDepth = 1.0;   // "weight_depth": >= 0
    double weightNormal = 1.0;  // "weight_normal": >= 0
};

struct Material {
    std::filesystem::path source;  // the material file, for messages
    ComposeParams compose;         // "resolution", "depth_scale", "normals", "color_from"
    std::vector<MaterialLayer> layers;
    // Ambient occlusion (strata/occlusion/meta_relief_ao.h). "ao": "exact" (default) | "multiply" |
    // "min" | "none"; nullopt is "none": no AO map, packed B = 1 (fully open).
    std::optional<MetaAoMode> ao = MetaAoMode::Exact;
    // "ao_method": "sweep" (default) | "paper" | "brute"; "ao_radius": R in composed tile widths, (0, 16],
    // default 1; "ao_directions": M, [3, 1024], default 50. Everything else keeps AoParams' defaults;
    // depthScale is not used (S is compose.depthScale).
    AoParams aoParams;
};

// The most layers a material may have (error 3 beyond): the papers combine two to four, and each layer
// costs a full map and a pass of every composition and AO step.
inline constexpr std::size_t kMaxMaterialLayers = 64;
// A layer's tiling is in (0, kMaxLayerTiling]: beyond, a tile is smaller than a texel of the largest map.
inline constexpr double kMaxLayerTiling = 4096.0;
// A layer's weights are in [0, kMaxLayerWeight]: they are relative, and their sum must stay finite.
inline constexpr double kMaxLayerWeight = 1e6;

// Parses and validates a material document. `source` names it in messages and its directory
// resolves relative paths. Files are checked for existence here; they are read by loadLayers.
Material parseMaterial(const nlohmann::json& document, const std::filesystem::path& source);

// Reads and parses a material file. Throws Error(Io) if it cannot be read and Error(InvalidInput)
// with the line and column for malformed JSON.
Material readMaterial(const std::filesystem::path& path);

// Builds every layer's maps: generates patterns, reads files (RGB depth/height maps through their
// luminance; such notes are appended to `notes`). `progress` (may be empty) hears "layer i/N: label"
// before each. Throws on unreadable or invalid files.
std::vector<CompositionLayer> loadLayers(const Material& material, std::vector<std::string>* notes = nullptr,
                                         const MetaAoProgress& progress = {});

// The material's texture: its layers loaded (loadLayers), composed (compose) and, unless material.ao is
// none, its AO map made by metaReliefAo. Warnings of the composition and notes of the loaders are appended
// to `notes`; `progress` (may be empty) hears a line before each long step. Throws like those functions.
ReliefTexture composeMaterial(const Material& material, std::vector<std::string>* notes = nullptr,
                              const MetaAoProgress& progress = {});

// How loadLayers names layer `index` in messages: "layers[1] (fabric)" (its "name", else its pattern).
std::string layerLabel(std::size_t index, const MaterialLayer& layer);
// The layer's combination keys (tiling and weights) set on `layer`, and its label (layerLabel): what
// loadLayers does after loading the maps, for callers that cache the maps and change only these.
void applyLayerSettings(std::size_t index, const MaterialLayer& spec, CompositionLayer& layer);

// All input files a material reads (for the never-overwrite-an-input check).
std::vector<std::filesystem::path> materialInputs(const Material& material);

}  // namespace strata
