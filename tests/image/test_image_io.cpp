// Image file I/O: round trips with exact expectations, the third-party formats, and every failure kind.
#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/image/image_io.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wconversion"
#include <stb/stb_image.h>        // an independent reader, to check what the writer stored
#include <stb/stb_image_write.h>  // implementation in libstb; used here only to make fixtures
#pragma GCC diagnostic pop

namespace fs = std::filesystem;

namespace strata {
namespace {

using test::ScratchDir;

// ---- helpers ------------------------------------------------------------------------------------------

// A deterministic pattern that visits many quantisation levels and differs per channel.
Image pattern(int width, int height, int channels) {
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                image.at(x, y, c) =
                    static_cast<float>(std::fmod(0.137 * x + 0.291 * y + 0.173 * c + 0.05, 1.0));
    return image;
}

double mean(const Image& image, int c = 0) {
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) sum += static_cast<double>(image.at(x, y, c));
    return sum / static_cast<double>(image.texelCount());
}

std::string readAll(const fs::path& path) {
    const auto bytes = readFileBytes(path);
    return std::string(bytes.begin(), bytes.end());
}

using test::bigEndian32;
using test::kPngSignature;
using test::pngChunk;
using test::pngCrc32;

// A zlib stream of stored (uncompressed) deflate blocks: enough to hand-make any PNG.
std::string zlibStored(const std::string& raw) {
    std::string out = "\x78\x01";
    std::size_t at = 0;
    do {
        const std::size_t n = std::min<std::size_t>(raw.size() - at, 65535);
        const bool last = at + n == raw.size();
        out += static_cast<char>(last ? 1 : 0);
        out += static_cast<char>(n & 0xff);
        out += static_cast<char>(n >> 8);
        out += static_cast<char>(~n & 0xff);
        out += static_cast<char>((~n >> 8) & 0xff);
        out += raw.substr(at, n);
        at += n;
    } while (at < raw.size());
    std::uint32_t a = 1, b = 0;
    for (unsigned char c : raw) {
        a = (a + c) % 65521;
        b = (b + a) % 65521;
    }
    return out + bigEndian32(b << 16 | a);
}

// A PNG from its IHDR fields, optional extra chunks before IDAT, and raw scanlines (filter byte included).
std::string makePng(std::uint32_t width, std::uint32_t height, int bitDepth, int colorType,
                    const std::string& scanlines, const std::string& extraChunks = "") {
    const std::string ihdr = bigEndian32(width) + bigEndian32(height) + static_cast<char>(bitDepth) +
                             static_cast<char>(colorType) + std::string(3, '\0');
    return kPngSignature + pngChunk("IHDR", ihdr) + extraChunks + pngChunk("IDAT", zlibStored(scanlines)) +
           pngChunk("IEND", "");
}

template <typename F>
void expectError(F&& f, ErrorKind kind, const fs::path& path, const std::string& fragment = "") {
    try {
        f();
        ADD_FAILURE() << "no error thrown for " << path;
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(path.string(), 0), 0u) << "message does not start with the path: " << message;
        if (!fragment.empty()) {
            EXPECT_NE(message.find(fragment), std::string::npos) << message;
        }
    }
}

void expectReadError(const fs::path& path, ErrorKind kind, const std::string& fragment = "") {
    expectError([&] { readImageInfo(path); }, kind, path, fragment);
    expectError([&] { readImage(path); }, kind, path, fragment);
}

// ---- PNG round trips ----------------------------------------------------------------------------------

class PngRoundTrip : public ::testing::TestWithParam<int> {};

TEST_P(PngRoundTrip, SixteenBitIsExactToHalfAStep) {
    ScratchDir dir("png16");
    const int channels = GetParam();
    const Image source = pattern(13, 7, channels);
    writePng(dir / "a.png", source);
    const ImageInfo info = readImageInfo(dir / "a.png");
    EXPECT_EQ(info.format, ImageFormat::Png);
    EXPECT_EQ(info.width, 13);
    EXPECT_EQ(info.height, 7);
    EXPECT_EQ(info.channels, channels);
    EXPECT_EQ(info.bitDepth, 16);
    const Image back = readImage(dir / "a.png");
    ASSERT_EQ(back.channels(), channels);
    // round(v * 65535) is within half a step of v; plus float rounding of the value itself.
    EXPECT_LE(test::maxAbsDiff(source, back), 0.5 / 65535.0 + 1e-7);
    // A value that is already a 16-bit level survives bit for bit.
    writePng(dir / "b.png", back);
    EXPECT_EQ(readImage(dir / "b.png"), back);
    EXPECT_EQ(test::countEntries(dir.path()), 2);  // no temporary files left
}

