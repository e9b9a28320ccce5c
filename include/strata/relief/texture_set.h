// A texture set on disk: the directory layout every Strata command writes and reads.
//
//   depth.png    16-bit gray, d in [0, 1] (0 = top)                         CONVENTIONS §2
//   normal.png   16-bit RGB, n * 0.5 + 0.5, OpenGL convention (green up)   CONVENTIONS §3
//   color.png    8-bit sRGB RGB (only if the set has colour)
//   ao.png       16-bit gray AO in [0, 1] (only if the set has AO)          CONVENTIONS §4
//   packed.png   16-bit RGBA: R = nx*0.5+0.5, G = ny*0.5+0.5, B = AO, A = d CONVENTIONS §5
//                (B = 1.0, fully open, while the set has no AO map)
//   strata.json  the sidecar of CONVENTIONS §6
//
// `--bit-depth 8` writes depth, normal, ao and packed as dithered 8-bit PNGs instead.
// `--format exr` writes them as 32-bit float EXRs (depth.exr, normal.exr, ao.exr, packed.exr) with the
// same encodings; colour stays an 8-bit sRGB PNG. `--write-height` adds height.png (or height.exr),
// h = 1 - d (white = high), for tools that take height. The sidecar names every file.
// Maps of different resolutions in one set are normal (e.g. colour 1024², depth 512²); packed.png
// has the depth map's resolution, with the normals resampled to it if they differ.
#pragma once

#include "strata/relief/relief_texture.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata {

inline constexpr const char* kSidecarName = "strata.json";
inline constexpr const char* kSidecarFormat = "strata.texture-set";

// How the AO map of a set was made (recorded in the sidecar; CONVENTIONS §4, §6).
struct AoRecord {
    double radius = 1.0;  // R, tile widths
    std::string definition =
        "cosine-weighted visible fraction of the hemisphere around the "
        "reference-plane normal (+z), toroidal, within R";
    std::string method;  // e.g. "sweep"
    int directions = 0;  // M, 0 = not applicable
};

// The file format of a set's data maps (depth, normal, ao, packed, height).
enum class MapFileFormat {
    Png,  // 16-bit (or 8-bit, dithered) PNG
    Exr,  // 32-bit float EXR
};
const char* toString(MapFileFormat format);  // "png", "exr"
// "png" or "exr"; throws Error(Usage) naming `flag` otherwise.
MapFileFormat parseMapFileFormat(const std::string& text, const std::string& flag = "--format");

struct TextureSetWriteOptions {
    int bitDepth = 16;  // PNG sets: 16 or 8 for depth, normal, ao and packed; colour is always 8-bit sRGB
    MapFileFormat format = MapFileFormat::Png;
    bool height = false;  // also write the height map h = 1 - d (white = high) beside depth
    // "paper" or "consistent" for composed sets, "derived" for normals computed from depth,
    // "file" for normals read from a file. Recorded in the sidecar.
    std::string normalSource = "derived";
    std::optional<AoRecord> ao;  // required when the texture has an AO map
    // Free-form provenance recorded under "source" (pattern and seed, material, input files).
    std::string sourceJson = "{}";
    // Files that must not be overwritten (the inputs of the command).
    std::vector<std::filesystem::path> inputs;
};

// Writes the set into `dir` (created if missing). All files are first written to a staging directory
// beside `dir` and then moved in, the sidecar last, so a failure leaves no partial set behind.
// Returns the paths written. Throws Error(Io) if a file cannot be written or would overwrite an input,
// Error(InvalidInput) for a bit depth other than 8 or 16 or a texture without depth or normals.
std::vector<std::filesystem::path> writeTextureSet(const std::filesystem::path& dir,
                                                   const ReliefTexture& texture,
                                                   const TextureSetWriteOptions& options = {});

// Adds (or replaces) the AO map of the set in `dir`: writes ao.png, packed.png with its B channel
// set to `ao` (its other channels copied as stored, so normals and depth are not re-quantised) and the
// sidecar's "ao" and "packed" entries, all staged and moved in as a whole, the sidecar last. `ao`:
// 1 channel at the depth map's size, in [0, 1]. Format and bit depth: the set's "file_format" (ao.exr and
// packed.exr in an EXR set) and "bit_depth". Returns the paths
// written. Throws like readSidecar, Error(InvalidInput) for an AO map of another size.
std::vector<std::filesystem::path> writeTextureSetAo(const std::filesystem::path& dir, const Image& ao,
                                                     const AoRecord& record);

// Reads a set written by writeTextureSet (its sidecar says which files exist; depth and normal are
// required). `path` is the directory or its strata.json. Throws Error(Io) for missing files and
// Error(InvalidInput) for a sidecar that is not valid JSON or not a Strata texture set.
ReliefTexture readTextureSet(const std::filesystem::path& path);

// The sidecar of a set, parsed (for `strata info`). Same errors as readTextureSet.
nlohmann::json readSidecar(const std::filesystem::path& path);

// Single maps from files, used by every input path (import, materials, texture sets) so that each
// says which encoding it reads and all of them check the same things.
enum class DepthEncoding {
    Depth,   // 0 = top, 1 = deepest (CONVENTIONS §2)
    Height,  // white = high, read as d = 1 - h
};
// A gray or gray+alpha file gives its gray channel; RGB(A) is read through its luminance and a note
// naming the file is stored in `note`. Throws like readImage.
Image readDepthMap(const std::filesystem::path& path, DepthEncoding encoding, std::string* note = nullptr);
// Decoded, renormalised unit normals in Strata's OpenGL convention; `flipY` converts a DirectX map
// (green down). Throws Error(InvalidInput) naming the file if it has fewer than 3 channels.
Image readNormalMap(const std::filesystem::path& path, bool flipY = false);

// packed.png's content (CONVENTIONS §5) as a 4-channel image at the depth map's resolution.
Image packRelief(const ReliefTexture& texture);

}  // namespace strata
