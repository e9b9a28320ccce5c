// strata ao DEPTH -o AO.png --depth-scale S [--radius R] [--directions M] [--method sweep|paper|brute]
//          [--filter auto|paper|none] [--normalize open|paper] [--height] [--bit-depth 8|16]
// DEPTH: a depth map (or, with --height, a height map), or a texture-set directory or its strata.json
// (its depth map, and its depth scale unless --depth-scale is given).
// Writes AO.png (gray, the input's resolution) and its sidecar AO.png.json.
// strata ao SET [--radius R] [--directions M] [--method ...]: without -o, a texture set's AO is baked at
// its own depth scale into the set: ao.png, packed.png's B channel and strata.json, moved in as a whole.
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/core/version.h"
#include "strata/image/image_io.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/relief/texture_set.h"

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <optional>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata::cli {

namespace {

inline constexpr const char* kAoSidecarFormat = "strata.ao-map";

struct AoOptions {
    fs::path input;
    fs::path output;
    std::optional<double> depthScale;
    double radius = 1.0;
    int directions = 50;
    std::string method = "sweep";
    std::string filter = "auto";
    std::string normalize = "open";
    bool height = false;
    int bitDepth = 16;
};

// The depth map to bake (cli_common.h) and the depth scale S: --depth-scale, else a texture set's.
DepthInput readInput(const AoOptions& options, double* depthScale) {
    std::error_code ec;
    const bool isSet = fs::is_directory(options.input, ec) || options.input.extension() == ".json";
    if (!isSet && !options.depthScale)
        throw Error(ErrorKind::Usage,
                    "ao: --depth-scale S is required for a depth or height map (AO depends on S; only a "
                    "texture set records it)");
    DepthInput input = readDepthInput(options.input, options.height, "ao");
    if (options.depthScale) {
        *depthScale = *options.depthScale;
    } else {
        const auto scale = input.set->find("depth_scale");
        if (scale == input.set->end() || !scale->is_number())
            throw Error(ErrorKind::InvalidInput,
                        input.setSidecar.string() + ": \"depth_scale\" is missing or not a number");
        *depthScale = scale->get<double>();
    }
    return input;
}

void runAo(const AoOptions& options) {
    std::error_code ec;
    const bool isSet = fs::is_directory(options.input, ec) || options.input.extension() == ".json";
    if (options.output.empty()) {
        if (!isSet)
            throw Error(ErrorKind::Usage,
                        "ao: give -o AO.png (only a texture set can be updated in place, got " +
                            options.input.string() + ")");
        if (options.depthScale)
            throw Error(
                ErrorKind::Usage,
                "ao: --depth-scale cannot be given when updating a texture set: its AO is baked at the "
                "set's own depth scale (use -o AO.png for a loose map at another scale)");
    }
    if (!options.output.empty()) checkOutputExtension(options.output, "ao: -o", {ImageFormat::Png});
    const fs::path sidecarPath = options.output.empty() ? fs::path() : sidecarPathFor(options.output);

    // Read and bake everything before writing anything.
    progress("reading " + options.input.string());
    double depthScale = 0.0;
    const DepthInput input = readInput(options, &depthScale);
    if (!options.output.empty())
        for (const fs::path& output : {options.output, sidecarPath})
            refuseToOverwriteInputs(output, input.inputs);

    AoParams params;
    params.method = parseAoMethod(options.method);
    params.directions = options.directions;
    params.radius = options.radius;
    params.depthScale = depthScale;
    params.filter = parseAoFilter(options.filter);
    params.normalize = parseAoNormalize(options.normalize);
    progress("ambient occlusion (" + options.method + ", " + std::to_string(params.directions) +
             " directions, R = " + formatNumber(params.radius) + ", S = " + formatNumber(params.depthScale) +
             ") of " + std::to_string(input.depth.width()) + "x" + std::to_string(input.depth.height()));
    const Image ao = bakeAo(input.depth, params);

    if (options.output.empty()) {
        AoRecord setRecord;
        setRecord.radius = params.radius;
        setRecord.method = toString(params.method);
        setRecord.directions = params.directions;
        const fs::path dir =
            fs::is_directory(options.input, ec) ? options.input : options.input.parent_path();
        reportWritten(dir, writeTextureSetAo(dir, ao, setRecord));
        return;
    }
    const AoRecord record;  // the definition text every Strata AO file carries (CONVENTIONS §4)
    json sidecar;
    sidecar["format"] = kAoSidecarFormat;
    sidecar["format_version"] = 1;
    sidecar["tool"] = std::string("strata ") + kVersion;
    sidecar["file"] = options.output.filename().string();
    sidecar["size"] = json::array({ao.width(), ao.height()});
    sidecar["bit_depth"] = options.bitDepth;
    sidecar["encoding"] = "gray, AO in [0, 1], 1 = fully open";
    sidecar["texture_space"] =
        "u along +x (tangent), v along +y (bitangent); file row 0 is v = 1; tiles toroidally";
    sidecar["definition"] = record.definition;
    sidecar["depth_scale"] = params.depthScale;
    sidecar["radius"] = params.radius;
    sidecar["directions"] = params.directions;
    sidecar["method"] = toString(params.method);
    sidecar["filter"] = options.filter;
    sidecar["normalize"] = options.normalize;
    sidecar["input"] = {{"file", input.file.string()}, {"encoding", input.encoding}};

    writeMapWithSidecar(options.output, ao,
                        {options.bitDepth == 8 ? PngBitDepth::Eight : PngBitDepth::Sixteen, true}, sidecar);
}

}  // namespace

void addAoCommand(CLI::App& app) {
    auto options = std::make_shared<AoOptions>();
    CLI::App* command = app.add_subcommand(
        "ao", "Bake the ambient-occlusion map of a depth map or texture set (meta-relief paper, Sec. IV)");
    addDepthInputOption(*command, options->input);
    command->add_option(
        "-o,--output", options->output,
        "Output AO map (.png); its sidecar is <output>.json. Without -o, a texture set's AO is "
        "written into the set (ao.png, packed.png, strata.json)");
    command
        ->add_option("--depth-scale", options->depthScale,
                     "Depth scale S (depth of d = 1 in tile widths), (0, 100]; required unless the input is "
                     "a texture set")
        ->check(CLI::PositiveNumber & CLI::Range(0.0, 100.0));
    command->add_option("--radius", options->radius, "Search radius R in tile widths, (0, 16]")
        ->check(CLI::PositiveNumber & CLI::Range(0.0, 16.0))
        ->capture_default_str();
    command->add_option("--directions", options->directions, "Number of directions M, [3, 1024]")
        ->check(CLI::Range(3, 1024))
        ->capture_default_str();
    command
        ->add_option("--method", options->method,
                     "sweep (exact horizons, default), paper (the paper's polygon), brute (marched)")
        ->check(CLI::IsMember({"sweep", "paper", "brute"}))
        ->capture_default_str();
    command
        ->add_option("--filter", options->filter,
                     "Low-pass filter at occluded texels: auto (paper for --method paper), paper, none")
        ->check(CLI::IsMember({"auto", "paper", "none"}))
        ->capture_default_str();
    command
        ->add_option("--normalize", options->normalize,
                     "--method paper: open (open = 1) or paper (divide by pi, open = 0.997 at M = 50)")
        ->check(CLI::IsMember({"open", "paper"}))
        ->capture_default_str();
    command->add_flag("--height", options->height, "The input is a height map (white = high): d = 1 - h");
    command->add_option("--bit-depth", options->bitDepth, "Bit depth of the AO PNG (8-bit is dithered)")
        ->check(CLI::IsMember({8, 16}))
        ->capture_default_str();
    command->callback([options] { runAo(*options); });
}

}  // namespace strata::cli
