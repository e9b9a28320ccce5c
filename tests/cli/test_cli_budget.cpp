// The memory budget (docs/images.md, docs/cli.md --max-memory) and corrupt data in readers: a tiny hostile
// file or a large --size is refused before it costs memory, and corrupt data is an error, not a picture.
// Each case runs the built `strata`, reads the child's peak resident set from wait4()'s rusage, and
// asserts the exit code, the message and that peak.
#include "test_support.h"

#include "strata/image/image_io.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic pop

namespace strata {
namespace {

namespace fs = std::filesystem;

constexpr long kMiBInKiB = 1024;

struct Measured {
    int exitCode = -1;
    long peakKiB = -1;   // ru_maxrss of the child (KiB on Linux)
    std::string output;  // stdout and stderr together
};

// fork + exec rather than posix_spawn: a vfork-style spawn shares this process's memory map until exec,
// and Linux carries that map's high-water mark into the child's ru_maxrss, so the child would report this
// test process's peak. A forked child starts from this process's current resident set instead (small:
// the fixtures' images are freed before the run).
Measured runMeasured(const std::vector<std::string>& args, const fs::path& scratch) {
    const std::string log = (scratch / "output.txt").string();
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(STRATA_CLI_PATH));
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    Measured result;
    const pid_t pid = fork();
    if (pid < 0) return result;
    if (pid == 0) {
        // Only async-signal-safe calls between fork and exec.
        const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0 || dup2(fd, 1) < 0 || dup2(fd, 2) < 0) _exit(126);
        execv(STRATA_CLI_PATH, argv.data());
        _exit(127);
    }
    int status = 0;
    rusage usage{};
    if (wait4(pid, &status, 0, &usage) != pid) return result;
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.peakKiB = usage.ru_maxrss;
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    result.output = text.str();
    return result;
}

// What the process costs anyway: the `strata` binary with its libraries (TBB, OpenVDB, Embree) running
// `info` on a 1x1 PNG. A release build peaks at about 37 MiB; a sanitizer build at several times that
// (ASan's shadow memory and allocator), so the baseline is measured, once, with the binary under test.
long baselineKiB() {
    static const long baseline = [] {
        test::ScratchDir dir("budget-baseline");
        writePng(dir / "one.png", Image(1, 1, 1, 0.5f));
        const Measured run = runMeasured({"info", (dir / "one.png").string()}, dir.path());
        EXPECT_EQ(run.exitCode, 0) << run.output;
        std::printf("baseline: peak %ld KiB\n", run.peakKiB);
        return run.peakKiB;
    }();
    return baseline;
}

// A refused input must cost what the process costs anyway: 64 MiB above the baseline is room for the
// small images a command holds before it reads the hostile file, and far below the gigabytes each hostile
// file cost before.
long peakLimitKiB() {
    return baselineKiB() + 64 * kMiBInKiB;
}

void expectRefused(const Measured& result, int exitCode, const std::string& message) {
    EXPECT_EQ(result.exitCode, exitCode) << result.output;
    EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
    EXPECT_GT(result.peakKiB, 0);
    EXPECT_LT(result.peakKiB, peakLimitKiB()) << result.output;
    ::testing::Test::RecordProperty("peak_kib", std::to_string(result.peakKiB));
    std::printf("peak %ld KiB, exit %d: %s", result.peakKiB, result.exitCode, result.output.c_str());
}

using test::bigEndian32;
using test::kPngSignature;
using test::pngChunk;

// 65 bytes: signature, an IHDR of 16384 x 16384 RGBA 16-bit with a valid CRC, an IDAT holding an empty
// zlib stream, IEND.
std::string hostilePng() {
    const std::string ihdr = bigEndian32(16384) + bigEndian32(16384) + std::string{16, 6, 0, 0, 0};
    return kPngSignature + pngChunk("IHDR", ihdr) +
           pngChunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) + pngChunk("IEND", "");
}

