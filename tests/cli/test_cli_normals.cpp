// Normal-map safety and AO on imported sets, through the built `strata`: every case names its exit code
// (docs/cli.md: 1 usage, 3 invalid input) and its message.
#include "test_support.h"

#include "strata/image/image_io.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>

namespace strata {
namespace {

namespace fs = std::filesystem;
using test::runCli;

using test::quoted;

void expectFailure(const std::string& args, int exitCode, const std::string& message) {
    const auto result = runCli(args);
    EXPECT_EQ(result.exitCode, exitCode) << args << "\n" << result.output;
    EXPECT_NE(result.output.find(message), std::string::npos) << args << "\n" << result.output;
}

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

// A 64^2 mini-bricks set in DIR/set, and its normal map with green flipped (DirectX) in DIR/dx.png.
void makeInputs(const test::ScratchDir& dir) {
    ASSERT_EQ(runCli("pattern mini-bricks --size 64 -o " + quoted(dir / "set")).exitCode, 0);
    Image normal = readImage(dir / "set" / "normal.png");
    for (int y = 0; y < normal.height(); ++y)
        for (int x = 0; x < normal.width(); ++x) normal.at(x, y, 1) = 1.0f - normal.at(x, y, 1);
    writePng(dir / "dx.png", normal);
}

Image filled(float r, float g, float b) {
    Image image(64, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            image.at(x, y, 0) = r;
            image.at(x, y, 1) = g;
            image.at(x, y, 2) = b;
        }
    return image;
}

TEST(CliNormals, ExplicitUpOnADirectXMapIsExit3WithTheOverride) {
    const test::ScratchDir dir("cli_normals_up");
    makeInputs(dir);
    const std::string base =
        "import --depth " + quoted(dir / "set" / "depth.png") + " --normal " + quoted(dir / "dx.png");
    expectFailure(
        base + " --normal-y up -o " + quoted(dir / "out"), 3,
        "dx.png: read as up (OpenGL), but its gradient says DirectX (green down): y is opposite to the "
        "depth map's normals (r = -1.00), more than 0.60 against; use --normal-y down or auto, or add "
        "--force to keep --normal-y up");
    EXPECT_FALSE(fs::exists(dir / "out"));
    // --force keeps it, with the same text as a warning.
    const auto forced = runCli(base + " --normal-y up --force -o " + quoted(dir / "forced"));
    EXPECT_EQ(forced.exitCode, 0) << forced.output;
    EXPECT_NE(forced.output.find("read as up (OpenGL), but its gradient says DirectX"), std::string::npos)
        << forced.output;
    EXPECT_EQ(readJson(dir / "forced" / "strata.json")["normal"]["source"], "file (OpenGL)");
    // The default is auto: detected and converted.
    const auto automatic = runCli(base + " -o " + quoted(dir / "auto"));
    EXPECT_EQ(automatic.exitCode, 0) << automatic.output;
    EXPECT_NE(automatic.output.find("dx.png: normal_y auto: DirectX (green down)"), std::string::npos)
        << automatic.output;
    EXPECT_EQ(readJson(dir / "auto" / "strata.json")["normal"]["source"],
              "file (DirectX, converted to OpenGL)");
    // The converted map is the pattern's own up to 16-bit quantisation of 1 - g (2 steps of 1/65535).
    EXPECT_LT(test::maxAbsDiff(readImage(dir / "auto" / "normal.png"), readImage(dir / "set" / "normal.png")),
              3.0 / 65535.0);
}

TEST(CliNormals, OpenGLMapReadAsDownIsExit3) {
    const test::ScratchDir dir("cli_normals_down");
    makeInputs(dir);
    expectFailure(
        "import --depth " + quoted(dir / "set" / "depth.png") + " --normal " +
            quoted(dir / "set" / "normal.png") + " --normal-y down -o " + quoted(dir / "out"),
        3,
        "normal.png: read as down (DirectX), but its gradient says OpenGL (green up): y agrees with the "
        "depth map's normals (r = 1.00), more than 0.60 against; use --normal-y up or auto, or add "
        "--force to keep --normal-y down");
}

TEST(CliNormals, AutoOnAFlatDepthFallsBackToUpWithANote) {
    const test::ScratchDir dir("cli_normals_flat");
    makeInputs(dir);
    Image flat(64, 64, 1);
    writePng(dir / "flat.png", flat);
    const auto result = runCli("import --depth " + quoted(dir / "flat.png") + " --normal " +
                               quoted(dir / "dx.png") + " -o " + quoted(dir / "out"));
    EXPECT_EQ(result.exitCode, 0) << result.output;
    EXPECT_NE(
        result.output.find("dx.png: normal_y auto: unknown: the depth map is flat, so there is nothing to "
                           "compare the normal map with; read as up (OpenGL)"),
        std::string::npos)
        << result.output;
    // --check-normal cannot tell either: exit 3 (scripts branch on it).
    expectFailure("import --check-normal " + quoted(dir / "dx.png") + " --depth " + quoted(dir / "flat.png"),
                  3, "dx.png: cannot tell the convention: unknown: the depth map is flat");
}

TEST(CliNormals, ObviouslyWrongMapsAreExit3) {
    const test::ScratchDir dir("cli_normals_wrong");
    makeInputs(dir);
    writePng(dir / "grey.png", filled(0.3f, 0.3f, 0.3f));
    writePng(dir / "black.png", filled(0.0f, 0.0f, 0.0f));
    writePng(dir / "signed.png", filled(0.4f, 0.7f, 0.0f));
    const std::string depth = " --depth " + quoted(dir / "set" / "depth.png") + " -o " + quoted(dir / "out");
    expectFailure(
        "import --normal " + quoted(dir / "grey.png") + depth, 3,
        "grey.png: not a normal map: 100 % of its texels are grey (r = g = b); is it a height or depth "
        "map?");
    expectFailure("import --normal " + quoted(dir / "black.png") + depth, 3,
                  "black.png: not a normal map: 100 % of its texels are grey");
    expectFailure(
        "import --normal " + quoted(dir / "signed.png") + depth, 3,
        "signed.png: not a tangent-space normal map: 100 % of its normals point into the surface (z < "
        "0); is it signed, black or empty?");
    // Normals given as height.
    expectFailure("import --height " + quoted(dir / "set" / "normal.png") + " -o " + quoted(dir / "out"), 3,
                  "normal.png: looks like a tangent-space normal map (mean r, g, b = 0.5");
    expectFailure(
        "ao " + quoted(dir / "set" / "normal.png") + " --depth-scale 0.1 -o " + quoted(dir / "ao.png"), 3,
        "not a height or depth map; give it as the normal map");
    EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(CliNormals, AoIntoASetAndImportAo) {
    const test::ScratchDir dir("cli_normals_ao");
    makeInputs(dir);
    ASSERT_EQ(runCli("import --depth " + quoted(dir / "set" / "depth.png") + " --depth-scale 0.08 -o " +
                     quoted(dir / "imp"))
                  .exitCode,
              0);
    EXPECT_TRUE(readJson(dir / "imp" / "strata.json")["ao"].is_null());
    const auto updated = runCli("ao " + quoted(dir / "imp"));
    EXPECT_EQ(updated.exitCode, 0) << updated.output;
    const nlohmann::json sidecar = readJson(dir / "imp" / "strata.json");
    EXPECT_EQ(sidecar["ao"]["file"], "ao.png");
    EXPECT_EQ(sidecar["ao"]["directions"], 50);
    EXPECT_EQ(sidecar["packed"]["ao_channel"], "ao.png");
    const Image ao = readImage(dir / "imp" / "ao.png");
    const Image packed = readImage(dir / "imp" / "packed.png");
    for (int y = 0; y < ao.height(); ++y)
        for (int x = 0; x < ao.width(); ++x)
            ASSERT_EQ(packed.at(x, y, 2), ao.at(x, y)) << x << "," << y;  // the same 16-bit values
    // import --ao bakes the same AO (same call, same defaults, same S): identical files.
    ASSERT_EQ(runCli("import --ao --depth " + quoted(dir / "set" / "depth.png") + " --depth-scale 0.08 -o " +
                     quoted(dir / "impao"))
                  .exitCode,
              0);
    EXPECT_EQ(test::maxAbsDiff(readImage(dir / "impao" / "ao.png"), ao), 0.0);
    EXPECT_EQ(test::maxAbsDiff(readImage(dir / "impao" / "packed.png"), packed), 0.0);
    // A loose map cannot be updated in place; a set takes its own S.
    expectFailure("ao " + quoted(dir / "set" / "depth.png") + " --depth-scale 0.1", 1,
                  "ao: give -o AO.png (only a texture set can be updated in place");
    expectFailure("ao " + quoted(dir / "imp") + " --depth-scale 0.1", 1,
                  "ao: --depth-scale cannot be given when updating a texture set");
}

}  // namespace
}  // namespace strata
