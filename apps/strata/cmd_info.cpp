// strata info PATH [--json]
// PATH: a texture-set directory, its strata.json sidecar, a GDM asset directory, or a single image file.
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/gdm/gdm_asset.h"
#include "strata/image/image_io.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata::cli {

namespace {

struct InfoOptions {
    fs::path path;
    bool json = false;
};

json imageJson(const fs::path& file) {
    const ImageInfo info = readImageInfo(file);
    // The header alone says nothing of the data: decode it all, so that a truncated or corrupt file is
    // reported as such (exit 3) instead of described.
    (void)readImage(file);
    return {{"file", file.string()}, {"format", toString(info.format)}, {"width", info.width},
            {"height", info.height}, {"channels", info.channels},       {"bit_depth", info.bitDepth}};
}

std::string sizeText(const json& size) {
    if (!size.is_array() || size.size() != 2) return "?";
    return std::to_string(size[0].get<int>()) + "x" + std::to_string(size[1].get<int>());
}

void printSet(const fs::path& path, const json& sidecar) {
    std::cout << path.string() << ": Strata texture set (" << sidecar.value("tool", "?") << ")\n";
    std::cout << "  depth scale S : " << sidecar.value("depth_scale", 0.0) << " tile widths\n";
    std::cout << "  bit depth     : " << sidecar.value("bit_depth", 0) << " ("
              << sidecar.value("file_format", "png") << ")\n";
    for (const char* key : {"depth", "height", "normal", "color", "ao", "packed"}) {
        const auto it = sidecar.find(key);
        if (std::string(key) == "height" && it == sidecar.end()) continue;  // only with --write-height
        std::cout << "  " << key << std::string(14 - std::string(key).size(), ' ') << ": ";
        if (it == sidecar.end() || it->is_null()) {
            std::cout << "none\n";
            continue;
        }
        std::cout << it->value("file", "?") << " " << sizeText(it->value("size", json()));
        if (std::string(key) == "normal")
            std::cout << ", " << it->value("convention", "?") << " (green " << it->value("green", "?")
                      << "), from " << it->value("source", "?");
        if (std::string(key) == "height")
            std::cout << ", white = high, amplitude " << it->value("amplitude", 0.0);
        if (std::string(key) == "ao")
            std::cout << ", R = " << it->value("radius", 0.0) << ", " << it->value("method", "?");
        if (std::string(key) == "packed") std::cout << ", B channel: " << it->value("ao_channel", "?");
        std::cout << "\n";
    }
    if (sidecar.contains("source")) std::cout << "  source        : " << sidecar["source"].dump() << "\n";
}

std::string mib(std::size_t bytes) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(2) << double(bytes) / double(1 << 20) << " MiB";
    return text.str();
}

// A GDM asset: read in full, so that `info` also says whether it is valid.
void printGdm(const fs::path& dir, bool asJson) {
    const GdmAsset asset = readGdmAsset(dir);
    if (asJson) {
        std::ifstream in(dir / kGdmAssetSidecar);
        std::cout << in.rdbuf();
        return;
    }
    const GdmSvd& svd = asset.svd;
    const GdmDims& d = svd.dims;
    std::cout << dir.string() << ": Strata GDM asset (version " << kGdmAssetVersion << ")\n";
    std::cout << "  dims          : " << d.nx << "x" << d.ny << "x" << d.nz << " voxels, " << d.ntheta << "x"
              << d.nphi << " directions\n";
    std::cout << "  height H      : " << svd.height << " tile widths\n";
    std::cout << "  rank          : " << svd.rank << ", layout " << toString(svd.layout) << " (" << svd.rows
              << " x " << svd.cols << "), exit tolerance " << svd.exitTolerance << "\n";
    std::cout << "  source        : " << asset.source << "\n";
    std::cout << "  bake          : " << asset.bake.settings << ", " << asset.bake.seconds << " s, "
              << asset.bake.date << "\n";
    const std::size_t raw = asset.raw ? asset.raw->values.size() * sizeof(float) : 0;
    std::cout << "  weights.f32   : " << svd.weights.size() * sizeof(float) << " bytes\n";
    std::cout << "  eigen.f32     : " << svd.eigen.size() * sizeof(float) << " bytes\n";
    std::cout << "  occupancy.u8  : " << asset.occupancy.size() << " bytes\n";
    std::cout << "  albedo.rgb8   : "
              << (asset.albedo.empty() ? std::string("none") : std::to_string(asset.albedo.size()) + " bytes")
              << "\n";
    std::cout << "  distance.f32  : "
              << (asset.distance.empty()
                      ? std::string("none (bake again for `--technique refine` on the distance)")
                      : std::to_string(asset.distance.size() * sizeof(float)) + " bytes")
              << "\n";
    std::cout << "  raw.f32       : " << (asset.raw ? std::to_string(raw) + " bytes" : std::string("none"))
              << "\n";
    std::cout << "  solid.obj     : "
              << (asset.solid ? std::to_string(asset.solid->triangles.size()) + " triangles, " +
                                    std::to_string(asset.solid->positions.size()) + " vertices"
                              : std::string("none (bake again for `strata gdm trace --reference`)"))
              << "\n";
    std::cout << "  memory        : " << mib(svd.mapBytes()) << " maps, " << mib(asset.occupancy.size())
              << " occupancy, raw GDM " << mib(d.valueCount() * sizeof(float)) << "\n";
}

void runInfo(const InfoOptions& options) {
    std::error_code ec;
    if (!fs::exists(options.path, ec))
        throw Error(ErrorKind::Io, options.path.string() + ": no such file or directory");
    if (fs::is_directory(options.path, ec) && isGdmAsset(options.path)) {
        printGdm(options.path, options.json);
        return;
    }
    const bool isSet = fs::is_directory(options.path, ec) || options.path.extension() == ".json";
    if (!isSet) {
        const json info = imageJson(options.path);
        if (options.json) {
            std::cout << info.dump(2) << "\n";
        } else {
            std::cout << options.path.string() << ": " << info["format"].get<std::string>() << " "
                      << info["width"] << "x" << info["height"] << ", " << info["channels"] << " channel(s), "
                      << info["bit_depth"] << "-bit\n";
        }
        return;
    }
    const json sidecar = readSidecar(options.path);
    if (options.json) {
        std::cout << sidecar.dump(2) << "\n";
    } else {
        printSet(options.path, sidecar);
    }
}

}  // namespace

void addInfoCommand(CLI::App& app) {
    auto options = std::make_shared<InfoOptions>();
    CLI::App* command =
        app.add_subcommand("info", "Describe a texture set, its sidecar, a GDM asset, or an image file");
    command
        ->add_option("path", options->path,
                     "Texture-set directory, strata.json, GDM asset directory, or image")
        ->required();
    command->add_flag("--json", options->json, "Print JSON (the sidecar, or the image header)");
    command->callback([options] { runInfo(*options); });
}

}  // namespace strata::cli