// A width x height 8-bit PNG of `channels` (1 = grey, 3 = RGB) whose every sample is `value`, deflated
// row by row so that a 16384^2 map never exists in this process (zlib's default level: about 1000:1
// on constant rows).
void writeConstantPng(const fs::path& path, int width, int height, int channels, unsigned char value) {
    const std::string ihdr = bigEndian32(static_cast<std::uint32_t>(width)) +
                             bigEndian32(static_cast<std::uint32_t>(height)) +
                             std::string{8, static_cast<char>(channels == 3 ? 2 : 0), 0, 0, 0};
    std::vector<unsigned char> row(1 + static_cast<std::size_t>(width) * static_cast<std::size_t>(channels),
                                   value);
    row[0] = 0;  // filter type None
    z_stream z{};
    ASSERT_EQ(deflateInit(&z, Z_DEFAULT_COMPRESSION), Z_OK);
    std::string idat;
    std::vector<unsigned char> out(1 << 16);
    for (int y = 0; y <= height; ++y) {
        const bool last = y == height;
        z.next_in = last ? nullptr : row.data();
        z.avail_in = last ? 0u : static_cast<unsigned>(row.size());
        int status = Z_OK;
        do {
            z.next_out = out.data();
            z.avail_out = static_cast<unsigned>(out.size());
            status = deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
            idat.append(reinterpret_cast<const char*>(out.data()), out.size() - z.avail_out);
        } while (z.avail_out == 0 || (last && status != Z_STREAM_END));
    }
    deflateEnd(&z);
    test::writeBytes(path,
                     kPngSignature + pngChunk("IHDR", ihdr) + pngChunk("IDAT", idat) + pngChunk("IEND", ""));
}

TEST(CliBudget, APngHeaderClaiming16384SquaredRgba16IsRefusedBeforeDecoding) {
    test::ScratchDir dir("budget-png");
    const std::string bytes = hostilePng();
    ASSERT_EQ(bytes.size(), 65u);
    test::writeBytes(dir / "big.png", bytes);
    // rows of 16384 * 8 bytes plus a filter byte, 16384 rows: 2.00 GiB that 69 bytes cannot hold.
    expectRefused(runMeasured({"info", (dir / "big.png").string()}, dir.path()), 3,
                  "strata: error: " + (dir / "big.png").string() +
                      ": truncated PNG: the header declares 16384 x 16384 (2.00 GiB of image data), more "
                      "than a 65-byte file can hold");
    expectRefused(
        runMeasured({"import", "--height", (dir / "big.png").string(), "-o", (dir / "set").string()},
                    dir.path()),
        3, ": truncated PNG: the header declares 16384 x 16384");
    EXPECT_FALSE(fs::exists(dir / "set"));
}

TEST(CliBudget, AJpegHeaderClaiming16000SquaredIsRefusedBeforeDecoding) {
    test::ScratchDir dir("budget-jpeg");
    std::string bytes = test::noiseJpeg(96, 12345u);
    // Patch the baseline frame header (FF C0, length, precision, height, width) to 16000 x 16000.
    const std::size_t sof = bytes.find("\xff\xc0", 0, 2);
    ASSERT_NE(sof, std::string::npos);
    bytes[sof + 5] = bytes[sof + 7] = static_cast<char>(16000 >> 8);
    bytes[sof + 6] = bytes[sof + 8] = static_cast<char>(16000 & 0xff);
    test::writeBytes(dir / "big.jpg", bytes);
    // 2000 x 2000 blocks, at least one bit each: 500000 bytes, and the file is a few KB.
    expectRefused(runMeasured({"info", (dir / "big.jpg").string()}, dir.path()), 3,
                  "strata: error: " + (dir / "big.jpg").string() +
                      ": truncated JPEG: the header declares 16000 x 16000, which needs at least 500000 "
                      "bytes of data; the file has " +
                      std::to_string(bytes.size()));
}

