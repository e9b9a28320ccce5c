// strata gdm bake (--meso NAME | --mesh F.obj | --vdb F.vdb) [--height H] [--size NXxNYxNZ] [--dirs NTxNP]
//                 [--rank K] [--layout xy-phi|xyz|xy] [--keep-raw] [--seed N] -o DIR
//
// `strata gdm` is a group: each of its subcommands registers itself on the `gdm` app (addGdmCommand below);
// `strata gdm trace` lives in cmd_gdm_trace.cpp.
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gdm/solid_mesh_io.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace fs = std::filesystem;

namespace strata::cli {

namespace {

struct GdmBakeOptions {
    std::string meso;
    fs::path mesh;
    fs::path vdb;
    std::optional<double> height;
    std::string size = "64x64x16";
    std::string dirs = "16x32";
    int rank = 8;
    std::string layout = "xy-phi";
    bool keepRaw = false;
    std::uint32_t seed = 1;
    fs::path output;
};

GdmLayout parseLayout(const std::string& name) {
    if (name == "xy-phi") return GdmLayout::XyPhiByThetaZ;
    if (name == "xyz") return GdmLayout::XyzByThetaPhi;
    if (name == "xy") return GdmLayout::XyByZThetaPhi;
    throw Error(ErrorKind::Usage, "gdm bake: --layout must be xy-phi, xyz or xy, got \"" + name + "\"");
}

std::string utcNow() {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return text;
}

void runGdmBake(const GdmBakeOptions& options) {
    const int sources = int(!options.meso.empty()) + int(!options.mesh.empty()) + int(!options.vdb.empty());
    if (sources != 1) throw Error(ErrorKind::Usage, "gdm bake: give exactly one of --meso, --mesh, --vdb");
    if (options.output.empty())
        throw Error(ErrorKind::Usage, "gdm bake: give the output directory with -o DIR");
    if (options.meso.empty() && !options.height)
        throw Error(ErrorKind::Usage,
                    "gdm bake: --mesh and --vdb need --height H (the mesh's shell thickness)");
    if (options.height && !(std::isfinite(*options.height) && *options.height > 0.0))
        throw Error(ErrorKind::InvalidInput, "gdm bake: --height must be a number > 0 (tile widths), got " +
                                                 formatNumber(*options.height));
    const std::vector<int> size = parseSizeList(options.size, 3, "--size", "NXxNYxNZ (e.g. 64x64x16)");
    const std::vector<int> dirs = parseSizeList(options.dirs, 2, "--dirs", "NTHETAxNPHI (e.g. 16x32)");
    const GdmDims dims{size[0], size[1], size[2], dirs[0], dirs[1]};
    const GdmLayout layout = parseLayout(options.layout);
    if (options.rank < 1)
        throw Error(ErrorKind::Usage, "gdm bake: --rank must be >= 1, got " + std::to_string(options.rank));
    if (dims.nx > 0 && dims.ny > 0 && dims.nz > 0 && dims.ntheta > 0 && dims.nphi > 0) {
        const std::size_t limit = std::min(gdmLayoutRows(dims, layout), gdmLayoutCols(dims, layout));
        if (std::size_t(options.rank) > limit)
            throw Error(ErrorKind::InvalidInput,
                        "gdm bake: --rank " + std::to_string(options.rank) +
                            " is more than min(rows, cols) = " + std::to_string(limit) + " of layout " +
                            toString(layout) + " at these dims");
    }
    // Refuse an output that could not be written before the (long) bake, not after it.
    std::error_code ec;
    if (fs::exists(options.output, ec)) {
        if (!fs::is_directory(options.output, ec))
            throw Error(ErrorKind::Io, options.output.string() + ": exists and is not a directory");
        if (fs::directory_iterator(options.output, ec) != fs::directory_iterator() &&
            !isGdmAsset(options.output))
            throw Error(ErrorKind::Io, options.output.string() +
                                           ": exists and is not a GDM asset (refusing to overwrite it)");
    }

    const auto start = std::chrono::steady_clock::now();
    SolidMesh solid;
    std::string source;
    std::vector<fs::path> inputs;
    std::vector<std::uint8_t> albedo;
    if (!options.meso.empty()) {
        MesostructureParams params;
        params.height = options.height.value_or(0.0);
        params.seed = options.seed;
        const Mesostructure meso = makeMesostructure(options.meso, params);
        validateGdmDims(dims, meso.height(), "gdm bake");
        const int resolution = std::clamp(std::max(dims.nx, dims.ny), kMinMeshResolution, kMaxMeshResolution);
        progress("meshing " + options.meso + " at " + std::to_string(resolution) + " voxels per tile");
        solid = meshMesostructure(meso, resolution);
        source = "meso " + options.meso;
        albedo = mesostructureAlbedo(meso, dims);
    } else {
        validateGdmDims(dims, *options.height, "gdm bake");
        const fs::path& file = options.mesh.empty() ? options.vdb : options.mesh;
        solid =
            options.mesh.empty() ? readSolidVdb(file, *options.height) : readSolidObj(file, *options.height);
        source = file.string();
        inputs.push_back(file);
    }

    int lastPercent = -1;
    const Gdm raw = bakeGdm(solid, dims, [&](double done) {
        const int percent = int(done * 100.0);
        if (percent / 10 == lastPercent / 10 && percent != 100) return;
        lastPercent = percent;
        progress("baking " + std::to_string(percent) + "%");
    });
    progress("compressing to rank " + std::to_string(options.rank));
    GdmAsset asset;
    asset.svd = compressGdm(raw, options.rank, layout);
    asset.occupancy = gdmOccupancy(raw);
    asset.albedo = std::move(albedo);
    if (options.keepRaw) asset.raw = raw;
    progress("signed distance volume");
    asset.distance = bakeGdmDistance(solid, dims);  // for the GL renderer's refine technique
    asset.solid = std::move(solid);                 // for the exact reference (strata gdm trace --reference)
    asset.source = source;
    std::ostringstream settings;
    settings << "--size " << options.size << " --dirs " << options.dirs << " --height "
             << formatNumber(asset.svd.height) << " --rank " << options.rank << " --layout " << options.layout
             << (options.meso.empty() ? "" : " --seed " + std::to_string(options.seed))
             << (options.keepRaw ? " --keep-raw" : "");
    asset.bake.settings = settings.str();
    asset.bake.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    asset.bake.date = utcNow();
    writeGdmAsset(options.output, asset, inputs);
    std::cout << "wrote " << options.output.string()
              << ": gdm.json weights.f32 eigen.f32 occupancy.u8 distance.f32"
              << (asset.albedo.empty() ? "" : " albedo.rgb8") << (options.keepRaw ? " raw.f32" : "")
              << " solid.obj\n";
}

void addGdmBakeCommand(CLI::App& gdm) {
    auto options = std::make_shared<GdmBakeOptions>();
    CLI::App* command = gdm.add_subcommand(
        "bake", "Bake a mesostructure's GDM, compress it (SVD) and write a GDM asset directory");
    command->add_option("--meso", options->meso, "A built-in mesostructure (see `strata meso --list`)");
    command->add_option("--mesh", options->mesh, "A solid mesh, OBJ in tile units (needs --height)");
    command->add_option("--vdb", options->vdb, "An OpenVDB level set in tile units (needs --height)");
    command->add_option("--height", options->height,
                        "Shell thickness H in tile widths (> 0; --meso default: the structure's own)");
    command->add_option("--size", options->size, "Voxels NXxNYxNZ")->capture_default_str();
    command->add_option("--dirs", options->dirs, "Directions NTHETAxNPHI")->capture_default_str();
    command->add_option("--rank", options->rank, "SVD rank K")->capture_default_str();
    command->add_option("--layout", options->layout, "SVD layout: xy-phi (the paper's), xyz or xy")
        ->capture_default_str();
    command->add_flag("--keep-raw", options->keepRaw, "Also write the raw GDM (raw.f32)");
    command->add_option("--seed", options->seed, "Random seed of --meso")->capture_default_str();
    command->add_option("-o,--output", options->output, "Output directory (the GDM asset)");
    command->callback([options] { runGdmBake(*options); });
}

}  // namespace

void addGdmCommand(CLI::App& app) {
    CLI::App* gdm = app.add_subcommand(
        "gdm", "Generalized displacement maps: bake an asset, trace its verification scene");
    gdm->require_subcommand(1);
    addGdmBakeCommand(*gdm);
    addGdmTraceCommand(*gdm);
}

}  // namespace strata::cli
