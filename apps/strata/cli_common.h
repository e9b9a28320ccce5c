// What the `strata` subcommands share: registration, progress and warning output, common options.
#pragma once

#include "strata/image/image_io.h"
#include "strata/relief/texture_set.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata::cli {

// Each subcommand lives in cmd_<name>.cpp and registers itself on the app; its callback does the work
// and throws strata::Error on failure (main() maps the kind to the exit code).
void addPatternCommand(CLI::App& app);
void addImportCommand(CLI::App& app);
void addComposeCommand(CLI::App& app);
void addAoCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addDualDepthCommand(CLI::App& app);
void addConeMapCommand(CLI::App& app);
void addMesoCommand(CLI::App& app);
void addExportCommand(CLI::App& app);
// `strata gdm` and its subcommands (cmd_gdm.cpp registers `bake`, and `trace` from cmd_gdm_trace.cpp).
void addGdmCommand(CLI::App& app);
void addGdmTraceCommand(CLI::App& gdm);

// A progress line on stderr, only when stderr is a terminal (pipes and CI logs stay clean).
void progress(const std::string& message);
// "strata: warning: ..." / "strata: note: ..." on stderr, always.
void warn(const std::string& message);
void note(const std::string& message);

// How a command writes its texture set: --bit-depth 8|16 (default 16), --format png|exr (default png) and
// --write-height, shared by every command that writes a set (pattern, import, compose).
struct SetOutputOptions {
    int bitDepth = 16;
    bool bitDepthGiven = false;
    std::string format = "png";
    bool height = false;
};
void addSetOutputOptions(CLI::App& command, SetOutputOptions& options);
// --bit-depth with --format exr is a usage error (EXR maps are float), raised when the command line is
// parsed. Copies them into `write`.
void applySetOutputOptions(const SetOutputOptions& options, TextureSetWriteOptions& write);

// The check of every --depth-scale that writes a set: (0, kMaxReliefDepthScale], as render takes it.
// CLI11 reports "--depth-scale: must be in (0, 10], got 50" (exit 1).
CLI::Validator depthScaleRange();

// Prints what was written ("wrote DIR: depth.png normal.png ...") on stdout.
void reportWritten(const std::filesystem::path& dir, const std::vector<std::filesystem::path>& files);

// A single map's sidecar sits beside it and keeps its full name: AO.png -> AO.png.json. That cannot collide
// with a texture set's strata.json or with another map's sidecar, and `ls` shows the pair together.
std::filesystem::path sidecarPathFor(const std::filesystem::path& output);
bool isPngName(const std::filesystem::path& path);  // .png, any case

// A size flag such as --size 1280x720 or 64x64x16: exactly `count` integers >= 0 separated by 'x' (or 'X').
// Throws Error(Usage) "<flag>: expected <example>, got '<text>'" otherwise. Ranges are the caller's to check.
std::vector<int> parseSizeList(const std::string& text, std::size_t count, const std::string& flag,
                               const std::string& example);

// The depth map a map-making command (ao, cone-map) reads: a depth map file (a height map with `height`),
// or a texture-set directory or its strata.json (its depth map).
struct DepthInput {
    Image depth;
    std::string encoding;                       // "depth" or "height"
    std::filesystem::path file;                 // the map that was read
    std::vector<std::filesystem::path> inputs;  // files an output must not overwrite
    std::optional<nlohmann::json> set;          // a texture set's sidecar
    std::filesystem::path setSidecar;           // and its path
};
// Throws Error(Usage) naming `command` for --height with a texture set; the read errors of readSidecar and
// readDepthMap otherwise.
DepthInput readDepthInput(const std::filesystem::path& input, bool height, const std::string& command);
// The DEPTH positional option that readDepthInput reads.
void addDepthInputOption(CLI::App& command, std::filesystem::path& input);

// Writes a map and its sidecar (sidecarPathFor(output)) so that a failure leaves neither: the sidecar is
// staged first and moves in last, the map renamed into place (atomically) inside the sidecar's write.
// Prints "wrote MAP SIDECAR".
void writeMapWithSidecar(const std::filesystem::path& output, const Image& map, const PngWriteOptions& png,
                         const nlohmann::json& sidecar);

}  // namespace strata::cli
