// Export presets: a texture set written in the layout a game engine reads (docs/export.md).
//
//   gltf        a glTF 2.0 asset (.gltf + .bin + PNGs): base colour, OpenGL normal map, ORM (R AO,
//               G roughness, B metallic), the height in the material's extras "strata_height"
//   unity-hdrp  HDRP Lit: base colour, OpenGL normal, mask map (R metallic, G AO, B detail mask,
//               A smoothness), white-is-high height with its amplitude
//   unreal      base colour, DirectX normal (green down), ARM (R AO, G roughness, B metallic), height
//   godot       Godot 4 StandardMaterial3D / ORMMaterial3D: albedo, OpenGL normal, ORM, height
//   strata      Strata's own set (depth, height next to it, normal, colour, AO, packed, strata.json),
//               as 16-bit PNG or as 32-bit float EXR
//
// Every preset's output is a directory written all or nothing (a staging directory beside it, moved in
// when every file is complete) with a manifest, export.json, naming each file's channels (the strata
// preset's manifest is its strata.json). Roughness and metallic are constants: a texture set has no maps
// of them.
#pragma once

#include "strata/mesh/mesh.h"
#include "strata/relief/relief_texture.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata {

enum class ExportPreset { Gltf, UnityHdrp, Unreal, Godot, Strata };
enum class NormalY { Up, Down };  // Up: OpenGL (green towards v = 1); Down: DirectX
enum class ExportFormat { Png, Exr };

// One channel (or all channels) of one output file.
struct ExportChannel {
    std::string file;     // e.g. "mask.png"
    std::string channel;  // "RGB", "R", "G", "B", "A" or "gray"
    std::string content;  // what it holds, e.g. "metallic (constant --metallic)"
};

// A preset as data: its name, the engine documentation it follows, its default normal convention and
// its channel table.
struct ExportPresetSpec {
    ExportPreset preset;
    std::string name;                     // as on the command line: "gltf", "unity-hdrp", ...
    std::string engine;                   // "glTF 2.0", "Unity HDRP (Lit shader)", ...
    NormalY normalY;                      // the engine's convention (the default of --normal-y)
    std::vector<std::string> sources;     // engine documentation pages followed (titles)
    std::vector<ExportChannel> channels;  // with file names for the PNG format
};

const std::vector<ExportPresetSpec>& exportPresets();
const ExportPresetSpec& exportPresetSpec(ExportPreset preset);
// Throws Error(Usage) naming --preset and the value, listing the known names.
ExportPreset parseExportPreset(const std::string& name);
NormalY parseNormalY(const std::string& text);            // "up" | "down"; Error(Usage) naming --normal-y
ExportFormat parseExportFormat(const std::string& text);  // "png" | "exr"; Error(Usage) naming --format

struct ExportOptions {
    ExportPreset preset = ExportPreset::Gltf;
    std::optional<NormalY> normalY;           // default: the preset's
    ExportFormat format = ExportFormat::Png;  // Exr: the strata preset only (engines read the PNGs)
    double roughness = 0.8;                   // [0, 1]
    double metallic = 0.0;                    // [0, 1]
    // gltf: the mesh to put the material on; none = the built-in "quad", the unit quad of CONVENTIONS §7.
    std::optional<Mesh> mesh;
    std::string assetName = "relief";  // gltf: <assetName>.gltf and <assetName>.bin
    // The input set's sidecar (JSON text), carried into the strata preset's strata.json; may be empty.
    std::string sourceSidecar;
    std::vector<std::filesystem::path> inputs;  // files that must not be overwritten
};

// The checks of exportTextureSet that need no texture (the CLI runs them before reading the set): throws
// Error(Usage) for gltf with NormalY::Down or EXR with an engine preset, Error(InvalidInput) for roughness or
// metallic outside [0, 1].
void checkExportOptions(const ExportOptions& options);

// Writes `texture` into `dir` in the preset's layout. Returns the files written (the manifest last).
// Throws Error(Usage) for a combination the preset cannot write (gltf with --normal-y down, EXR for an
// engine preset), Error(InvalidInput) for a texture without depth or normals or roughness/metallic
// outside [0, 1], Error(Io) when a file cannot be written or would overwrite an input.
std::vector<std::filesystem::path> exportTextureSet(const std::filesystem::path& dir,
                                                    const ReliefTexture& texture,
                                                    const ExportOptions& options);

}  // namespace strata
