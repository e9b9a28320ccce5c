// The `strata` CLI end to end: documented exit codes, outputs, and nothing written on failure.
#include "test_support.h"

#include "strata/image/image_io.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/relief/patterns.h"
#include "strata/relief/texture_set.h"
#include "strata/scene/material.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace strata {
namespace {

using test::runCli;

using test::quoted;

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

nlohmann::json readJson(const std::filesystem::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

// The B channel of packed.png as a 1-channel image.
Image packedAo(const std::filesystem::path& packedPng) {
    const Image packed = readImage(packedPng);
    Image ao(packed.width(), packed.height(), 1);
    for (int y = 0; y < packed.height(); ++y)
        for (int x = 0; x < packed.width(); ++x) ao.at(x, y) = packed.at(x, y, 2);
    return ao;
}

TEST(Cli, AoBakesADepthMapAndRecordsHowInItsSidecar) {
    test::ScratchDir dir("cli-ao");
    ASSERT_EQ(runCli("pattern base --size 64 --depth-scale 0.05 -o " + quoted(dir / "set")).exitCode, 0);
    const auto result = runCli("ao " + quoted(dir / "set" / "depth.png") + " -o " + quoted(dir / "ao.png") +
                               " --depth-scale 0.2 --radius 0.5 --directions 16");
    ASSERT_EQ(result.exitCode, 0) << result.output;
    const ImageInfo info = readImageInfo(dir / "ao.png");
    EXPECT_EQ(info.width, 64);
    EXPECT_EQ(info.height, 64);
    EXPECT_EQ(info.channels, 1);
    EXPECT_EQ(info.bitDepth, 16);

    const auto sidecar = readJson(dir / "ao.png.json");
    EXPECT_EQ(sidecar["format"], "strata.ao-map");
    EXPECT_EQ(sidecar["format_version"], 1);
    EXPECT_EQ(sidecar["depth_scale"].get<double>(), 0.2);
    EXPECT_EQ(sidecar["radius"].get<double>(), 0.5);
    EXPECT_EQ(sidecar["directions"], 16);
    EXPECT_EQ(sidecar["method"], "sweep");
    EXPECT_EQ(sidecar["filter"], "auto");
    EXPECT_EQ(sidecar["normalize"], "open");
    EXPECT_EQ(sidecar["definition"], AoRecord{}.definition);
    EXPECT_EQ(sidecar["size"], nlohmann::json::array({64, 64}));
    EXPECT_EQ(sidecar["input"]["file"], (dir / "set" / "depth.png").string());
    EXPECT_EQ(sidecar["input"]["encoding"], "depth");

    // The library's bake of the same file, quantised to 16 bits: within half a step (plus float noise).
    AoParams params;
    params.depthScale = 0.2;
    params.radius = 0.5;
    params.directions = 16;
    const Image expected = bakeAo(readDepthMap(dir / "set" / "depth.png", DepthEncoding::Depth), params);
    EXPECT_LE(test::maxAbsDiff(readImage(dir / "ao.png"), expected), 0.5 / 65535 + 1e-6);

    // A texture set as input: its depth map at its recorded depth scale.
    const auto fromSet = runCli("ao " + quoted(dir / "set") + " -o " + quoted(dir / "set-ao.png") +
                                " --directions 16 --method paper");
    ASSERT_EQ(fromSet.exitCode, 0) << fromSet.output;
    const auto setSidecar = readJson(dir / "set-ao.png.json");
    EXPECT_EQ(setSidecar["depth_scale"].get<double>(), 0.05);
    EXPECT_EQ(setSidecar["method"], "paper");
    EXPECT_EQ(setSidecar["radius"].get<double>(), 1.0);
}

TEST(Cli, AoErrorsAreDocumentedCodesAndLeaveNothing) {
    test::ScratchDir dir("cli-ao-errors");
    ASSERT_EQ(runCli("pattern base --size 64 -o " + quoted(dir / "set")).exitCode, 0);
    const std::string depth = quoted(dir / "set" / "depth.png");
    const std::string out = " -o " + quoted(dir / "ao.png");
    auto nothingWritten = [&] {
        return !std::filesystem::exists(dir / "ao.png") && !std::filesystem::exists(dir / "ao.png.json") &&
               test::countEntries(dir.path()) == 1;
    };
    // A bare map does not say its depth scale: usage.
    const auto noScale = runCli("ao " + depth + out);
    EXPECT_EQ(noScale.exitCode, 1);
    EXPECT_NE(noScale.output.find("--depth-scale"), std::string::npos) << noScale.output;
    EXPECT_EQ(runCli("ao " + depth + out + " --depth-scale 0.1 --method fast").exitCode, 1);
    EXPECT_EQ(runCli("ao " + depth + out + " --depth-scale 0.1 --radius 17").exitCode, 1);
    EXPECT_EQ(runCli("ao " + depth + out + " --depth-scale 0").exitCode, 1);
    EXPECT_EQ(runCli("ao " + depth + " -o " + quoted(dir / "ao.exr") + " --depth-scale 0.1").exitCode, 1);
    EXPECT_EQ(runCli("ao " + quoted(dir / "set") + out + " --height").exitCode, 1);
    EXPECT_TRUE(nothingWritten());

    const auto missing = runCli("ao " + quoted(dir / "missing.png") + out + " --depth-scale 0.1");
    EXPECT_EQ(missing.exitCode, 2);
    EXPECT_NE(missing.output.find("missing.png"), std::string::npos) << missing.output;
    EXPECT_TRUE(nothingWritten());

    test::writeBytes(dir / "text.png", "not a PNG\n");
    EXPECT_EQ(runCli("ao " + quoted(dir / "text.png") + out + " --depth-scale 0.1").exitCode, 3);
    std::filesystem::remove(dir / "text.png");
    EXPECT_TRUE(nothingWritten());

    // The output may not be the input.
    const Image before = readImage(dir / "set" / "depth.png");
    const auto overwrite = runCli("ao " + depth + " -o " + depth + " --depth-scale 0.1");
    EXPECT_EQ(overwrite.exitCode, 2);
    EXPECT_NE(overwrite.output.find("refusing to overwrite"), std::string::npos) << overwrite.output;
    EXPECT_EQ(readImage(dir / "set" / "depth.png"), before);
    EXPECT_FALSE(std::filesystem::exists(dir / "set" / "depth.png.json"));
}

TEST(Cli, ComposeBakesTheMaterialsAoIntoAoPngAndPackedB) {
    test::ScratchDir dir("cli-compose-ao");
    test::writeBytes(dir / "m.json", R"({"resolution": 32, "depth_scale": 0.1, "layers": [
        {"pattern": "base", "size": 64}, {"pattern": "metal", "size": 64, "tiling": 2, "weight_depth": 0.3, "weight_normal": 0.3}]})");
    const auto exact = runCli("compose " + quoted(dir / "m.json") + " -o " + quoted(dir / "exact"));
    ASSERT_EQ(exact.exitCode, 0) << exact.output;
    ASSERT_TRUE(std::filesystem::exists(dir / "exact" / "ao.png"));
    const Image ao = readImage(dir / "exact" / "ao.png");
    EXPECT_EQ(ao.width(), 32);
    // Both files quantise the same float map to 16 bits: identical.
    EXPECT_EQ(packedAo(dir / "exact" / "packed.png"), ao);
    auto sidecar = readSidecar(dir / "exact");
    EXPECT_EQ(sidecar["ao"]["method"], "sweep");
    EXPECT_EQ(sidecar["ao"]["radius"].get<double>(), 1.0);
    EXPECT_EQ(sidecar["ao"]["directions"], 50);
    EXPECT_EQ(sidecar["ao"]["baked_at_depth_scale"].get<double>(), 0.1);
    EXPECT_EQ(sidecar["source"]["ao"]["mode"], "exact");