TEST_P(PngRoundTrip, EightBitDitheredIsWithinOneStep) {
    ScratchDir dir("png8");
    const int channels = GetParam();
    const Image source = pattern(19, 11, channels);
    writePng(dir / "a.png", source, {PngBitDepth::Eight, true});
    EXPECT_EQ(readImageInfo(dir / "a.png").bitDepth, 8);
    const Image back = readImage(dir / "a.png");
    // The dither threshold lies in (0, 1) LSB, so the error is under one step.
    EXPECT_LE(test::maxAbsDiff(source, back), 1.0 / 255.0 + 1e-7);
    // Without dither it is plain rounding: half a step.
    writePng(dir / "b.png", source, {PngBitDepth::Eight, false});
    EXPECT_LE(test::maxAbsDiff(source, readImage(dir / "b.png")), 0.5 / 255.0 + 1e-7);
}

INSTANTIATE_TEST_SUITE_P(Channels, PngRoundTrip, ::testing::Values(1, 2, 3, 4));

TEST(PngWrite, DitherPreservesTheMeanOfAGrayBetweenTwoLevels) {
    ScratchDir dir("dither");
    const double level = (100.0 + 0.3) / 255.0;  // 30% of the way from level 100 to 101
    const Image flat(64, 64, 1, static_cast<float>(level));
    writePng(dir / "d.png", flat, {PngBitDepth::Eight, true});
    writePng(dir / "r.png", flat, {PngBitDepth::Eight, false});
    const Image dithered = readImage(dir / "d.png");
    const Image rounded = readImage(dir / "r.png");
    // Only the two neighbouring levels occur.
    for (float v : dithered.pixels()) EXPECT_TRUE(v == 100.0f / 255.0f || v == 101.0f / 255.0f) << v;
    // The 64 Bayer thresholds (b + 0.5) / 64 leave at most 0.5/64 LSB of mean error over whole 8x8 blocks.
    EXPECT_NEAR(mean(dithered), level, 0.5 / 64.0 / 255.0 + 1e-7);
    EXPECT_NEAR(mean(dithered), level, 0.002);
    // Plain rounding loses the 0.3 LSB: that is what the dither is for.
    EXPECT_NEAR(mean(rounded), 100.0 / 255.0, 1e-7);
    EXPECT_GT(std::fabs(mean(rounded) - level), 0.29 / 255.0);
    // Deterministic: the same input writes the same bytes.
    writePng(dir / "d2.png", flat, {PngBitDepth::Eight, true});
    EXPECT_EQ(readAll(dir / "d.png"), readAll(dir / "d2.png"));
}

TEST(PngWrite, ClampsAndQuantisesAsDocumented) {
    ScratchDir dir("clamp");
    Image image(4, 1, 1);
    image.at(0, 0) = -0.5f;
    image.at(1, 0) = 2.0f;
    image.at(2, 0) = std::nanf("");
    image.at(3, 0) = 0.5f;
    writePng(dir / "c.png", image);
    const Image back = readImage(dir / "c.png");
    EXPECT_EQ(back.at(0, 0), 0.0f);
    EXPECT_EQ(back.at(1, 0), 1.0f);
    EXPECT_EQ(back.at(2, 0), 0.0f);                 // NaN is written as 0
    EXPECT_EQ(back.at(3, 0), 32768.0f / 65535.0f);  // round(0.5 * 65535) = round(32767.5) = 32768
}

TEST(PngWrite, AnIndependentReaderSeesTheSameSixteenBitLevels) {
    ScratchDir dir("stb16");
    Image image(3, 1, 1);
    image.at(0, 0) = 0x1234 / 65535.0f;
    image.at(1, 0) = 0xfe01 / 65535.0f;
    image.at(2, 0) = 1.0f;
    writePng(dir / "s.png", image);
    int w = 0, h = 0, n = 0;
    stbi_us* levels = stbi_load_16((dir / "s.png").c_str(), &w, &h, &n, 0);
    ASSERT_NE(levels, nullptr);
    EXPECT_EQ(w * h * n, 3);
    // stb_image decodes PNG's big-endian samples; a byte-swapped writer would give 0x3412 here.
    EXPECT_EQ(levels[0], 0x1234);
    EXPECT_EQ(levels[1], 0xfe01);
    EXPECT_EQ(levels[2], 0xffff);
    stbi_image_free(levels);
    // And our reader decodes a hand-made big-endian sample the same way.
    test::writeBytes(dir / "h.png", makePng(1, 1, 16, 0, std::string("\0\x12\x34", 3)));
    EXPECT_EQ(readImage(dir / "h.png").at(0, 0), 0x1234 / 65535.0f);
}

