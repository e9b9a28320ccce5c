// Helpers shared by the test suites: scratch directories, running the CLI, writing small files.
#pragma once

#include "strata/image/image.h"

#include <cstdint>
#include <filesystem>
#include <string>

namespace strata::test {

// A fresh empty directory under the system temp dir, removed when the object goes away.
class ScratchDir {
public:
    explicit ScratchDir(const std::string& name);
    ~ScratchDir();
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    const std::filesystem::path& path() const { return mPath; }
    std::filesystem::path operator/(const std::string& name) const { return mPath / name; }

private:
    std::filesystem::path mPath;
};

struct CommandResult {
    int exitCode;
    std::string output;  // stdout and stderr together
};

// Runs the built `strata` binary with the given argument string (shell-quoted by the caller).
CommandResult runCli(const std::string& args);

// A path in double quotes, for runCli's argument string (test paths hold no quotes or dollars).
std::string quoted(const std::filesystem::path& path);

// A baseline JPEG (stb_image_write, quality 90) of `size` x `size` RGB noise from `seed`: a file whose every
// block carries data, for corrupt- and oversized-JPEG tests.
std::string noiseJpeg(int size, std::uint32_t seed);

// Hand-made PNG files for the readers' tests: the 8-byte signature, a big-endian 32-bit field, the CRC-32 of
// the PNG specification (computed bitwise here, independently of zlib) and a whole chunk (length, type, data,
// CRC of type and data).
inline const std::string kPngSignature{"\x89PNG\r\n\x1a\n", 8};
std::string bigEndian32(std::uint32_t value);
std::uint32_t pngCrc32(const std::string& bytes);
std::string pngChunk(const std::string& type, const std::string& data);

// Writes raw bytes to a file (for corrupt-file tests).
void writeBytes(const std::filesystem::path& path, const std::string& bytes);

// Number of entries in a directory (for "nothing was written" checks).
int countEntries(const std::filesystem::path& dir);

// Largest absolute difference between two images of the same shape (checked).
double maxAbsDiff(const Image& a, const Image& b);

}  // namespace strata::test