    const auto multiply = runCli("compose " + quoted(dir / "m.json") +
                                 " --ao multiply --ao-method brute -o " + quoted(dir / "multiply"));
    ASSERT_EQ(multiply.exitCode, 0) << multiply.output;
    EXPECT_EQ(packedAo(dir / "multiply" / "packed.png"), readImage(dir / "multiply" / "ao.png"));
    sidecar = readSidecar(dir / "multiply");
    EXPECT_EQ(sidecar["ao"]["method"], "multiply of per-layer brute");
    EXPECT_EQ(sidecar["source"]["ao"]["mode"], "multiply");
    ASSERT_EQ(sidecar["source"]["ao"]["layers"].size(), 2u);
    // S_2 = 0.1 * 0.3 / 1.3 * 2, R_2 = 1 * 2 (meta_relief_ao.h).
    EXPECT_NEAR(sidecar["source"]["ao"]["layers"][1]["depth_scale"].get<double>(), 0.06 / 1.3, 1e-12);
    EXPECT_EQ(sidecar["source"]["ao"]["layers"][1]["radius"].get<double>(), 2.0);

    test::writeBytes(dir / "none.json", R"({"ao": "none", "layers": [{"pattern": "base", "size": 64}]})");
    const auto none = runCli("compose " + quoted(dir / "none.json") + " -o " + quoted(dir / "none"));
    ASSERT_EQ(none.exitCode, 0) << none.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "none" / "ao.png"));
    EXPECT_EQ(packedAo(dir / "none" / "packed.png"), Image(64, 64, 1, 1.0f));
    EXPECT_TRUE(readSidecar(dir / "none")["ao"].is_null());
    EXPECT_EQ(readSidecar(dir / "none")["source"]["ao"], "none");

    EXPECT_EQ(
        runCli("compose " + quoted(dir / "m.json") + " --ao product -o " + quoted(dir / "bad")).exitCode, 1);
    EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
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
