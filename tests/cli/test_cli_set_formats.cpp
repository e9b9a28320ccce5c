// Texture sets in float and with height: `--format exr` and `--write-height` on every command that writes a
// set (pattern, import, compose), and the commands that read a set afterwards (ao, render, export).
#include "test_support.h"

#include "strata/image/image_io.h"
#include "strata/relief/patterns.h"
#include "strata/relief/texture_set.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace strata {
namespace {

namespace fs = std::filesystem;
using test::runCli;

using test::quoted;

TEST(CliSetFormats, PatternWritesAFloatSetWithHeightThatOtherCommandsRead) {
    test::ScratchDir dir("set-exr");
    const auto result =
        runCli("pattern stone-bricks --size 64 --format exr --write-height -o " + quoted(dir / "s"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    for (const char* name :
         {"depth.exr", "height.exr", "normal.exr", "packed.exr", "color.png", "strata.json"})
        EXPECT_TRUE(fs::exists(dir / "s" / name)) << name;
    EXPECT_FALSE(fs::exists(dir / "s" / "depth.png"));
    EXPECT_EQ(readImageInfo(dir / "s" / "depth.exr").format, ImageFormat::Exr);
    const nlohmann::json sidecar = readSidecar(dir / "s");
    EXPECT_EQ(sidecar["file_format"], "exr");
    EXPECT_EQ(sidecar["bit_depth"], 32);
    EXPECT_EQ(sidecar["height"]["file"], "height.exr");
    EXPECT_DOUBLE_EQ(sidecar["height"]["amplitude"].get<double>(), sidecar["depth_scale"].get<double>());

    const auto info = runCli("info " + quoted(dir / "s"));
    EXPECT_NE(info.output.find("bit depth     : 32 (exr)"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("height        : height.exr 64x64, white = high, amplitude 0.08"),
              std::string::npos)
        << info.output;

    // Float maps hold the library's maps exactly; the height map is 1 - depth.
    PatternParams params;
    params.size = 64;
    const ReliefTexture expected = makePattern("stone-bricks", params);
    const ReliefTexture back = readTextureSet(dir / "s");
    EXPECT_EQ(test::maxAbsDiff(back.depth, expected.depth), 0.0);
    // n * 0.5 + 0.5 in float, decoded and renormalised: a few float ulps.
    EXPECT_LE(test::maxAbsDiff(back.normal, expected.normal), 1e-6);
    EXPECT_EQ(test::maxAbsDiff(readImage(dir / "s" / "height.exr"), heightToDepth(expected.depth)), 0.0);

    // `strata ao` keeps the set in its format: ao.exr, and packed.exr's B replaced.
    const auto ao = runCli("ao " + quoted(dir / "s") + " --directions 8");
    ASSERT_EQ(ao.exitCode, 0) << ao.output;
    EXPECT_EQ(readSidecar(dir / "s")["ao"]["file"], "ao.exr");
    const Image aoMap = readImage(dir / "s" / "ao.exr");
    const Image packed = readImage(dir / "s" / "packed.exr");
    for (int y = 0; y < 64; y += 7)
        for (int x = 0; x < 64; x += 5) {
            EXPECT_EQ(packed.at(x, y, 2), aoMap.at(x, y));
            EXPECT_EQ(packed.at(x, y, 3), expected.depth.at(x, y));
        }
    // The float set renders like the 16-bit one: the two differ by less than one 8-bit level almost
    // everywhere (the depths differ by at most half a 16-bit step).
    ASSERT_EQ(runCli("pattern stone-bricks --size 64 -o " + quoted(dir / "p")).exitCode, 0);
    ASSERT_EQ(runCli("ao " + quoted(dir / "p") + " --directions 8").exitCode, 0);
    const auto renderExr = runCli("render --mesh quad --material " + quoted(dir / "s") + " --size 96x96 -o " +
                                  quoted(dir / "exr.png"));
    ASSERT_EQ(renderExr.exitCode, 0) << renderExr.output;
    ASSERT_EQ(runCli("render --mesh quad --material " + quoted(dir / "p") + " --size 96x96 -o " +
                     quoted(dir / "png.png"))
                  .exitCode,
              0);
    const Image a = readImage(dir / "exr.png");
    const Image b = readImage(dir / "png.png");
    int differing = 0;
    for (std::size_t i = 0; i < a.pixels().size(); ++i)
        if (std::abs(a.pixels()[i] - b.pixels()[i]) > 1.5f / 255.0f) ++differing;
    EXPECT_LE(differing, static_cast<int>(a.pixels().size() / 100)) << "more than 1 % of the samples differ";
}

TEST(CliSetFormats, ImportAndComposeTakeTheSameFlags) {
    test::ScratchDir dir("set-exr-import");
    ASSERT_EQ(runCli("pattern base --size 64 -o " + quoted(dir / "base")).exitCode, 0);
    const auto imported = runCli("import --depth " + quoted(dir / "base" / "depth.png") +
                                 " --format exr --write-height -o " + quoted(dir / "imported"));
    ASSERT_EQ(imported.exitCode, 0) << imported.output;
    EXPECT_TRUE(fs::exists(dir / "imported" / "depth.exr"));
    EXPECT_TRUE(fs::exists(dir / "imported" / "height.exr"));
    // The imported depth is the 16-bit file's values, exactly, in float.
    EXPECT_EQ(
        test::maxAbsDiff(readImage(dir / "imported" / "depth.exr"), readImage(dir / "base" / "depth.png")),
        0.0);
    test::writeBytes(dir / "m.json", R"({"resolution": 64, "layers": [
        {"pattern": "base", "size": 64, "tiling": 1, "weight_depth": 1, "weight_normal": 1}]})");
    const auto composed = runCli("compose " + quoted(dir / "m.json") + " --ao none --format exr -o " +
                                 quoted(dir / "composed"));
    ASSERT_EQ(composed.exitCode, 0) << composed.output;
    EXPECT_EQ(readSidecar(dir / "composed")["file_format"], "exr");
    EXPECT_TRUE(fs::exists(dir / "composed" / "packed.exr"));
    EXPECT_FALSE(readSidecar(dir / "composed").contains("height"));
}

TEST(CliSetFormats, BitDepthWithExrAndUnknownFormatsAreUsageErrors) {
    test::ScratchDir dir("set-exr-usage");
    for (const std::string& command :
         {std::string("pattern base --size 64"), "import --depth " + quoted(dir / "missing.png")}) {
        const auto result = runCli(command + " --format exr --bit-depth 8 -o " + quoted(dir / "out"));
        EXPECT_EQ(result.exitCode, 1) << result.output;
        EXPECT_NE(
            result.output.find("strata: error: --bit-depth applies to PNG maps; --format exr writes 32-bit "
                               "float"),
            std::string::npos)
            << result.output;
    }
    const auto tiff = runCli("pattern base --size 64 --format tiff -o " + quoted(dir / "out"));
    EXPECT_EQ(tiff.exitCode, 1) << tiff.output;
    EXPECT_NE(tiff.output.find("strata: error: --format: tiff not in {png,exr}"), std::string::npos)
        << tiff.output;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace strata
