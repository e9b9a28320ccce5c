#include "test_support.h"

#include "strata/core/check.h"

#include <stb/stb_image_write.h>  // implementation in libstb (linked through strata::image)

#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

namespace fs = std::filesystem;

namespace strata::test {

ScratchDir::ScratchDir(const std::string& name) {
    static std::atomic<int> counter{0};
    mPath = fs::temp_directory_path() /
            ("strata-test-" + name + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(mPath);
    fs::create_directories(mPath);
}

ScratchDir::~ScratchDir() {
    std::error_code ec;
    fs::remove_all(mPath, ec);
}

std::string bigEndian32(std::uint32_t value) {
    return {static_cast<char>(value >> 24), static_cast<char>(value >> 16), static_cast<char>(value >> 8),
            static_cast<char>(value)};
}

std::uint32_t pngCrc32(const std::string& bytes) {
    std::uint32_t crc = 0xffffffffu;
    for (const unsigned char byte : bytes) {
        crc ^= byte;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return crc ^ 0xffffffffu;
}

std::string pngChunk(const std::string& type, const std::string& data) {
    return bigEndian32(static_cast<std::uint32_t>(data.size())) + type + data +
           bigEndian32(pngCrc32(type + data));
}

std::string quoted(const std::filesystem::path& path) {
    return "\"" + path.string() + "\"";
}

CommandResult runCli(const std::string& args) {
    const std::string command = std::string("\"") + STRATA_CLI_PATH + "\" " + args + " 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    STRATA_CHECK(pipe != nullptr);
    std::string output;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe)) output += buffer.data();
    const int status = ::pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

namespace {
void appendBytes(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
}
}  // namespace

std::string noiseJpeg(int size, std::uint32_t seed) {
    std::vector<unsigned char> pixels(static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 3);
    std::uint32_t state = seed;
    for (unsigned char& p : pixels) {
        state = state * 1664525u + 1013904223u;
        p = static_cast<unsigned char>(state >> 24);
    }
    std::string out;
    stbi_write_jpg_to_func(appendBytes, &out, size, size, 3, pixels.data(), 90);
    return out;
}

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

int countEntries(const fs::path& dir) {
    if (!fs::exists(dir)) return 0;
    int n = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
    return n;
}

double maxAbsDiff(const Image& a, const Image& b) {
    STRATA_CHECK_EQ(a.width(), b.width());
    STRATA_CHECK_EQ(a.height(), b.height());
    STRATA_CHECK_EQ(a.channels(), b.channels());
    double worst = 0.0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i)
        worst = std::max(worst, static_cast<double>(std::fabs(a.pixels()[i] - b.pixels()[i])));
    return worst;
}

}  // namespace strata::test