TEST(PngWrite, RowsAreTopFirstWithNoFlip) {
    ScratchDir dir("rows");
    Image image(1, 2, 1);
    image.at(0, 0) = 1.0f;  // row 0: the top row, v near 1
    image.at(0, 1) = 0.0f;
    writePng(dir / "r.png", image, {PngBitDepth::Eight, false});
    // An independent reader (stb_image) sees the white row first in the file.
    int w = 0, h = 0, n = 0;
    stbi_uc* stored = stbi_load((dir / "r.png").c_str(), &w, &h, &n, 0);
    ASSERT_NE(stored, nullptr);
    EXPECT_EQ(stored[0], 255);
    EXPECT_EQ(stored[1], 0);
    stbi_image_free(stored);
    const Image back = readImage(dir / "r.png");
    EXPECT_EQ(back.at(0, 0), 1.0f);
    EXPECT_EQ(back.at(0, 1), 0.0f);
    // Hand-made file with the same content: first scanline 0xff, second 0x00.
    test::writeBytes(dir / "h.png", makePng(1, 2, 8, 0, std::string("\0\xff\0\0", 4)));
    EXPECT_EQ(readImage(dir / "h.png"), back);
}

// ---- PNG variants that are expanded on read -------------------------------------------------------------

TEST(PngRead, PaletteIsExpandedToRgbAndTransparencyToAlpha) {
    ScratchDir dir("palette");
    const std::string palette =
        pngChunk("PLTE", std::string("\xff\x00\x00\x00\x80\xff", 6));  // red, (0,128,255)
    const std::string rows =
        std::string("\0\x00\x01", 3) + std::string("\0\x01\x00", 3);  // 2x2, 8-bit indices
    test::writeBytes(dir / "p.png", makePng(2, 2, 8, 3, rows, palette));
    const ImageInfo info = readImageInfo(dir / "p.png");
    EXPECT_EQ(info.channels, 3);
    EXPECT_EQ(info.bitDepth, 8);
    const Image rgb = readImage(dir / "p.png");
    ASSERT_EQ(rgb.channels(), 3);
    EXPECT_EQ(rgb.at(0, 0, 0), 1.0f);
    EXPECT_EQ(rgb.at(0, 0, 1), 0.0f);
    EXPECT_EQ(rgb.at(1, 0, 1), 128.0f / 255.0f);
    EXPECT_EQ(rgb.at(1, 0, 2), 1.0f);
    EXPECT_EQ(rgb.at(0, 1, 2), 1.0f);

    test::writeBytes(dir / "t.png",
                     makePng(2, 2, 8, 3, rows, palette + pngChunk("tRNS", std::string("\x40", 1))));
    EXPECT_EQ(readImageInfo(dir / "t.png").channels, 4);
    const Image rgba = readImage(dir / "t.png");
    ASSERT_EQ(rgba.channels(), 4);
    EXPECT_EQ(rgba.at(0, 0, 3), 64.0f / 255.0f);  // index 0 has alpha 0x40
    EXPECT_EQ(rgba.at(1, 0, 3), 1.0f);            // entries beyond tRNS are opaque
}

TEST(PngRead, LowBitGrayIsExpandedToEightBitLevels) {
    ScratchDir dir("gray1");
    // 1-bit: 8 texels in one byte 0b10110000 -> 1,0,1,1,0,0,0,0.
    test::writeBytes(dir / "g1.png", makePng(8, 1, 1, 0, std::string("\0\xb0", 2)));
    const Image g1 = readImage(dir / "g1.png");
    ASSERT_EQ(g1.channels(), 1);
    const float expected1[] = {1, 0, 1, 1, 0, 0, 0, 0};
    for (int x = 0; x < 8; ++x) EXPECT_EQ(g1.at(x, 0), expected1[x]) << x;
    // 4-bit: 0x5f -> levels 5 and 15 of 15, i.e. 0x55 and 0xff after expansion.
    test::writeBytes(dir / "g4.png", makePng(2, 1, 4, 0, std::string("\0\x5f", 2)));
    const Image g4 = readImage(dir / "g4.png");
    EXPECT_EQ(g4.at(0, 0), 85.0f / 255.0f);
    EXPECT_EQ(g4.at(1, 0), 1.0f);
    EXPECT_EQ(readImageInfo(dir / "g4.png").bitDepth, 8);
}

