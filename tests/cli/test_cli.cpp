// The `strata` CLI end to end: documented exit codes, outputs, and nothing written on failure.
#include "test_support.h"

#include "strata/compose/material.h"
#include "strata/image/image_io.h"
#include "strata/relief/patterns.h"
#include "strata/relief/texture_set.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace strata {
namespace {

using test::runCli;

std::string quoted(const std::filesystem::path& path) {
    return "\"" + path.string() + "\"";
}

TEST(Cli, HelpAndUsageExitCodes) {
    EXPECT_EQ(runCli("--help").exitCode, 0);
    EXPECT_EQ(runCli("compose --help").exitCode, 0);
    EXPECT_EQ(runCli("").exitCode, 1);  // a subcommand is required
    EXPECT_EQ(runCli("frobnicate").exitCode, 1);
    EXPECT_EQ(runCli("pattern base --size 10 -o x").exitCode, 1);  // out of the documented range
    EXPECT_EQ(runCli("pattern base").exitCode, 1);                 // no -o
}

TEST(Cli, PatternListNamesEveryPattern) {
    const auto result = runCli("pattern --list");
    EXPECT_EQ(result.exitCode, 0);
    for (const auto& info : patternList())
        EXPECT_NE(result.output.find(info.name), std::string::npos) << info.name;
}

TEST(Cli, PatternWritesTheLayoutAndMatchesTheLibrary) {
    test::ScratchDir dir("cli-pattern");
    const auto result = runCli("pattern base --size 128 -o " + quoted(dir / "base"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    for (const char* name : {"depth.png", "normal.png", "color.png", "packed.png", "strata.json"})
        EXPECT_TRUE(std::filesystem::exists(dir / "base" / name)) << name;
    PatternParams params;
    params.size = 128;
    const ReliefTexture expected = makePattern("base", params);
    // Same defaults everywhere: the file is the library's map quantised to 16 bits (half a step).
    EXPECT_LE(test::maxAbsDiff(readImage(dir / "base" / "depth.png"), expected.depth), 0.5 / 65535 + 1e-7);
}

TEST(Cli, UnknownPatternIsInvalidInput) {
    test::ScratchDir dir("cli-unknown");
    const auto result = runCli("pattern tweed -o " + quoted(dir / "out"));
    EXPECT_EQ(result.exitCode, 3);
    EXPECT_NE(result.output.find("tweed"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(Cli, ComposeWritesASetAndWarnsAboutFractionalTiling) {
    test::ScratchDir dir("cli-compose");
    test::writeBytes(dir / "m.json", R"({"resolution": 64, "layers": [
        {"pattern": "base", "size": 64}, {"pattern": "metal", "size": 64, "tiling": 2.5, "weight_depth": 0.3, "weight_normal": 0.3}]})");
    const auto result = runCli("compose " + quoted(dir / "m.json") + " -o " + quoted(dir / "out"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_NE(result.output.find("warning"), std::string::npos);
    EXPECT_NE(result.output.find("2.5"), std::string::npos);
    const auto sidecar = readSidecar(dir / "out");
    EXPECT_EQ(sidecar["source"]["kind"], "meta-relief");
    EXPECT_EQ(readImageInfo(dir / "out" / "packed.png").channels, 4);
}

TEST(Cli, ARejectedMaterialWritesNothing) {
    test::ScratchDir dir("cli-reject");
    test::writeBytes(dir / "m.json",
                     R"({"layers": [{"pattern": "base", "size": 64, "weight_depth": -0.3}]})");
    const auto result = runCli("compose " + quoted(dir / "m.json") + " -o " + quoted(dir / "out"));
    EXPECT_EQ(result.exitCode, 3);
    EXPECT_NE(result.output.find("layers[0].weight_depth"), std::string::npos) << result.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
    EXPECT_EQ(test::countEntries(dir.path()), 1);
}

TEST(Cli, ImportErrorsAreDocumentedCodesAndLeaveNothing) {
    test::ScratchDir dir("cli-import");
    EXPECT_EQ(
        runCli("import --height " + quoted(dir / "missing.png") + " -o " + quoted(dir / "out")).exitCode, 2);
    test::writeBytes(dir / "text.png", "this is a text file, not a PNG\n");
    const auto notImage =
        runCli("import --height " + quoted(dir / "text.png") + " -o " + quoted(dir / "out"));
    EXPECT_EQ(notImage.exitCode, 3);
    EXPECT_NE(notImage.output.find("text.png"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
    EXPECT_EQ(runCli("import -o " + quoted(dir / "out")).exitCode, 1);  // no depth input
}

TEST(Cli, ImportReadsAnRgbHeightThroughItsLuminanceWithANote) {
    test::ScratchDir dir("cli-rgb");
    writePng(dir / "h.png", Image(64, 64, 3, 0.5f));
    const auto result = runCli("import --height " + quoted(dir / "h.png") + " -o " + quoted(dir / "out"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_NE(result.output.find("luminance"), std::string::npos) << result.output;
}

TEST(Cli, ImportNeverOverwritesItsInput) {
    test::ScratchDir dir("cli-overwrite");
    const ReliefTexture texture = makePattern("base", {64, 1, 0.08});
    writePng(dir / "depth.png", texture.depth, {PngBitDepth::Eight, true});
    const Image before = readImage(dir / "depth.png");
    const auto result = runCli("import --depth " + quoted(dir / "depth.png") + " -o " + quoted(dir.path()));
    EXPECT_EQ(result.exitCode, 2);
    EXPECT_NE(result.output.find("refusing to overwrite"), std::string::npos) << result.output;
    // The 8-bit input would have been replaced by a 16-bit file: it is still the 8-bit original.
    EXPECT_EQ(readImageInfo(dir / "depth.png").bitDepth, 8);
    EXPECT_EQ(readImage(dir / "depth.png"), before);
    EXPECT_EQ(test::countEntries(dir.path()), 1);
}

TEST(Cli, CheckNormalReportsTheConvention) {
    test::ScratchDir dir("cli-check");
    const ReliefTexture texture = makePattern("stone-bricks", {128, 1, 0.08});
    writePng(dir / "depth.png", texture.depth);
    writePng(dir / "gl.png", encodeNormals(texture.normal));
    writePng(dir / "dx.png", encodeNormals(decodeNormals(encodeNormals(texture.normal), true)));
    const auto gl =
        runCli("import --depth " + quoted(dir / "depth.png") + " --check-normal " + quoted(dir / "gl.png"));
    EXPECT_EQ(gl.exitCode, 0) << gl.output;
    EXPECT_NE(gl.output.find("OpenGL"), std::string::npos) << gl.output;
    const auto dx =
        runCli("import --depth " + quoted(dir / "depth.png") + " --check-normal " + quoted(dir / "dx.png"));
    EXPECT_NE(dx.output.find("DirectX"), std::string::npos) << dx.output;
    // --normal-y auto converts the DirectX map: the imported normals match the OpenGL original.
    const auto imported = runCli("import --depth " + quoted(dir / "depth.png") + " --normal " +
                                 quoted(dir / "dx.png") + " --normal-y auto -o " + quoted(dir / "set"));
    ASSERT_EQ(imported.exitCode, 0) << imported.output;
    EXPECT_LE(test::maxAbsDiff(readTextureSet(dir / "set").normal, texture.normal), 1e-4);
}

TEST(Cli, InfoDescribesASetAndAnImage) {
    test::ScratchDir dir("cli-info");
    ASSERT_EQ(runCli("pattern fabric --size 64 --depth-scale 0.05 -o " + quoted(dir / "set")).exitCode, 0);
    const auto text = runCli("info " + quoted(dir / "set"));
    EXPECT_EQ(text.exitCode, 0);
    EXPECT_NE(text.output.find("0.05"), std::string::npos) << text.output;
    const auto json = runCli("info --json " + quoted(dir / "set" / "strata.json"));
    EXPECT_EQ(nlohmann::json::parse(json.output)["depth_scale"].get<double>(), 0.05);
    const auto image = runCli("info " + quoted(dir / "set" / "packed.png"));
    EXPECT_NE(image.output.find("64x64"), std::string::npos) << image.output;
    EXPECT_EQ(runCli("info " + quoted(dir / "nothing")).exitCode, 2);
}

TEST(Cli, TheShippedExamplesCompose) {
    test::ScratchDir dir("cli-examples");
    for (const char* name : {"shaped_fabric", "shaped_metal", "three_layers"}) {
        const std::string material = std::string(STRATA_SOURCE_DIR) + "/examples/" + name + ".json";
        const auto result = runCli("compose \"" + material + "\" --resolution 128 -o " + quoted(dir / name));
        EXPECT_EQ(result.exitCode, 0) << name << ": " << result.output;
        EXPECT_TRUE(std::filesystem::exists(dir / name / "packed.png")) << name;
    }
}

}  // namespace
}  // namespace strata
