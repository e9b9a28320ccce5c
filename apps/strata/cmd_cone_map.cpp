// strata cone-map DEPTH -o CONE.png [--height] [--depth-levels K] [--max-ratio C]
// DEPTH: a depth map (or, with --height, a height map), or a texture-set directory or its strata.json.
// Writes CONE.png (16-bit gray + alpha: per cell the highest point and the encoded cone ratio, exactly what
// the `cone` technique reads) and its sidecar CONE.png.json (docs/cli.md, docs/renderer.md).
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/core/version.h"
#include "strata/image/image_io.h"
#include "strata/image/quantize.h"
#include "strata/relief/cone_map.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata::cli {

namespace {

inline constexpr const char* kConeSidecarFormat = "strata.cone-map";

struct ConeMapCommandOptions {
    fs::path input;
    fs::path output;
    bool height = false;
    int depthLevels = ConeMapOptions{}.depthLevels;
    float maxRatio = 0.0f;
};

void runConeMap(const ConeMapCommandOptions& options) {
    checkOutputExtension(options.output, "cone-map: -o", {ImageFormat::Png});
    const fs::path sidecarPath = sidecarPathFor(options.output);

    progress("reading " + options.input.string());
    DepthInput input = readDepthInput(options.input, options.height, "cone-map");
    for (const fs::path& output : {options.output, sidecarPath})
        refuseToOverwriteInputs(output, input.inputs);
    // The cones must describe the height field a shader will sample: the depth as a 16-bit texture holds
    // it (the file's own values for a 16-bit map).
    for (float& d : input.depth.pixels()) d = quantizeUnorm16(d);

    ConeMapOptions coneOptions;
    coneOptions.depthLevels = options.depthLevels;
    coneOptions.maxRatio = options.maxRatio;
    progress("cone map of " + std::to_string(input.depth.width()) + "x" +
             std::to_string(input.depth.height()) + ", " + std::to_string(options.depthLevels) +
             " depth bands");
    const PackedConeMap packed = packConeMap(input.depth, coneOptions);
    // Frame rows (v up) to file rows (top row first, CONVENTIONS §1): a loader that flips the rows on upload,
    // as GL needs (t = v), gets the frame back.
    const int width = packed.texels.width(), height = packed.texels.height();
    Image file(width, height, 2);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 2; ++c) file.at(x, height - 1 - y, c) = packed.texels.at(x, y, c);

    json sidecar;
    sidecar["format"] = kConeSidecarFormat;
    sidecar["format_version"] = 1;
    sidecar["tool"] = std::string("strata ") + kVersion;
    sidecar["file"] = options.output.filename().string();
    sidecar["size"] = json::array({width, height});
    sidecar["bit_depth"] = 16;
    sidecar["encoding"] =
        "gray = m, the cell's highest point (smallest corner depth, rounded down to 16 bits); alpha = "
        "sqrt(c / max_ratio) rounded down, c the cone ratio in texels per unit of depth: for every point x "
        "of the cell, d(y) >= d(x) - |y - x| / c everywhere (decode c = (alpha)^2 * max_ratio)";
    sidecar["cells"] =
        "after a row flip on upload (t = v), texel (i, j) is the cell between the depth map's texel centres "
        "i, i + 1 along u and j, j + 1 along v counting rows from v = 0, wrapping; in file terms, file texel "
        "(i, r) is the cell between depth-map file columns i, i + 1 and rows r, r - 1 (row 0: the top row "
        "and, wrapping, the bottom one)";
    sidecar["max_ratio"] = packed.maxRatio;
    sidecar["depth_levels"] = packed.depthLevels;
    sidecar["input"] = {{"file", input.file.string()}, {"encoding", input.encoding}};

    writeMapWithSidecar(options.output, file, {PngBitDepth::Sixteen, false}, sidecar);
}

}  // namespace

void addConeMapCommand(CLI::App& app) {
    auto options = std::make_shared<ConeMapCommandOptions>();
    CLI::App* command = app.add_subcommand(
        "cone-map", "Make the conservative cone map of a depth map or texture set (the `cone` technique's)");
    addDepthInputOption(*command, options->input);
    command
        ->add_option("-o,--output", options->output, "Output cone map (.png); its sidecar is <output>.json")
        ->required();
    command->add_flag("--height", options->height, "The input file is a height map (white = high)");
    command
        ->add_option("--depth-levels", options->depthLevels,
                     "Depth bands of the far-field bound, [1, 4096]: more give wider cones, cost linearly")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    command
        ->add_option("--max-ratio", options->maxRatio,
                     "Cap on the cone ratio in texels per unit of depth (default: the map's larger side)")
        ->check(CLI::PositiveNumber);
    command->callback([options] { runConeMap(*options); });
}

}  // namespace strata::cli