TEST(PngRead, InterlacedFileDecodes) {
    ScratchDir dir("adam7");
    // A 2x2 8-bit gray Adam7 file: pass 1 holds (0,0); pass 6 holds (1,0); pass 7 holds row 1.
    std::string ihdr = bigEndian32(2) + bigEndian32(2) + std::string("\x08\x00\x00\x00\x01", 5);
    const std::string raw =
        std::string("\0\x10", 2) + std::string("\0\x20", 2) + std::string("\0\x30\x40", 3);
    test::writeBytes(dir / "i.png", kPngSignature + pngChunk("IHDR", ihdr) +
                                        pngChunk("IDAT", zlibStored(raw)) + pngChunk("IEND", ""));
    const Image image = readImage(dir / "i.png");
    EXPECT_EQ(image.at(0, 0), 16.0f / 255.0f);
    EXPECT_EQ(image.at(1, 0), 32.0f / 255.0f);
    EXPECT_EQ(image.at(0, 1), 48.0f / 255.0f);
    EXPECT_EQ(image.at(1, 1), 64.0f / 255.0f);
}

// ---- EXR ----------------------------------------------------------------------------------------------

TEST(Exr, RoundTripIsExactForEveryChannelCount) {
    ScratchDir dir("exr");
    for (int channels = 1; channels <= 4; ++channels) {
        Image source = pattern(9, 5, channels);
        // Values outside [0, 1] and not representable in half survive too: EXR is stored as float.
        source.at(0, 0, 0) = -3.25f;
        source.at(1, 0, 0) = 1234.5678f;
        source.at(2, 0, 0) = 1e-7f;
        const fs::path file = dir / ("e" + std::to_string(channels) + ".exr");
        writeExr(file, source);
        const ImageInfo info = readImageInfo(file);
        EXPECT_EQ(info.format, ImageFormat::Exr);
        EXPECT_EQ(info.width, 9);
        EXPECT_EQ(info.height, 5);
        EXPECT_EQ(info.channels, channels);
        EXPECT_EQ(info.bitDepth, 32);
        EXPECT_EQ(readImage(file), source) << channels << " channels";
    }
    EXPECT_EQ(test::countEntries(dir.path()), 4);
}

TEST(Exr, WriteImageChoosesByExtensionCaseInsensitively) {
    ScratchDir dir("ext");
    const Image source = pattern(3, 3, 3);
    writeImage(dir / "a.EXR", source);
    EXPECT_EQ(readImageInfo(dir / "a.EXR").format, ImageFormat::Exr);
    writeImage(dir / "b.Png", source, {PngBitDepth::Eight, false});
    EXPECT_EQ(readImageInfo(dir / "b.Png").format, ImageFormat::Png);
    EXPECT_EQ(readImageInfo(dir / "b.Png").bitDepth, 8);
    // .jpg has a writer now (test_image_write_formats.cpp); a format without one is refused.
    expectError([&] { writeImage(dir / "c.tif", source); }, ErrorKind::Unsupported, dir / "c.tif", ".tif");
    expectError([&] { writeImage(dir / "noext", source); }, ErrorKind::Unsupported, dir / "noext");
    EXPECT_EQ(test::countEntries(dir.path()), 2);
}

// Finds the dataWindow attribute's 16 value bytes in an EXR file.
std::size_t exrDataWindowOffset(const std::string& bytes) {
    const std::string key("dataWindow\0box2i\0", 17);
    const std::size_t at = bytes.find(key);
    return at == std::string::npos ? at : at + key.size() + 4;  // skip the attribute's size field
}

void putLe32(std::string& bytes, std::size_t at, std::int32_t value) {
    const auto v = static_cast<std::uint32_t>(value);
    for (int k = 0; k < 4; ++k) bytes[at + static_cast<std::size_t>(k)] = static_cast<char>(v >> (8 * k));
}

TEST(Exr, CorruptOrTruncatedPixelDataIsInvalidInput) {
    ScratchDir dir("exrbad");
    writeExr(dir / "g.exr", pattern(32, 32, 4));
    const std::string good = readAll(dir / "g.exr");
    // Garbled ZIP data in the last scanline blocks: tinyexr fails while decoding pixels (a path on
    // which it frees part of the image itself; the reader must neither free it again nor leak).
    std::string garbled = good;
    for (std::size_t i = good.size() - 200; i < good.size(); i += 7)
        garbled[i] = static_cast<char>(garbled[i] ^ 0xa5);
    test::writeBytes(dir / "garbled.exr", garbled);
    expectError([&] { readImage(dir / "garbled.exr"); }, ErrorKind::InvalidInput, dir / "garbled.exr", "EXR");
    test::writeBytes(dir / "cut.exr", good.substr(0, good.size() / 2));
    expectError([&] { readImage(dir / "cut.exr"); }, ErrorKind::InvalidInput, dir / "cut.exr", "EXR");
    test::writeBytes(dir / "head.exr", good.substr(0, 40));
    expectReadError(dir / "head.exr", ErrorKind::InvalidInput, "EXR");
}

