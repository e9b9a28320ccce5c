// strata import (--height F | --depth F) [--normal F [--normal-y auto|up|down [--force]]]
//               [--color F] [--depth-scale S] [--ao] -o DIR
// strata import --from-photo F [--large W --medium W --small W] [--invert] [--depth-scale S] [--ao] -o DIR
// strata import --check-normal F (--height F | --depth F)   reports the convention, writes nothing
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/image/image_ops.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/relief/import.h"
#include "strata/relief/relief_texture.h"

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

namespace fs = std::filesystem;

namespace strata::cli {

namespace {

struct ImportOptions {
    fs::path height;
    fs::path depth;
    fs::path normal;
    std::string normalY = "auto";
    bool force = false;
    bool ao = false;
    fs::path color;
    fs::path photo;
    fs::path checkNormal;
    PhotoImportParams photoParams;
    double depthScale = kDefaultDepthScale;
    SetOutputOptions setOutput;
    fs::path output;
};

Image readDepthInput(const ImportOptions& options, nlohmann::json& source) {
    const bool height = !options.height.empty();
    std::string readNote;
    Image depth = readDepthMap(height ? options.height : options.depth,
                               height ? DepthEncoding::Height : DepthEncoding::Depth, &readNote);
    source[height ? "height" : "depth"] = (height ? options.height : options.depth).string();
    if (!readNote.empty()) note(readNote);
    return depth;
}

void runImport(ImportOptions options) {
    const int depthInputs = !options.height.empty() + !options.depth.empty() + !options.photo.empty();
    if (depthInputs != 1)
        throw Error(ErrorKind::Usage, "import: give exactly one of --height, --depth or --from-photo");

    nlohmann::json source{{"kind", "import"}};
    if (!options.checkNormal.empty()) {
        if (!options.photo.empty())
            throw Error(ErrorKind::Usage, "import: --check-normal needs --height or --depth");
        const Image depth = readDepthInput(options, source);
        const NormalConventionReport report =
            detectNormalConvention(readNormalMap(options.checkNormal), depth);
        // Scripts branch on the exit code: 0 only for a convention found; "cannot tell" is exit 3.
        if (report.convention == NormalConvention::Unknown)
            throw Error(ErrorKind::InvalidInput,
                        options.checkNormal.string() + ": cannot tell the convention: " + report.summary);
        std::cout << options.checkNormal.string() << ": " << report.summary << "\n";
        return;
    }
    if (options.output.empty())
        throw Error(ErrorKind::Usage, "import: give the output directory with -o DIR");

    std::vector<fs::path> inputs;
    ReliefTexture texture;
    std::string normalSource = "derived";
    if (!options.photo.empty()) {
        if (!options.normal.empty() || !options.color.empty())
            throw Error(ErrorKind::Usage, "import: --from-photo makes its own normal and colour maps");
        options.photoParams.depthScale = options.depthScale;
        progress("building depth from " + options.photo.string());
        texture = reliefFromPhoto(readImage(options.photo), options.photoParams);
        source["photo"] = options.photo.string();
        source["bands"] = {{"large", options.photoParams.weightLarge},
                           {"medium", options.photoParams.weightMedium},
                           {"small", options.photoParams.weightSmall},
                           {"invert", options.photoParams.invert}};
        inputs.push_back(options.photo);
    } else {
        texture.depth = readDepthInput(options, source);
        texture.depthScale = options.depthScale;
        inputs.push_back(options.height.empty() ? options.depth : options.height);
        if (!options.normal.empty()) {
            // Read as stored (no flip) to judge the convention, then convert if needed.
            texture.normal = readNormalMap(options.normal);
            const NormalY setting = options.normalY == "up"     ? NormalY::Up
                                    : options.normalY == "down" ? NormalY::Down
                                                                : NormalY::Auto;
            const NormalYResolution resolved =
                resolveNormalY(texture.normal, texture.depth, setting, options.force, options.normal.string(),
                               "use --normal-y " + std::string(setting == NormalY::Up ? "down" : "up") +
                                   " or auto, or add --force to keep --normal-y " + options.normalY);
            if (!resolved.note.empty())
                (options.force && setting != NormalY::Auto ? warn : note)(resolved.note);
            const bool flipY = resolved.flipY;
            if (flipY)  // DirectX -> OpenGL: green points down; negating y keeps the vector unit length
                for (int y = 0; y < texture.normal.height(); ++y)
                    for (int x = 0; x < texture.normal.width(); ++x) texture.normal.at(x, y, 1) *= -1.0f;
            normalSource = flipY ? "file (DirectX, converted to OpenGL)" : "file (OpenGL)";
            source["normal"] = options.normal.string();
            inputs.push_back(options.normal);
        } else {
            texture.normal = normalsFromDepth(texture.depth, texture.depthScale);
        }
        if (!options.color.empty()) {
            texture.color = toRgb(readImage(options.color));
            source["color"] = options.color.string();
            inputs.push_back(options.color);
        }
    }

    TextureSetWriteOptions write;
    if (options.ao) {
        // The same bake as `strata ao SET` with its defaults (sweep, 50 directions, R = 1) at the set's S.
        AoParams params;
        params.depthScale = texture.depthScale;
        progress("ambient occlusion (sweep, " + std::to_string(params.directions) + " directions, R = " +
                 formatNumber(params.radius) + ", S = " + formatNumber(params.depthScale) + ")");
        texture.ao = bakeAo(texture.depth, params);
        write.ao = AoRecord{};
        write.ao->radius = params.radius;
        write.ao->method = toString(params.method);
        write.ao->directions = params.directions;
    }
    applySetOutputOptions(options.setOutput, write);
    write.normalSource = normalSource;
    write.sourceJson = source.dump();
    write.inputs = inputs;
    reportWritten(options.output, writeTextureSet(options.output, texture, write));
}

}  // namespace

void addImportCommand(CLI::App& app) {
    auto options = std::make_shared<ImportOptions>();
    CLI::App* command = app.add_subcommand(
        "import", "Make a texture set from a height, depth or normal map, or a colour photo");
    command->add_option("--height", options->height, "Height map (white = high); read as d = 1 - h");
    command->add_option("--depth", options->depth, "Depth map (0 = top, 1 = deepest)");
    command->add_option("--normal", options->normal,
                        "Tangent-space normal map (otherwise derived from depth)");
    command
        ->add_option("--normal-y", options->normalY,
                     "Green channel of --normal: up (OpenGL), down (DirectX, converted), auto (detected from "
                     "depth; up "
                     "when it cannot tell)")
        ->check(CLI::IsMember({"up", "down", "auto"}))
        ->capture_default_str();
    command->add_flag("--force", options->force,
                      "Keep an explicit --normal-y that the depth map's gradient clearly contradicts");
    command->add_option("--color", options->color, "Colour map (any resolution)");
    command->add_option("--from-photo", options->photo,
                        "Colour photo: build depth and normals from its luminance bands");
    command->add_option("--large", options->photoParams.weightLarge, "--from-photo: weight of large detail")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command
        ->add_option("--medium", options->photoParams.weightMedium, "--from-photo: weight of medium detail")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_option("--small", options->photoParams.weightSmall, "--from-photo: weight of fine detail")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_flag("--invert", options->photoParams.invert,
                      "--from-photo: dark is high instead of bright");
    command->add_flag("--ao", options->ao,
                      "Bake the AO map into the set (as `strata ao SET` with its defaults: sweep, 50 "
                      "directions, R = 1)");
    command->add_option("--check-normal", options->checkNormal,
                        "Report whether this normal map is OpenGL or DirectX, by comparing it with "
                        "--height/--depth; writes nothing");
    command
        ->add_option("--depth-scale", options->depthScale,
                     "Depth scale S (depth of d = 1 in tile widths), (0, 10]")
        ->check(depthScaleRange())
        ->capture_default_str();
    addSetOutputOptions(*command, options->setOutput);
    command->add_option("-o,--output", options->output, "Output directory");
    command->callback([options] { runImport(*options); });
}

}  // namespace strata::cli
