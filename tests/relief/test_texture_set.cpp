// Texture sets on disk: layout, packing (CONVENTIONS §5), sidecar (§6), atomic writes.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/relief/texture_set.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace strata {
namespace {

ReliefTexture smallSet() {
    ReliefTexture texture;
    texture.depth = Image(8, 4, 1);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) texture.depth.at(x, y) = static_cast<float>(x + 8 * y) / 31.0f;
    texture.depthScale = 0.12;
    texture.normal = normalsFromDepth(texture.depth, texture.depthScale);
    texture.color = Image(16, 8, 3, 0.5f);  // another resolution: normal, not an error
    return texture;
}

constexpr double kSixteenBitStep = 1.0 / 65535.0;

TEST(TextureSet, RoundTripsAt16Bits) {
    test::ScratchDir dir("set");
    const ReliefTexture texture = smallSet();
    const auto written = writeTextureSet(dir.path(), texture);
    EXPECT_EQ(written.size(), 5u);  // depth, normal, color, packed, sidecar
    const ReliefTexture back = readTextureSet(dir.path());
    // Quantisation to 16 bits rounds to the nearest step: at most half a step off.
    EXPECT_LE(test::maxAbsDiff(back.depth, texture.depth), 0.5 * kSixteenBitStep + 1e-7);
    // Normals are stored as n * 0.5 + 0.5, so a component is off by at most one step after decoding,
    // and renormalisation moves it a little more.
    EXPECT_LE(test::maxAbsDiff(back.normal, texture.normal), 2.0 * kSixteenBitStep);
    EXPECT_EQ(back.color.width(), 16);
    EXPECT_DOUBLE_EQ(back.depthScale, 0.12);
    EXPECT_TRUE(back.ao.empty());
}

TEST(TextureSet, PackedHoldsNormalXYAoAndDepth) {
    test::ScratchDir dir("packed");
    const ReliefTexture texture = smallSet();
    writeTextureSet(dir.path(), texture);
    const Image packed = readImage(dir / "packed.png");
    ASSERT_EQ(packed.channels(), 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            EXPECT_NEAR(packed.at(x, y, 0), texture.normal.at(x, y, 0) * 0.5f + 0.5f, kSixteenBitStep);
            EXPECT_NEAR(packed.at(x, y, 1), texture.normal.at(x, y, 1) * 0.5f + 0.5f, kSixteenBitStep);
            EXPECT_EQ(packed.at(x, y, 2), 1.0f);  // no AO yet: fully open
            EXPECT_NEAR(packed.at(x, y, 3), texture.depth.at(x, y), kSixteenBitStep);
            // The shader rebuilds nz = sqrt(1 - nx^2 - ny^2); it must match the stored normal's z.
            const double nx = static_cast<double>(packed.at(x, y, 0)) * 2.0 - 1.0;
            const double ny = static_cast<double>(packed.at(x, y, 1)) * 2.0 - 1.0;
            EXPECT_NEAR(std::sqrt(1.0 - nx * nx - ny * ny), texture.normal.at(x, y, 2), 1e-3);
        }
}

TEST(TextureSet, SidecarRecordsWhatAReaderCannotGuess) {
    test::ScratchDir dir("sidecar");
    writeTextureSet(dir.path(), smallSet());
    const nlohmann::json sidecar = readSidecar(dir.path());
    EXPECT_EQ(sidecar["format"], "strata.texture-set");
    EXPECT_DOUBLE_EQ(sidecar["depth_scale"].get<double>(), 0.12);
    EXPECT_EQ(sidecar["depth"]["encoding"], "depth");
    EXPECT_EQ(sidecar["normal"]["convention"], "opengl");
    EXPECT_EQ(sidecar["bit_depth"], 16);
    EXPECT_TRUE(sidecar["ao"].is_null());
    EXPECT_NE(sidecar["tool"].get<std::string>().find("strata"), std::string::npos);
    EXPECT_EQ(readImageInfo(dir / "depth.png").bitDepth, 16);
    EXPECT_EQ(readImageInfo(dir / "color.png").bitDepth, 8);
}

TEST(TextureSet, EightBitOptionWritesEightBitData) {
    test::ScratchDir dir("eight");
    TextureSetWriteOptions options;
    options.bitDepth = 8;
    writeTextureSet(dir.path(), smallSet(), options);
    EXPECT_EQ(readImageInfo(dir / "depth.png").bitDepth, 8);
    EXPECT_EQ(readImageInfo(dir / "packed.png").bitDepth, 8);
    EXPECT_EQ(readSidecar(dir.path())["bit_depth"], 8);
}