TEST(Exr, OversizedHeaderIsRefusedBeforeDecoding) {
    ScratchDir dir("exrbig");
    writeExr(dir / "s.exr", Image(2, 2, 1, 0.5f));
    std::string bytes = readAll(dir / "s.exr");
    const std::size_t window = exrDataWindowOffset(bytes);
    ASSERT_NE(window, std::string::npos);
    putLe32(bytes, window + 8, 99999);  // max_x: 100000 texels wide
    test::writeBytes(dir / "big.exr", bytes);
    expectReadError(dir / "big.exr", ErrorKind::Unsupported, "16384");
}

// ---- JPEG, TGA, BMP through stb_image -------------------------------------------------------------------

// 8-bit copy of an image, for stb_image_write.
std::vector<unsigned char> toBytes(const Image& image) {
    std::vector<unsigned char> bytes;
    for (float v : image.pixels()) bytes.push_back(static_cast<unsigned char>(std::lround(v * 255.0f)));
    return bytes;
}

Image quantised8(const Image& image) {
    Image out = image;
    for (float& v : out.pixels()) v = static_cast<float>(std::lround(v * 255.0f)) / 255.0f;
    return out;
}

TEST(StbFormats, TgaAndBmpReadExactlyAndTopFirst) {
    ScratchDir dir("stb");
    for (int channels : {1, 3, 4}) {
        const Image source = quantised8(pattern(7, 5, channels));
        const auto bytes = toBytes(source);
        const std::string tag = std::to_string(channels);
        for (int rle : {0, 1}) {
            stbi_write_tga_with_rle = rle;
            const fs::path tga = dir / ("t" + tag + "_" + std::to_string(rle) + ".tga");
            ASSERT_TRUE(stbi_write_tga(tga.c_str(), 7, 5, channels, bytes.data()));
            const ImageInfo info = readImageInfo(tga);
            EXPECT_EQ(info.format, ImageFormat::Tga);
            EXPECT_EQ(info.channels, channels);
            EXPECT_EQ(info.bitDepth, 8);
            EXPECT_EQ(readImage(tga), source) << tga;  // 8-bit values come back as v / 255 exactly
        }
        if (channels != 4) {  // stb writes BMP as 24-bit
            const fs::path bmp = dir / ("b" + tag + ".bmp");
            ASSERT_TRUE(stbi_write_bmp(bmp.c_str(), 7, 5, channels, bytes.data()));
            EXPECT_EQ(readImageInfo(bmp).format, ImageFormat::Bmp);
            const Image back = readImage(bmp);
            ASSERT_EQ(back.channels(), 3);
            for (int y = 0; y < 5; ++y)
                for (int x = 0; x < 7; ++x)
                    for (int c = 0; c < 3; ++c)
                        EXPECT_EQ(back.at(x, y, c), source.at(x, y, channels == 1 ? 0 : c)) << x << "," << y;
        }
    }
    stbi_write_tga_with_rle = 1;
}

TEST(StbFormats, HandMadeBottomUpTgaIsFlippedToTopFirst) {
    ScratchDir dir("tga");
    // 1x2 uncompressed gray TGA, origin bottom-left (descriptor 0): the first stored texel is the bottom.
    std::string header(18, '\0');
    header[2] = 3;   // uncompressed gray
    header[12] = 1;  // width 1
    header[14] = 2;  // height 2
    header[16] = 8;  // bits per pixel
    test::writeBytes(dir / "g.tga", header + std::string("\x00\xff", 2));
    const Image image = readImage(dir / "g.tga");
    ASSERT_EQ(image.height(), 2);
    EXPECT_EQ(image.at(0, 0), 1.0f);  // top row: the one stored last
    EXPECT_EQ(image.at(0, 1), 0.0f);

    header[17] = 0x20;  // top-left origin: stored order is the image order
    test::writeBytes(dir / "t.tga", header + std::string("\x00\xff", 2));
    EXPECT_EQ(readImage(dir / "t.tga").at(0, 0), 0.0f);
}

