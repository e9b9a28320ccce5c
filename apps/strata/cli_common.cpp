#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/core/file.h"

#include <unistd.h>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <iostream>

namespace fs = std::filesystem;

namespace strata::cli {

void progress(const std::string& message) {
    if (::isatty(STDERR_FILENO)) std::cerr << "strata: " << message << "\n";
}

void warn(const std::string& message) {
    std::cerr << "strata: warning: " << message << "\n";
}

void note(const std::string& message) {
    std::cerr << "strata: note: " << message << "\n";
}

void addBitDepthOption(CLI::App& command, int& bitDepth) {
    command
        .add_option("--bit-depth", bitDepth,
                    "Bit depth of depth, normal, AO and packed PNGs (colour is always 8-bit sRGB)")
        ->check(CLI::IsMember({8, 16}))
        ->capture_default_str();
}

void reportWritten(const std::filesystem::path& dir, const std::vector<std::filesystem::path>& files) {
    std::cout << "wrote " << dir.string() << ":";
    for (const auto& file : files) std::cout << " " << file.filename().string();
    std::cout << "\n";
}

fs::path sidecarPathFor(const fs::path& output) {
    return fs::path(output.string() + ".json");
}

bool isPngName(const fs::path& path) {
    return lowerCaseExtension(path) == ".png";
}

DepthInput readDepthInput(const fs::path& path, bool height, const std::string& command) {
    std::error_code ec;
    const bool isDirectory = fs::is_directory(path, ec);
    DepthInput input;
    if (isDirectory || path.extension() == ".json") {
        if (height)
            throw Error(ErrorKind::Usage,
                        command + ": --height is for a height-map file; a texture set holds depth");
        input.set = readSidecar(path);
        const fs::path dir = isDirectory ? path : path.parent_path();
        input.setSidecar = dir / kSidecarName;
        const auto depthEntry = input.set->find("depth");
        if (depthEntry == input.set->end() || !depthEntry->is_object() || !depthEntry->contains("file") ||
            !(*depthEntry)["file"].is_string())
            throw Error(ErrorKind::InvalidInput,
                        input.setSidecar.string() + ": \"depth\" has no \"file\" string");
        input.file = dir / (*depthEntry)["file"].get<std::string>();
        input.encoding = "depth";
        input.inputs = {input.setSidecar, input.file};
        input.depth = readDepthMap(input.file, DepthEncoding::Depth);
        return input;
    }
    input.encoding = height ? "height" : "depth";
    input.file = path;
    input.inputs = {path};
    std::string readNote;
    input.depth = readDepthMap(path, height ? DepthEncoding::Height : DepthEncoding::Depth, &readNote);
    if (!readNote.empty()) note(readNote);
    return input;
}

void addDepthInputOption(CLI::App& command, fs::path& input) {
    command
        .add_option("depth", input,
                    "Depth map (0 = top), height map with --height, or a texture-set directory / strata.json")
        ->required();
}

void writeMapWithSidecar(const fs::path& output, const Image& map, const PngWriteOptions& png,
                         const nlohmann::json& sidecar) {
    const fs::path sidecarPath = sidecarPathFor(output);
    writeFileAtomic(sidecarPath, [&](const fs::path& tmp) {
        writeTextFileAtomic(tmp, sidecar.dump(2) + "\n");
        writePng(output, map, png);
    });
    std::cout << "wrote " << output.string() << " " << sidecarPath.string() << "\n";
}

}  // namespace strata::cli