TEST(TextureSet, ExrSetsKeepEveryDataMapInFloat) {
    test::ScratchDir dir("exr");
    ReliefTexture texture = smallSet();
    texture.ao = Image(8, 4, 1);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) texture.ao.at(x, y) = 0.3f + 0.01f * static_cast<float>(x * y);
    TextureSetWriteOptions options;
    options.format = MapFileFormat::Exr;
    options.height = true;
    options.ao = AoRecord{};
    const auto written = writeTextureSet(dir.path(), texture, options);
    EXPECT_EQ(written.size(), 7u);  // depth, height, normal, color, ao, packed, sidecar
    for (const char* name : {"depth.exr", "height.exr", "normal.exr", "ao.exr", "packed.exr"})
        EXPECT_EQ(readImageInfo(dir / name).format, ImageFormat::Exr) << name;
    EXPECT_EQ(readImageInfo(dir / "color.png").bitDepth, 8);  // colour stays 8-bit sRGB
    const ReliefTexture back = readTextureSet(dir.path());
    EXPECT_EQ(test::maxAbsDiff(back.depth, texture.depth), 0.0);
    EXPECT_EQ(test::maxAbsDiff(back.ao, texture.ao), 0.0);
    EXPECT_LE(test::maxAbsDiff(back.normal, texture.normal), 1e-6);  // n * 0.5 + 0.5 and back, renormalised
    EXPECT_EQ(test::maxAbsDiff(readImage(dir / "height.exr"), heightToDepth(texture.depth)), 0.0);
    const nlohmann::json sidecar = readSidecar(dir.path());
    EXPECT_EQ(sidecar["file_format"], "exr");
    EXPECT_EQ(sidecar["bit_depth"], 32);
    EXPECT_EQ(sidecar["packed"]["file"], "packed.exr");
    EXPECT_EQ(sidecar["packed"]["ao_channel"], "ao.exr");
    EXPECT_EQ(sidecar["height"]["encoding"], "height");
    EXPECT_DOUBLE_EQ(sidecar["height"]["amplitude"].get<double>(), 0.12);

    // A new AO map keeps the set's format and the stored depth and normals bit for bit.
    const Image ao(8, 4, 1, 0.25f);
    const auto updated = writeTextureSetAo(dir.path(), ao, AoRecord{});
    EXPECT_EQ(updated.size(), 3u);
    const Image packed = readImage(dir / "packed.exr");
    const Image packedBefore = packRelief(texture);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            EXPECT_EQ(packed.at(x, y, 2), 0.25f);
            EXPECT_EQ(packed.at(x, y, 3), packedBefore.at(x, y, 3));
            EXPECT_EQ(packed.at(x, y, 0), packedBefore.at(x, y, 0));
        }
    EXPECT_EQ(readSidecar(dir.path())["ao"]["file"], "ao.exr");
}

TEST(TextureSet, HeightBesideAPngSetIsOneMinusDepth) {
    test::ScratchDir dir("height");
    TextureSetWriteOptions options;
    options.height = true;
    writeTextureSet(dir.path(), smallSet(), options);
    const Image height = readImage(dir / "height.png");
    const Image depth = readImage(dir / "depth.png");
    // Both quantised to 16 bits from exact complements: their sum is 1 within one step.
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) EXPECT_NEAR(height.at(x, y) + depth.at(x, y), 1.0f, kSixteenBitStep);
    EXPECT_EQ(readSidecar(dir.path())["height"]["file"], "height.png");
    EXPECT_EQ(readSidecar(dir.path())["file_format"], "png");

    test::ScratchDir plain("no-height");
    writeTextureSet(plain.path(), smallSet());
    EXPECT_FALSE(readSidecar(plain.path()).contains("height"));
    EXPECT_FALSE(std::filesystem::exists(plain / "height.png"));
}

TEST(TextureSet, AFailedWriteLeavesNothingBehind) {
    test::ScratchDir dir("fail");
    test::writeBytes(dir / "taken", "a file where the set directory should be");
    EXPECT_THROW(writeTextureSet(dir / "taken", smallSet()), Error);
    EXPECT_EQ(test::countEntries(dir.path()), 1);  // no staging directory left
}

TEST(TextureSet, AnInputIsNeverOverwritten) {
    test::ScratchDir dir("input");
    const ReliefTexture texture = smallSet();
    writePng(dir / "depth.png", texture.depth);
    const auto before = std::filesystem::last_write_time(dir / "depth.png");
    TextureSetWriteOptions options;
    options.inputs = {dir / "depth.png"};
    try {
        writeTextureSet(dir.path(), texture, options);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
        EXPECT_NE(std::string(e.what()).find("refusing to overwrite an input"), std::string::npos);
    }
    EXPECT_EQ(std::filesystem::last_write_time(dir / "depth.png"), before);
    EXPECT_EQ(test::countEntries(dir.path()), 1);
}

TEST(TextureSet, AGrayNormalMapIsAnErrorNotACrash) {
    test::ScratchDir dir("graynormal");
    writeTextureSet(dir.path(), smallSet());
    writePng(dir / "normal.png", Image(8, 4, 1, 0.5f));  // a user replaced it with a gray image
    try {
        readTextureSet(dir.path());
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("normal.png: a normal map needs 3 channels"), std::string::npos)
            << e.what();
    }
}

TEST(TextureSet, SingleMapReadersFollowTheirEncoding) {
    test::ScratchDir dir("single");
    writePng(dir / "h.png", Image(4, 4, 1, 0.25f));
    EXPECT_NEAR(readDepthMap(dir / "h.png", DepthEncoding::Height).at(1, 1), 0.75f, 1.0 / 65535);
    EXPECT_NEAR(readDepthMap(dir / "h.png", DepthEncoding::Depth).at(1, 1), 0.25f, 1.0 / 65535);
    const ReliefTexture texture = smallSet();
    writePng(dir / "n.png", encodeNormals(texture.normal));
    const Image gl = readNormalMap(dir / "n.png");
    const Image dx = readNormalMap(dir / "n.png", true);
    // Stored n * 0.5 + 0.5 at 16 bits: one step after decoding, a little more after renormalising.
    EXPECT_LE(test::maxAbsDiff(gl, texture.normal), 2.0 * kSixteenBitStep);
    EXPECT_EQ(dx.at(3, 2, 1), -gl.at(3, 2, 1));
    EXPECT_EQ(dx.at(3, 2, 0), gl.at(3, 2, 0));
}

TEST(TextureSet, ASidecarOfAnotherKindIsRejected) {
    test::ScratchDir dir("notours");
    test::writeBytes(dir / "strata.json", "{\"format\": \"something-else\"}");
    EXPECT_THROW(readTextureSet(dir.path()), Error);
    test::writeBytes(dir / "strata.json", "not json");
    try {
        readSidecar(dir.path());
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
    }
}

}  // namespace
}  // namespace strata
