#include "cli_common.h"

#include "strata/relief/relief_texture.h"

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

void addSetOutputOptions(CLI::App& command, SetOutputOptions& options) {
    command
        .add_option("--bit-depth", options.bitDepth,
                    "Bit depth of depth, normal, AO and packed PNGs (colour is always 8-bit sRGB)")
        ->check(CLI::IsMember({8, 16}))
        ->each([&options](const std::string&) { options.bitDepthGiven = true; })
        ->capture_default_str();
    command
        .add_option("--format", options.format,
                    "File format of depth, normal, AO and packed maps: png, or exr (32-bit float); colour "
                    "stays an 8-bit sRGB PNG")
        ->check(CLI::IsMember({"png", "exr"}))
        ->capture_default_str();
    command.add_flag("--write-height", options.height,
                     "Also write the height map h = 1 - depth (white = high) beside the depth map");
    // Checked as soon as the command line is parsed, before the set is computed.
    command.parse_complete_callback([&options] {
        if (options.format == "exr" && options.bitDepthGiven)
            throw Error(ErrorKind::Usage,
                        "--bit-depth applies to PNG maps; --format exr writes 32-bit float");
    });
}

void applySetOutputOptions(const SetOutputOptions& options, TextureSetWriteOptions& write) {
    write.format = parseMapFileFormat(options.format);
    write.bitDepth = options.bitDepth;
    write.height = options.height;
}

CLI::Validator depthScaleRange() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            double value = 0.0;
            try {
                std::size_t used = 0;
                value = std::stod(text, &used);
                if (used != text.size()) return "must be a number in (0, 10], got '" + text + "'";
            } catch (const std::exception&) {
                return "must be a number in (0, 10], got '" + text + "'";
            }
            if (!(value > 0.0 && value <= kMaxReliefDepthScale)) return "must be in (0, 10], got " + text;
            return {};
        },
        "(0, 10]");
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

std::vector<int> parseSizeList(const std::string& text, std::size_t count, const std::string& flag,
                               const std::string& example) {
    std::vector<int> sizes;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find_first_of("xX", start);
        const std::string part =
            text.substr(start, end == std::string::npos ? std::string::npos : end - start);
        if (part.empty() || part.size() > 9 ||
            !std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; }))
            break;
        sizes.push_back(std::stoi(part));
        if (end == std::string::npos) {
            if (sizes.size() == count) return sizes;
            break;
        }
        start = end + 1;
    }
    throw Error(ErrorKind::Usage, flag + ": expected " + example + ", got '" + text + "'");
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
