#include "cli_common.h"

#include <unistd.h>
#include <cstdio>
#include <iostream>

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

}  // namespace strata::cli