TEST(StbFormats, JpegReadsCloseToTheSource) {
    ScratchDir dir("jpeg");
    // A smooth gradient: JPEG at quality 100 reproduces it to a few levels.
    Image source(16, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            source.at(x, y, 0) = static_cast<float>(x) / 15.0f;
            source.at(x, y, 1) = static_cast<float>(y) / 15.0f;
            source.at(x, y, 2) = 0.5f;
        }
    source = quantised8(source);
    const auto bytes = toBytes(source);
    ASSERT_TRUE(stbi_write_jpg((dir / "j.jpg").c_str(), 16, 16, 3, bytes.data(), 100));
    const ImageInfo info = readImageInfo(dir / "j.jpg");
    EXPECT_EQ(info.format, ImageFormat::Jpeg);
    EXPECT_EQ(info.width, 16);
    EXPECT_EQ(info.channels, 3);
    const Image back = readImage(dir / "j.jpg");
    // Quality 100 still quantises DCT coefficients and subsamples chroma; 12 levels bounds the error
    // on this gradient, and the top-left / bottom-right corners show the orientation.
    EXPECT_LE(test::maxAbsDiff(source, back), 12.0 / 255.0);
    EXPECT_LT(back.at(0, 0, 1), 0.1f);
    EXPECT_GT(back.at(15, 15, 1), 0.9f);

    // Cut short: the end-of-image marker is gone.
    const std::string full = readAll(dir / "j.jpg");
    test::writeBytes(dir / "cut.jpg", full.substr(0, full.size() / 2));
    expectError([&] { readImage(dir / "cut.jpg"); }, ErrorKind::InvalidInput, dir / "cut.jpg", "truncated");
}

TEST(StbFormats, TruncatedOrOversizedTgaAndBmpAreRefused) {
    ScratchDir dir("stbbad");
    const Image source = quantised8(pattern(6, 4, 3));
    const auto bytes = toBytes(source);
    stbi_write_tga_with_rle = 0;
    ASSERT_TRUE(stbi_write_tga((dir / "a.tga").c_str(), 6, 4, 3, bytes.data()));
    stbi_write_tga_with_rle = 1;
    ASSERT_TRUE(stbi_write_bmp((dir / "a.bmp").c_str(), 6, 4, 3, bytes.data()));
    const std::string tga = readAll(dir / "a.tga");
    const std::string bmp = readAll(dir / "a.bmp");

    test::writeBytes(dir / "cut.tga", tga.substr(0, 30));
    expectError([&] { readImage(dir / "cut.tga"); }, ErrorKind::InvalidInput, dir / "cut.tga", "truncated");
    test::writeBytes(dir / "cut.bmp", bmp.substr(0, bmp.size() - 10));
    expectError([&] { readImage(dir / "cut.bmp"); }, ErrorKind::InvalidInput, dir / "cut.bmp", "truncated");
    test::writeBytes(dir / "head.bmp", bmp.substr(0, 10));
    expectReadError(dir / "head.bmp", ErrorKind::InvalidInput);

    std::string bigTga = tga;
    bigTga[12] = static_cast<char>(20000 & 0xff);  // width 20000
    bigTga[13] = static_cast<char>(20000 >> 8);
    test::writeBytes(dir / "big.tga", bigTga);
    expectReadError(dir / "big.tga", ErrorKind::Unsupported, "20000 x 4");
    std::string bigBmp = bmp;
    putLe32(bigBmp, 18, 100000);
    test::writeBytes(dir / "big.bmp", bigBmp);
    expectReadError(dir / "big.bmp", ErrorKind::Unsupported, "100000 x 4");

    std::string zeroTga = tga;
    zeroTga[12] = zeroTga[13] = 0;
    test::writeBytes(dir / "zero.tga", zeroTga);
    expectReadError(dir / "zero.tga", ErrorKind::InvalidInput);
}

// ---- readScalarMap ------------------------------------------------------------------------------------

