// Shared parts of the fuzz targets (docs/fuzzing.md): a per-process scratch directory for readers that take a
// path, and the rule that strata::Error is the expected outcome of bad input. Anything else that escapes a
// target (another exception, a crash, a sanitizer report, a leak) is a finding.
#pragma once

#include "strata/core/error.h"

#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace strata::fuzz {

// A directory of this process's own under the system temp directory, removed at exit.
inline const std::filesystem::path& scratchDir() {
    struct Dir {
        std::filesystem::path path;
        Dir() {
            path = std::filesystem::temp_directory_path() / ("strata_fuzz_" + std::to_string(::getpid()));
            std::filesystem::create_directories(path);
        }
        ~Dir() {
            std::error_code ignored;
            std::filesystem::remove_all(path, ignored);
        }
    };
    static const Dir dir;
    return dir.path;
}

// Writes the fuzz input to `path` (truncating it) and returns the path.
inline std::filesystem::path writeInput(const std::filesystem::path& path, const std::uint8_t* data,
                                        std::size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return path;
}

// Runs `f`; a strata::Error (bad input refused with a message) is the expected result of most inputs.
template <class F>
int expectOnlyErrors(F&& f) {
    try {
        f();
    } catch (const Error&) {
    }
    return 0;
}

// STRATA_FUZZ_SEED_OUT=DIR: copies a valid file that a target wrote into DIR as valid.json (how the
// sidecar-like corpora were seeded).
inline void exportSeed(const std::filesystem::path& valid) {
    if (const char* out = std::getenv("STRATA_FUZZ_SEED_OUT"))
        std::filesystem::copy_file(valid, std::filesystem::path(out) / "valid.json",
                                   std::filesystem::copy_options::overwrite_existing);
}

}  // namespace strata::fuzz