TEST(CliBudget, ATruncatedJpegWithAnEndMarkerAppendedIsCorrupt) {
    test::ScratchDir dir("budget-jpeg-cut");
    const std::string full = test::noiseJpeg(64, 12345u);
    test::writeBytes(dir / "ok.jpg", full);
    ASSERT_EQ(runMeasured({"info", (dir / "ok.jpg").string()}, dir.path()).exitCode, 0);
    // Half the entropy-coded data, then FF D9: stb_image read this as an image with a flat lower half.
    test::writeBytes(dir / "cut.jpg", full.substr(0, full.size() / 2) + "\xff\xd9");
    expectRefused(runMeasured({"info", (dir / "cut.jpg").string()}, dir.path()), 3,
                  "strata: error: " + (dir / "cut.jpg").string() +
                      ": corrupt or truncated JPEG: Corrupt JPEG data: premature end of data segment");
}

TEST(CliBudget, AGltfAccessorOf400MillionElementsIsRefusedBeforeAllocating) {
    test::ScratchDir dir("budget-gltf");
    // Positions without a buffer view are all zeros by the glTF spec: any count in a few bytes of JSON.
    const std::string header = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0,
 "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],)";
    const std::string gltf = header + R"(
 "accessors": [{"componentType": 5126, "count": 400000000, "type": "VEC3",
                "min": [0, 0, 0], "max": [0, 0, 0]}]})";
    test::writeBytes(dir / "huge.gltf", gltf);
    ASSERT_LT(gltf.size(), 800u);
    expectRefused(
        runMeasured({"dual-depth", "--mesh", (dir / "huge.gltf").string(), "-o", (dir / "out").string()},
                    dir.path()),
        3,
        "strata: error: " + (dir / "huge.gltf").string() +
            ": POSITION accessor 0 of 400000000 elements has no buffer view (every position would be 0)");
    EXPECT_FALSE(fs::exists(dir / "out"));
    // The same count over a 12-byte buffer: refused by the budget (or, within it, as running past the
    // buffer). --max-memory makes the case independent of this machine's memory.
    test::writeBytes(dir / "view.gltf", header + R"(
 "buffers": [{"byteLength": 12, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}],
 "bufferViews": [{"buffer": 0, "byteLength": 12}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 400000000, "type": "VEC3",
                "min": [0, 0, 0], "max": [0, 0, 0]}]})");
    // 400 M x (12 bytes of floats + a 48-byte vertex + 2 bytes of flags) = 23.10 GiB.
    expectRefused(
        runMeasured({"--max-memory", "1G", "dual-depth", "--mesh", (dir / "view.gltf").string(), "-o",
                     (dir / "out").string()},
                    dir.path()),
        5,
        "strata: error: " + (dir / "view.gltf").string() +
            ": POSITION accessor 0 of 400000000 elements needs 23.10 GiB, more than the memory budget "
            "of 1.00 GiB (--max-memory)");
    expectRefused(
        runMeasured({"--max-memory", "64G", "dual-depth", "--mesh", (dir / "view.gltf").string(), "-o",
                     (dir / "out").string()},
                    dir.path()),
        3, "strata: error: " + (dir / "view.gltf").string() + ": POSITION accessor 0 runs past its buffer");
    EXPECT_FALSE(fs::exists(dir / "out"));
}

// A valid 2048^2 normal map (48 MiB of floats once read) after its 2048^2 depth map (16 MiB): refused
// before it is decoded when it does not fit alone (32 MiB), and when it fits alone but not with the
// depth map held (56 MiB): the budget bounds every image the process holds at once.
TEST(CliBudget, ANormalMapIsRefusedAloneOrWithTheImagesAlreadyHeld) {
    test::ScratchDir dir("budget-normal");
    writeConstantPng(dir / "n.png", 2048, 2048, 3, 0);
    writeConstantPng(dir / "d.png", 2048, 2048, 1, 128);
    for (const std::string& budget : {std::string("32M"), std::string("56M")}) {
        expectRefused(
            runMeasured({"--max-memory", budget, "import", "--depth", (dir / "d.png").string(), "--normal",
                         (dir / "n.png").string(), "-o", (dir / "set").string()},
                        dir.path()),
            5,
            "strata: error: " + (dir / "n.png").string() +
                ": a 2048 x 2048 PNG of 3 channels needs 48 MiB; with 16 MiB of images already held, "
                "that is more than the memory budget of " +
                budget.substr(0, 2) + " MiB (--max-memory)");
        EXPECT_FALSE(fs::exists(dir / "set"));
    }
}

