// strata meso --list
// strata meso NAME [--height H] [--seed N] [--resolution N] [--preview-size N] -o DIR
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gdm/mesostructure_preview.h"

#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>

namespace strata::cli {

namespace {

struct MesoOptions {
    bool list = false;
    std::string name;
    std::optional<double> height;
    std::uint32_t seed = 1;
    int resolution = 64;
    MesostructurePreviewParams preview;
    std::filesystem::path output;
};

void runMeso(const MesoOptions& options) {
    if (options.list) {
        for (const auto& info : mesostructureList())
            std::cout << std::left << std::setw(8) << info.name << "H " << std::setw(6) << info.defaultHeight
                      << info.description << "\n";
        return;
    }
    if (options.name.empty())
        throw Error(ErrorKind::Usage, "meso: give a mesostructure NAME (see `strata meso --list`)");
    if (options.output.empty()) throw Error(ErrorKind::Usage, "meso: give the output directory with -o DIR");
    if (options.height && !(std::isfinite(*options.height) && *options.height > 0.0))
        throw Error(ErrorKind::InvalidInput, "meso: --height must be a number > 0 (tile widths), got " +
                                                 formatNumber(*options.height));
    MesostructureParams params;
    params.height = options.height.value_or(0.0);
    params.seed = options.seed;
    const Mesostructure meso = makeMesostructure(options.name, params);
    progress("meshing " + options.name + " at " + std::to_string(options.resolution) + " voxels per tile");
    const SolidMesh mesh = meshMesostructure(meso, options.resolution);
    progress("rendering the preview");
    const Image preview = renderMesostructurePreview(meso, options.preview);
    reportWritten(options.output, writeMesostructureOutputs(options.output, mesh, preview));
}

}  // namespace

void addMesoCommand(CLI::App& app) {
    auto options = std::make_shared<MesoOptions>();
    CLI::App* command =
        app.add_subcommand("meso", "Write a built-in mesostructure as a solid mesh (OBJ) with a preview");
    command->add_flag("--list", options->list, "List the built-in mesostructures and exit");
    command->add_option("name", options->name, "Mesostructure name (see --list)");
    command->add_option("--height", options->height,
                        "Shell thickness H in tile widths (> 0; default: the structure's own)");
    command->add_option("--seed", options->seed, "Random seed")->capture_default_str();
    command->add_option("--resolution", options->resolution, "Meshing voxels per tile width")
        ->check(CLI::Range(kMinMeshResolution, kMaxMeshResolution))
        ->capture_default_str();
    command->add_option("--preview-size", options->preview.size, "Width = height of preview.png, pixels")
        ->check(CLI::Range(16, 4096))
        ->capture_default_str();
    command->add_option("-o,--output", options->output, "Output directory (mesh.obj, preview.png)");
    command->callback([options] { runMeso(*options); });
}

}  // namespace strata::cli
