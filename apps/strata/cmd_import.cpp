// strata import (--height F | --depth F) [--normal F [--normal-y up|down|auto]] [--color F] [--depth-scale S]
// -o DIR strata import --from-photo F [--large W --medium W --small W] [--invert] [--depth-scale S] -o DIR
// strata import --check-normal F (--height F | --depth F)      reports the normal map's convention, writes
// nothing
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/image/image_ops.h"
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
    std::string normalY = "up";
    fs::path color;
    fs::path photo;
    fs::path checkNormal;
    PhotoImportParams photoParams;
    double depthScale = kDefaultDepthScale;
    int bitDepth = 16;
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
            const NormalConventionReport report = detectNormalConvention(texture.normal, texture.depth);
            bool flipY = options.normalY == "down";
            if (options.normalY == "auto") {
                if (report.convention == NormalConvention::Unknown)
                    throw Error(ErrorKind::InvalidInput,
                                options.normal.string() +
                                    ": --normal-y auto cannot tell the convention: " + report.summary);
                flipY = report.convention == NormalConvention::DirectX;
                note(options.normal.string() + ": " + report.summary);
            } else if ((report.convention == NormalConvention::DirectX && !flipY) ||
                       (report.convention == NormalConvention::OpenGL && flipY)) {
                warn(options.normal.string() + ": read with --normal-y " + options.normalY + ", but " +
                     report.summary);
            }
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
    write.bitDepth = options.bitDepth;
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
        ->add_option(
            "--normal-y", options->normalY,
            "Green channel of --normal: up (OpenGL), down (DirectX, converted), auto (detected from depth)")
        ->check(CLI::IsMember({"up", "down", "auto"}))
        ->capture_default_str();
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
    command->add_option("--check-normal", options->checkNormal,
                        "Report whether this normal map is OpenGL or DirectX, by comparing it with "
                        "--height/--depth; writes nothing");
    command
        ->add_option("--depth-scale", options->depthScale,
                     "Depth scale S (depth of d = 1 in tile widths), (0, 10]")
        ->check(depthScaleRange())
        ->capture_default_str();
    addBitDepthOption(*command, options->bitDepth);
    command->add_option("-o,--output", options->output, "Output directory");
    command->callback([options] { runImport(*options); });
}

}  // namespace strata::cli
