// strata info PATH [--json]
// PATH: a texture-set directory, its strata.json sidecar, or a single image file.
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

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
    std::cout << "  bit depth     : " << sidecar.value("bit_depth", 0) << "\n";
    for (const char* key : {"depth", "normal", "color", "ao", "packed"}) {
        const auto it = sidecar.find(key);
        std::cout << "  " << key << std::string(14 - std::string(key).size(), ' ') << ": ";
        if (it == sidecar.end() || it->is_null()) {
            std::cout << "none\n";
            continue;
        }
        std::cout << it->value("file", "?") << " " << sizeText(it->value("size", json()));
        if (std::string(key) == "normal")
            std::cout << ", " << it->value("convention", "?") << " (green " << it->value("green", "?")
                      << "), from " << it->value("source", "?");
        if (std::string(key) == "ao")
            std::cout << ", R = " << it->value("radius", 0.0) << ", " << it->value("method", "?");
        if (std::string(key) == "packed") std::cout << ", B channel: " << it->value("ao_channel", "?");
        std::cout << "\n";
    }
    if (sidecar.contains("source")) std::cout << "  source        : " << sidecar["source"].dump() << "\n";
}

void runInfo(const InfoOptions& options) {
    std::error_code ec;
    if (!fs::exists(options.path, ec))
        throw Error(ErrorKind::Io, options.path.string() + ": no such file or directory");
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
    CLI::App* command = app.add_subcommand("info", "Describe a texture set, its sidecar, or an image file");
    command->add_option("path", options->path, "Texture-set directory, strata.json, or image")->required();
    command->add_flag("--json", options->json, "Print JSON (the sidecar, or the image header)");
    command->callback([options] { runInfo(*options); });
}

}  // namespace strata::cli