TEST(ScalarMap, GrayIsItselfAndRgbIsLuminanceWithANote) {
    ScratchDir dir("scalar");
    Image gray(2, 1, 2);
    gray.at(0, 0, 0) = 0.25f;
    gray.at(0, 0, 1) = 1.0f;
    gray.at(1, 0, 0) = 0.75f;
    writeExr(dir / "ga.exr", gray);
    std::string note = "unchanged";
    const Image g = readScalarMap(dir / "ga.exr", &note);
    ASSERT_EQ(g.channels(), 1);
    EXPECT_EQ(g.at(0, 0), 0.25f);
    EXPECT_EQ(g.at(1, 0), 0.75f);
    EXPECT_EQ(note, "unchanged");  // gray files need no note

    Image rgb(1, 1, 3);
    rgb.at(0, 0, 0) = 1.0f;  // pure red: luminance 0.2126
    writeExr(dir / "rgb.exr", rgb);
    const Image r = readScalarMap(dir / "rgb.exr", &note);
    ASSERT_EQ(r.channels(), 1);
    EXPECT_FLOAT_EQ(r.at(0, 0), 0.2126f);
    EXPECT_EQ(
        note.rfind((dir / "rgb.exr").string() + ": RGB image read as a scalar map through its luminance", 0),
        0u)
        << note;
    EXPECT_NE(note.find("709"), std::string::npos);

    Image rgba(1, 1, 4, 1.0f);
    rgba.at(0, 0, 3) = 0.0f;
    writePng(dir / "rgba.png", rgba);
    const Image a = readScalarMap(dir / "rgba.png", &note);
    EXPECT_NEAR(a.at(0, 0), 1.0f, 1e-6);  // 0.2126 + 0.7152 + 0.0722 = 1; alpha does not enter
    EXPECT_NE(note.find("RGBA"), std::string::npos);
    EXPECT_NO_THROW(readScalarMap(dir / "rgba.png"));  // the note is optional
}

// ---- bad input ----------------------------------------------------------------------------------------

TEST(BadInput, MissingFileAndDirectoryAreIoErrors) {
    ScratchDir dir("missing");
    expectReadError(dir / "nope.png", ErrorKind::Io);
    expectReadError(dir / "no_dir" / "x.png", ErrorKind::Io);
    expectReadError(dir.path(), ErrorKind::Io, "directory");
    expectError([&] { readScalarMap(dir / "nope.png"); }, ErrorKind::Io, dir / "nope.png");
}

TEST(BadInput, EmptyTextAndUnknownFilesAreInvalidInput) {
    ScratchDir dir("bad");
    test::writeBytes(dir / "empty.png", "");
    expectReadError(dir / "empty.png", ErrorKind::InvalidInput, "empty");
    test::writeBytes(dir / "text.png", "Hello, this is not an image at all.\n");
    expectReadError(dir / "text.png", ErrorKind::InvalidInput, "not an image (unrecognised content)");
    test::writeBytes(dir / "short.png", kPngSignature.substr(0, 4));
    expectReadError(dir / "short.png", ErrorKind::InvalidInput, "truncated");
    test::writeBytes(dir / "one.png", "x");
    expectReadError(dir / "one.png", ErrorKind::InvalidInput);
    test::writeBytes(dir / "a.pgm", "P5\n2 2\n255\n\x01\x02\x03\x04");
    expectReadError(dir / "a.pgm", ErrorKind::Unsupported, "Netpbm");
    // A GIF is an image, but not one Strata reads.
    test::writeBytes(dir / "a.gif", "GIF89a\x01\x00\x01\x00\x00\x00\x00;");
    expectReadError(dir / "a.gif", ErrorKind::Unsupported, "GIF");
}

TEST(BadInput, FormatComesFromContentNotExtension) {
    ScratchDir dir("sniff");
    writeExr(dir / "really_exr.png", Image(2, 2, 1, 0.25f));
    EXPECT_EQ(readImageInfo(dir / "really_exr.png").format, ImageFormat::Exr);
    EXPECT_EQ(readImage(dir / "really_exr.png").at(1, 1), 0.25f);
    writePng(dir / "p.png", Image(2, 2, 1, 0.25f));
    fs::rename(dir / "p.png", dir / "p.jpg");
    EXPECT_EQ(readImageInfo(dir / "p.jpg").format, ImageFormat::Png);
}

TEST(BadInput, TruncatedAndCorruptPngAreInvalidInput) {
    ScratchDir dir("corrupt");
    writePng(dir / "good.png", pattern(32, 32, 3));
    const std::string good = readAll(dir / "good.png");
    for (std::size_t keep : {std::size_t{12}, std::size_t{40}, good.size() / 2, good.size() - 6}) {
        const fs::path cut = dir / ("cut" + std::to_string(keep) + ".png");
        test::writeBytes(cut, good.substr(0, keep));
        expectError([&] { readImage(cut); }, ErrorKind::InvalidInput, cut, "PNG");
    }
    // A flipped byte inside IDAT breaks its CRC.
    std::string flipped = good;
    flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x5a);
    test::writeBytes(dir / "flip.png", flipped);
    expectError([&] { readImage(dir / "flip.png"); }, ErrorKind::InvalidInput, dir / "flip.png", "PNG");
    // Valid chunks, garbage compressed data.
    std::string garbage = kPngSignature +
                          pngChunk("IHDR", bigEndian32(4) + bigEndian32(4) + std::string("\x08\0\0\0\0", 5)) +
                          pngChunk("IDAT", "this is not zlib data") + pngChunk("IEND", "");
    test::writeBytes(dir / "garbage.png", garbage);
    expectError([&] { readImage(dir / "garbage.png"); }, ErrorKind::InvalidInput, dir / "garbage.png");
    EXPECT_EQ(readImageInfo(dir / "garbage.png").width, 4);  // the header alone is fine
}