// The issue's case: an all-zero 16384^2 normal map cost 9.4 GB. Next to its 16384^2 depth map (1 GiB of
// floats) its 3 GiB do not fit a 3.5 GiB budget, and the process stops holding the depth map alone: the
// measured peak is the depth map plus the ~40 MiB every run costs, far under the budget.
TEST(CliBudget, AnAllZero16384SquaredNormalMapStaysUnderTheBudget) {
    test::ScratchDir dir("budget-zero-normal");
    writeConstantPng(dir / "n.png", 16384, 16384, 3, 0);
    writeConstantPng(dir / "d.png", 16384, 16384, 1, 128);
    const Measured result =
        runMeasured({"--max-memory", "3584M", "import", "--depth", (dir / "d.png").string(), "--normal",
                     (dir / "n.png").string(), "-o", (dir / "set").string()},
                    dir.path());
    EXPECT_EQ(result.exitCode, 5) << result.output;
    EXPECT_NE(
        result.output.find("strata: error: " + (dir / "n.png").string() +
                           ": a 16384 x 16384 PNG of 3 channels needs 3.00 GiB; with 1.00 GiB of images "
                           "already held, that is more than the memory budget of 3.50 GiB (--max-memory)"),
        std::string::npos)
        << result.output;
    // The depth map's 1 GiB, and an eighth more for ASan's shadow of it in a sanitizer build.
    EXPECT_LT(result.peakKiB, peakLimitKiB() + 1024 * kMiBInKiB * 9 / 8) << result.output;
    EXPECT_GT(result.peakKiB, 1024 * kMiBInKiB) << "the depth map was read: " << result.output;
    EXPECT_FALSE(fs::exists(dir / "set"));
    std::printf("peak %ld KiB: %s", result.peakKiB, result.output.c_str());
}

TEST(CliBudget, ASizeFlagOverTheBudgetIsRefusedBeforeAllocating) {
    test::ScratchDir dir("budget-size");
    // 4096^2 floats of one channel: 64 MiB, over a 16 MiB budget.
    expectRefused(
        runMeasured({"--max-memory", "16M", "pattern", "base", "--size", "4096", "-o", (dir / "p").string()},
                    dir.path()),
        5,
        "strata: error: a 4096 x 4096 image of 1 channel needs 64 MiB, more than the memory budget of 16 MiB "
        "(--max-memory)");
    EXPECT_FALSE(fs::exists(dir / "p"));
    // The same command within the budget works, and the meter sees what the child allocates: a 2048^2 set
    // holds several 16 MiB float maps at once, over 100 MiB above the baseline.
    const Measured within = runMeasured(
        {"--max-memory", "4G", "pattern", "base", "--size", "2048", "-o", (dir / "q").string()}, dir.path());
    EXPECT_EQ(within.exitCode, 0) << within.output;
    EXPECT_GT(within.peakKiB, baselineKiB() + 100 * kMiBInKiB) << within.output;
    std::printf("within the budget: peak %ld KiB\n", within.peakKiB);
}

TEST(CliBudget, AMalformedMaxMemoryIsAUsageError) {
    test::ScratchDir dir("budget-flag");
    for (const std::string bad : {"12X", "0", "-5", "G", "99999999999T"}) {
        const Measured result = runMeasured({"--max-memory", bad, "pattern", "--list"}, dir.path());
        EXPECT_EQ(result.exitCode, 1) << bad << "\n" << result.output;
        EXPECT_NE(result.output.find("strata: error: --max-memory '" + bad + "': "), std::string::npos)
            << result.output;
    }
    EXPECT_EQ(runMeasured({"--max-memory", "512MiB", "pattern", "--list"}, dir.path()).exitCode, 0);
}

}  // namespace
}  // namespace strata
