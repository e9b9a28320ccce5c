// Readers against the memory budget, and corrupt data that is an error rather than a picture
// (docs/images.md).
#include "strata/core/error.h"
#include "strata/core/memory_budget.h"
#include "strata/image/image_io.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
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
using test::ScratchDir;

std::string readError(const fs::path& path, ErrorKind* kind) {
    try {
        readImage(path);
    } catch (const Error& e) {
        *kind = e.kind();
        return e.what();
    }
    return "no error";
}

class ReaderBudget : public ::testing::Test {
protected:
    void TearDown() override { setMemoryBudget(mSaved); }
    std::uint64_t mSaved = memoryBudget();
};

TEST_F(ReaderBudget, EveryFormatIsCheckedBeforeDecoding) {
    ScratchDir dir("reader-budget");
    const Image gray(256, 128, 1, 0.25f);
    writePng(dir / "g.png", gray);
    writeExr(dir / "g.exr", gray);
    // 256 x 128 floats = 128 KiB, plus the decoder's buffers: over a 100 KiB budget for every reader.
    setMemoryBudget(100 * 1024);
    for (const char* name : {"g.png", "g.exr"}) {
        ErrorKind kind = ErrorKind::Runtime;
        const std::string message = readError(dir / name, &kind);
        EXPECT_EQ(kind, ErrorKind::Unsupported) << message;
        EXPECT_EQ(message.rfind((dir / name).string() + ": a 256 x 128 ", 0), 0u) << message;
        EXPECT_NE(message.find(" of 1 channel needs "), std::string::npos) << message;
        EXPECT_NE(message.find("more than the memory budget of 102400 bytes (--max-memory)"),
                  std::string::npos)
            << message;
    }
    // The header alone allocates nothing proportional to the image and stays readable.
    EXPECT_EQ(readImageInfo(dir / "g.png").width, 256);
    setMemoryBudget(mSaved);
    EXPECT_EQ(readImage(dir / "g.png").width(), 256);
}

TEST_F(ReaderBudget, ImagesMadeFromFlagsAreCheckedToo) {
    setMemoryBudget(std::uint64_t{1} << 20);
    try {
        Image big(1024, 1024, 1);
        ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Unsupported);
        EXPECT_STREQ(e.what(),
                     "a 1024 x 1024 image of 1 channel needs 4 MiB, more than the memory budget of 1 MiB "
                     "(--max-memory)");
    }
    EXPECT_EQ(Image(512, 512, 1).width(), 512);  // exactly 1 MiB: within
}

TEST(ExrFiniteValues, NanAndInfinityAreErrorsNamingTheFirstTexel) {
    ScratchDir dir("exr-nan");
    Image normals(8, 4, 3, 0.5f);
    normals.at(5, 2, 1) = std::numeric_limits<float>::quiet_NaN();
    normals.at(6, 3, 0) = std::numeric_limits<float>::infinity();
    writeExr(dir / "n.exr", normals);
    ErrorKind kind = ErrorKind::Runtime;
    EXPECT_EQ(
        readError(dir / "n.exr", &kind),
        (dir / "n.exr").string() +
            ": EXR channel G holds nan at column 5, row 2 (row 0 is the top); only finite values are read");
    EXPECT_EQ(kind, ErrorKind::InvalidInput);
    Image depth(4, 4, 1, 0.1f);
    depth.at(0, 3) = -std::numeric_limits<float>::infinity();
    writeExr(dir / "d.exr", depth);
    EXPECT_EQ(
        readError(dir / "d.exr", &kind),
        (dir / "d.exr").string() +
            ": EXR channel Y holds -inf at column 0, row 3 (row 0 is the top); only finite values are read");
}

TEST(JpegCorruptData, ACutFileWithAnEndMarkerAppendedIsAnError) {
    ScratchDir dir("jpeg-cut-eoi");
    const std::string full = test::noiseJpeg(64, 7u);
    test::writeBytes(dir / "ok.jpg", full);
    const Image ok = readImage(dir / "ok.jpg");
    EXPECT_EQ(ok.width(), 64);
    EXPECT_EQ(ok.channels(), 3);
    for (const std::size_t keep : {full.size() / 2, full.size() - 40}) {
        test::writeBytes(dir / "cut.jpg", full.substr(0, keep) + "\xff\xd9");
        ErrorKind kind = ErrorKind::Runtime;
        EXPECT_EQ(readError(dir / "cut.jpg", &kind),
                  (dir / "cut.jpg").string() +
                      ": corrupt or truncated JPEG: Corrupt JPEG data: premature end of data segment")
            << keep;
        EXPECT_EQ(kind, ErrorKind::InvalidInput);
    }
}

TEST(JpegCorruptData, AHeaderClaimingMoreThanTheFileCanHoldIsRefused) {
    ScratchDir dir("jpeg-big");
    std::string bytes = test::noiseJpeg(16, 7u);
    const std::size_t sof = bytes.find("\xff\xc0", 0, 2);
    ASSERT_NE(sof, std::string::npos);
    bytes[sof + 5] = bytes[sof + 7] = static_cast<char>(16000 >> 8);
    bytes[sof + 6] = bytes[sof + 8] = static_cast<char>(16000 & 0xff);
    test::writeBytes(dir / "big.jpg", bytes);
    ErrorKind kind = ErrorKind::Runtime;
    EXPECT_EQ(readError(dir / "big.jpg", &kind),
              (dir / "big.jpg").string() +
                  ": truncated JPEG: the header declares 16000 x 16000, which needs at least 500000 bytes of "
                  "data; the file has " +
                  std::to_string(bytes.size()));
    EXPECT_EQ(kind, ErrorKind::InvalidInput);
}

// The fuzzer's finding: a few bytes of run-length coded TGA claiming 12346 x 10752 decoded (1.3 GB) before
// they ran out. A packet repeats at most 128 pixels, so such a header is refused by the file's size alone.
TEST(RunLengthData, ATgaHeaderClaimingMoreThanItsPacketsCanHoldIsRefused) {
    test::ScratchDir dir("rle-tga");
    std::string tga(18, '\0');
    tga[2] = 10;  // run-length coded true colour
    tga[12] = static_cast<char>(12346 & 0xff);
    tga[13] = static_cast<char>(12346 >> 8);
    tga[14] = static_cast<char>(10752 & 0xff);
    tga[15] = static_cast<char>(10752 >> 8);
    tga[16] = 24;
    tga += std::string("\xff\x10\x20\x30", 4) + std::string(14, '\0');  // one packet of 128 pixels, and junk
    test::writeBytes(dir / "big.tga", tga);
    ErrorKind kind = ErrorKind::Runtime;
    EXPECT_EQ(
        readError(dir / "big.tga", &kind),
        (dir / "big.tga").string() +
            ": truncated TGA data: the header declares 12346 x 10752, more than its 36-byte file can hold "
            "even run-length coded");
    EXPECT_EQ(kind, ErrorKind::InvalidInput);
    // A small run-length coded TGA whose packets do cover it still reads: 2 x 1, one packet of 2 pixels.
    std::string small(18, '\0');
    small[2] = 10;
    small[12] = 2;
    small[14] = 1;
    small[16] = 24;
    small += std::string("\x81\x10\x20\x30", 4);
    test::writeBytes(dir / "small.tga", small);
    const Image image = readImage(dir / "small.tga");
    EXPECT_EQ(image.width(), 2);
    EXPECT_NEAR(image.at(1, 0, 2), 0x10 / 255.0, 1e-6);  // TGA stores BGR: blue 0x10
}

}  // namespace
}  // namespace strata