TEST(BadInput, ZeroWidthPngIsInvalidInput) {
    ScratchDir dir("zero");
    test::writeBytes(dir / "w0.png", makePng(0, 4, 8, 0, ""));
    expectReadError(dir / "w0.png", ErrorKind::InvalidInput, "width is zero");
    test::writeBytes(dir / "h0.png", makePng(4, 0, 8, 0, ""));
    expectReadError(dir / "h0.png", ErrorKind::InvalidInput);
}

TEST(BadInput, OversizedPngIsRefusedFromItsHeader) {
    ScratchDir dir("huge");
    writePng(dir / "small.png", Image(3, 2, 4, 0.5f));
    std::string bytes = readAll(dir / "small.png");
    // Patch IHDR (length at 8, type at 12, data at 16, CRC at 29) to 100000 x 100000 and fix its CRC,
    // so that the header is valid and only its size is wrong. Decoding it would need 160 GB of floats.
    ASSERT_EQ(bytes.substr(12, 4), "IHDR");
    bytes.replace(16, 4, bigEndian32(100000));
    bytes.replace(20, 4, bigEndian32(100000));
    bytes.replace(29, 4, bigEndian32(pngCrc32(bytes.substr(12, 17))));
    test::writeBytes(dir / "huge.png", bytes);
    expectReadError(dir / "huge.png", ErrorKind::Unsupported, "100000 x 100000");
    // One side over the limit is enough.
    test::writeBytes(dir / "wide.png", makePng(Image::kMaxDimension + 1, 1, 8, 0, std::string(2, '\0')));
    expectReadError(dir / "wide.png", ErrorKind::Unsupported, "16385 x 1");
}

// ---- failed writes leave nothing ---------------------------------------------------------------------

TEST(FailedWrite, MissingDirectoryIsIoAndLeavesNothing) {
    ScratchDir dir("wfail");
    const Image image = pattern(4, 4, 3);
    expectError([&] { writePng(dir / "no_dir" / "a.png", image); }, ErrorKind::Io, dir / "no_dir" / "a.png");
    expectError([&] { writeExr(dir / "no_dir" / "a.exr", image); }, ErrorKind::Io, dir / "no_dir" / "a.exr");
    EXPECT_EQ(test::countEntries(dir.path()), 0);
}

TEST(FailedWrite, DestinationThatIsADirectoryIsIoAndLeavesNoTemporary) {
    ScratchDir dir("wdir");
    fs::create_directory(dir / "taken.png");
    fs::create_directory(dir / "taken.exr");
    fs::create_directory(dir / "taken.png" / "inside");  // non-empty: rename cannot replace it
    fs::create_directory(dir / "taken.exr" / "inside");
    const Image image = pattern(4, 4, 1);
    expectError([&] { writePng(dir / "taken.png", image); }, ErrorKind::Io, dir / "taken.png");
    expectError([&] { writeExr(dir / "taken.exr", image); }, ErrorKind::Io, dir / "taken.exr");
    EXPECT_EQ(test::countEntries(dir.path()), 2);  // only the two directories
}

TEST(FailedWrite, ExistingFileIsReplacedWhole) {
    ScratchDir dir("replace");
    writePng(dir / "a.png", Image(8, 8, 3, 1.0f));
    writePng(dir / "a.png", Image(2, 3, 1, 0.0f));
    const ImageInfo info = readImageInfo(dir / "a.png");
    EXPECT_EQ(info.width, 2);
    EXPECT_EQ(info.height, 3);
    EXPECT_EQ(info.channels, 1);
    EXPECT_EQ(test::countEntries(dir.path()), 1);
}

TEST(ImageFormatNames, AreStable) {
    EXPECT_STREQ(toString(ImageFormat::Png), "PNG");
    EXPECT_STREQ(toString(ImageFormat::Jpeg), "JPEG");
    EXPECT_STREQ(toString(ImageFormat::Tga), "TGA");
    EXPECT_STREQ(toString(ImageFormat::Bmp), "BMP");
    EXPECT_STREQ(toString(ImageFormat::Exr), "EXR");
}

}  // namespace
}  // namespace strata
