// `strata render --gdm` end to end: on --mesh quad its debug outputs are the GDM verification scene's
// (CONVENTIONS §8) and must be `strata gdm trace --gl`'s pictures exactly; shaded pictures on a mesh are
// drawn over the background; the documented errors write nothing.
#include "test_support.h"

#include "strata/image/image_io.h"
#include "strata/image/srgb.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace strata {
namespace {

namespace fs = std::filesystem;
using test::runCli;

#define SKIP_WITHOUT_GL(result) \
    if ((result).exitCode == 5) GTEST_SKIP() << "no OpenGL context: " << (result).output

using test::quoted;

// A tiny weave asset for the suite: 16 x 16 x 4 voxels, 8 x 16 directions, rank 8, with the raw GDM; and a
// copy baked without it.
class CliRenderGdm : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir = std::make_unique<test::ScratchDir>("cli-render-gdm");
        for (const char* raw : {" --keep-raw", ""}) {
            const std::string name = *raw ? "weave" : "noraw";
            const auto bake = runCli("gdm bake --meso weave --size 16x16x4 --dirs 8x16" + std::string(raw) +
                                     " -o " + quoted(*dir / name));
            ASSERT_EQ(bake.exitCode, 0) << bake.output;
        }
    }
    static void TearDownTestSuite() { dir.reset(); }
    static std::unique_ptr<test::ScratchDir> dir;
};
std::unique_ptr<test::ScratchDir> CliRenderGdm::dir;

// The verification scene's view, as `strata gdm trace` has it by default, at 64 x 48.
const std::string kView =
    " --eye 0.5,-0.6314,1.1314 --target 0.5,0.5,0 --fov 45 --light 0.5,-0.6,1.1 --size 64x48";

TEST_F(CliRenderGdm, QuadOutputsAreTheVerificationScenesOfGdmTrace) {
    const fs::path weave = *dir / "weave";
    // --gdm-rank raw is trace's --gdm raw; the default rank is the stored SVD, trace's --gdm svd.
    for (const auto& [rank, gdm] : {std::pair{"", "svd"}, std::pair{" --gdm-rank raw", "raw"}}) {
        for (const char* output : {"uvw", "shadow", "mask"}) {
            SCOPED_TRACE(std::string(output) + " " + gdm);
            const fs::path a = *dir / (std::string("render_") + output + "_" + gdm + ".png");
            const fs::path b = *dir / (std::string("trace_") + output + "_" + gdm + ".png");
            const auto render = runCli("render --gdm " + quoted(weave) + rank + " --mesh quad --output " +
                                       output + kView + " -o " + quoted(a));
            SKIP_WITHOUT_GL(render);
            ASSERT_EQ(render.exitCode, 0) << render.output;
            const auto trace = runCli("gdm trace " + quoted(weave) + " --gl --gdm " + gdm + " --output " +
                                      output + kView + " -o " + quoted(b));
            ASSERT_EQ(trace.exitCode, 0) << trace.output;
            // §8: 16-bit PNGs, the same values to the bit (the same renderer on the same shell).
            EXPECT_EQ(readImageInfo(a).bitDepth, 16);
            const Image x = readImage(a), y = readImage(b);
            ASSERT_EQ(x.channels(), y.channels());
            EXPECT_EQ(test::maxAbsDiff(x, y), 0.0);
            if (std::string(output) == "mask") {
                double hits = 0.0;
                for (int row = 0; row < 48; ++row)
                    for (int col = 0; col < 64; ++col) hits += double(x.at(col, row));
                EXPECT_GT(hits, 64 * 48 / 5);  // the weave covers about half of the picture
            }
        }
    }
}

TEST_F(CliRenderGdm, ShadedMeshIsDrawnOverTheBackground) {
    const fs::path out = *dir / "sphere.png";
    const auto render =
        runCli("render --gdm " + quoted(*dir / "weave") +
               " --mesh sphere --tessellation 4 --tiling 2 --size 64x48 --samples 4 -o " + quoted(out));
    SKIP_WITHOUT_GL(render);
    ASSERT_EQ(render.exitCode, 0) << render.output;
    EXPECT_NE(render.output.find("GDM"), std::string::npos) << render.output;
    EXPECT_EQ(readImageInfo(out).bitDepth, 8);
    const Image picture = readImage(out);
    // The corner is the default background (0.16, 0.17, 0.19), to one 8-bit step (the dither's); the centre
    // is the weave.
    EXPECT_NEAR(picture.at(0, 0, 0), 0.16f, 1.0f / 255.0f + 1e-6f);
    EXPECT_NEAR(picture.at(0, 0, 2), 0.19f, 1.0f / 255.0f + 1e-6f);
    double differs = 0.0;
    for (int y = 16; y < 32; ++y)
        for (int x = 24; x < 40; ++x) differs += std::abs(picture.at(x, y, 0) - 0.16f) > 0.02f ? 1.0 : 0.0;
    EXPECT_GT(differs, 16 * 16 * 0.5);
}

TEST_F(CliRenderGdm, LightFrameChangesOnlyTheShadowsOfAStretchedMesh) {
    // The sphere at tiling 2 has tiles stretched 2 : 1 (u runs 3.14 around, v 1.57 pole to pole), where the
    // Jacobian's light direction differs from the tangent frame's; the hits do not change.
    Image pictures[2][2];
    for (int f = 0; f < 2; ++f)
        for (int o = 0; o < 2; ++o) {
            const char* frame = f == 0 ? "tangent" : "jacobian";
            const char* output = o == 0 ? "mask" : "shadow";
            const fs::path out = *dir / (std::string("frame_") + frame + "_" + output + ".png");
            const auto render =
                runCli("render --gdm " + quoted(*dir / "weave") +
                       " --mesh sphere --tessellation 4 --tiling 2 --size 96x96 --gdm-light-frame " + frame +
                       " --output " + output + " -o " + quoted(out));
            SKIP_WITHOUT_GL(render);
            ASSERT_EQ(render.exitCode, 0) << render.output;
            pictures[f][o] = readImage(out);
        }
    EXPECT_EQ(test::maxAbsDiff(pictures[0][0], pictures[1][0]), 0.0);
    int differ = 0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x) differ += pictures[0][1].at(x, y) != pictures[1][1].at(x, y);
    EXPECT_GT(differ, 0);
    std::printf("light frame: %d of %d shadow pixels differ\n", differ, 96 * 96);
}

// A scene file for the environment tests: the weave on a sphere, the point light off (colour 0), so that the
// environment alone lights it; `extra` adds keys.
fs::path environmentScene(const fs::path& dir, const std::string& name, const std::string& extra) {
    const fs::path path = dir / (name + ".json");
    test::writeBytes(path,
                     R"({"mesh": "sphere", "tessellation": 4, "tiling": 2, "size": [64, 48], "samples": 1,
        "light": {"color": [0, 0, 0]}, "background": [0, 0, 0])" +
                         extra + "}");
    return path;
}

TEST_F(CliRenderGdm, TheEnvironmentLightsTheGdm) {
    // A constant environment of radiance 0.25 as an EXR (CONVENTIONS §9), and the built-in sunset sky.
    const fs::path exr = *dir / "grey.exr";
    Image grey(16, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x)
            for (int c = 0; c < 3; ++c) grey.at(x, y, c) = 0.25f;
    writeExr(exr, grey);
    const std::string weave = " --gdm " + quoted(*dir / "weave");
    const auto render = [&](const std::string& name, const std::string& args, const std::string& keys = "") {
        const fs::path out = *dir / (name + ".png");
        const auto result = runCli("render " + quoted(environmentScene(dir->path(), name, keys)) + args +
                                   " -o " + quoted(out));
        return std::pair{result, out};
    };
    // Without an environment and with the light off, the ambient term alone; with one, the environment
    // replaces it.
    const auto [ambient, ambientPng] = render("ambient", weave);
    SKIP_WITHOUT_GL(ambient);
    ASSERT_EQ(ambient.exitCode, 0) << ambient.output;
    const auto [sky, skyPng] = render("sky", weave + " --env sky-sunset");
    ASSERT_EQ(sky.exitCode, 0) << sky.output;
    EXPECT_NE(sky.output.find("sky-sunset (RTV rank 4, 1 bounce)"), std::string::npos) << sky.output;
    EXPECT_GT(test::maxAbsDiff(readImage(ambientPng), readImage(skyPng)), 0.05);
    // Radiance is linear in the environment: twice the intensity, twice the linear radiance (the PNG is
    // sRGB, 8 bits: compared where it is neither dark nor clipped).
    const auto [twice, twicePng] = render("twice", weave + " --env sky-sunset --env-intensity 2");
    ASSERT_EQ(twice.exitCode, 0) << twice.output;
    const Image one = readImage(skyPng), two = readImage(twicePng);
    int compared = 0;
    double worst = 0.0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) {
                const double a = srgbToLinear(double(one.at(x, y, c))),
                             b = srgbToLinear(double(two.at(x, y, c)));
                if (a < 0.05 || b > 0.9) continue;
                worst = std::max(worst, std::abs(b / a - 2.0));
                ++compared;
            }
    EXPECT_GT(compared, 200);
    // 8-bit rounding of a value >= 0.05 linear (about 0.25 in sRGB) is at most 1/255 in sRGB, 2% relative.
    EXPECT_LT(worst, 0.1);
    // Turning the sunset sky (its sun low at one azimuth) moves the light; a whole turn does not.
    const auto [turned, turnedPng] = render(
        "turned", "",
        R"(, "gdm": ")" + (*dir / "weave").string() + R"(", "env": "sky-sunset", "env_rotation": 120)");
    ASSERT_EQ(turned.exitCode, 0) << turned.output;
    EXPECT_GT(test::maxAbsDiff(readImage(turnedPng), one), 0.05);
    const auto [whole, wholePng] = render("whole", weave + " --env sky-sunset --env-rotation 360");
    ASSERT_EQ(whole.exitCode, 0) << whole.output;
    EXPECT_LE(test::maxAbsDiff(readImage(wholePng), one), 1.0 / 255.0 + 1e-6);
    // A glossy term adds light (white, under the positive overcast sky) and is named in the summary.
    const auto [matte, mattePng] = render("matte", weave + " --env sky-overcast");
    ASSERT_EQ(matte.exitCode, 0) << matte.output;
    const auto [glossy, glossyPng] = render("glossy", weave + " --env sky-overcast --env-specular 0.5");
    ASSERT_EQ(glossy.exitCode, 0) << glossy.output;
    EXPECT_NE(glossy.output.find("glossy 0.5 s 8"), std::string::npos) << glossy.output;
    double added = 0.0;
    const Image mattePicture = readImage(mattePng), glossyPicture = readImage(glossyPng);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            added += double(glossyPicture.at(x, y, 1)) - double(mattePicture.at(x, y, 1));
    EXPECT_GT(added, 0.0);
    // An EXR, on the asset without its raw GDM (the radiance transfer's visibility is baked again from its
    // solid). The EXR is an input: never overwritten.
    const auto [fromExr, exrPng] =
        render("exr", " --gdm " + quoted(*dir / "noraw") + " --env " + quoted(exr) + " --env-bounces 0");
    ASSERT_EQ(fromExr.exitCode, 0) << fromExr.output;
    EXPECT_NE(fromExr.output.find("0 bounces"), std::string::npos) << fromExr.output;
    const auto before = fs::file_size(exr);
    const auto overwrite =
        runCli("render" + weave + " --env " + quoted(exr) + " --mesh quad --size 16x16 -o " + quoted(exr));
    EXPECT_EQ(overwrite.exitCode, 2) << overwrite.output;
    EXPECT_EQ(fs::file_size(exr), before);
}

TEST_F(CliRenderGdm, ErrorsHaveTheirCodesAndWriteNothing) {
    const fs::path out = *dir / "error.png";
    const std::string small = " --mesh quad --size 16x16 -o " + quoted(out);
    const std::string weave = " --gdm " + quoted(*dir / "weave");
    struct Case {
        std::string args;
        int code;
        std::string says;
    };
    const Case cases[] = {
        // Usage (1): a malformed rank, a material or a depth map with a GDM, an unknown technique.
        {weave + " --gdm-rank two" + small, 1, "--gdm-rank"},
        {weave + " --material stone-bricks" + small, 1, "--material"},
        {weave + " --gdm-technique exact" + small, 1, "--gdm-technique"},
        {weave + " --gdm-light-frame sideways" + small, 1, "--gdm-light-frame"},
        // The environment's flags: without a GDM, out of range (each names its flag).
        {" --env sky-clear" + small, 1, "give --gdm"},
        {weave + " --env sky-clear --env-rank 0" + small, 1, "--env-rank"},
        {weave + " --env sky-clear --env-bounces 9" + small, 1, "--env-bounces"},
        {weave + " --env sky-clear --env-intensity -1" + small, 1, "--env-intensity"},
        {weave + " --env sky-clear --env-specular -1" + small, 1, "--env-specular"},
        {weave + " --env sky-clear --env-shininess 100" + small, 1, "--env-shininess"},
        // A flag out of range or out of place is usage too, and names the flag, not the scene key.
        {weave + " --output uv" + small, 1, "--output: uv is a relief output"},
        {" --gdm-technique refine" + small, 1, "give --gdm"},
        {weave + " --shell-thickness 0" + small, 1, "--shell-thickness: must be > 0"},
        // Invalid input (3): an environment that is neither a built-in sky nor a file.
        {weave + " --env sky-mars" + small, 3, "sky-mars"},
        // Invalid input (3): neither an asset nor a built-in, a rank above the stored one, raw without
        // raw.f32.
        {" --gdm no-such-meso" + small, 3, "no-such-meso"},
        {weave + " --gdm-rank 9" + small, 3, "gdm_rank 9"},
        {" --gdm " + quoted(*dir / "noraw") + " --gdm-rank raw" + small, 3, "raw"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const auto result = runCli("render" + c.args);
        SKIP_WITHOUT_GL(result);
        EXPECT_EQ(result.exitCode, c.code) << result.output;
        EXPECT_NE(result.output.find(c.says), std::string::npos) << result.output;
        EXPECT_FALSE(fs::exists(out));
    }
    // `strata gdm trace --light-frame` is the OpenGL renderer's (1 without --gl), tangent or jacobian.
    for (const std::string& args :
         {std::string(" --light-frame jacobian"), std::string(" --gl --light-frame world")}) {
        const auto trace =
            runCli("gdm trace " + quoted(*dir / "weave") + args + " --output mask -o " + quoted(out));
        EXPECT_EQ(trace.exitCode, 1) << trace.output;
        EXPECT_NE(trace.output.find("--light-frame"), std::string::npos) << trace.output;
        EXPECT_FALSE(fs::exists(out));
    }
    // A directory that is not an asset (2), and an output that is one of the asset's files: its .json
    // extension is refused before any work (1, docs/export.md), so the file is untouched.
    const auto notAsset = runCli("render --gdm " + quoted(dir->path()) + small);
    EXPECT_EQ(notAsset.exitCode, 2) << notAsset.output;
    const fs::path sidecar = *dir / "weave" / "gdm.json";
    const auto before = fs::file_size(sidecar);
    const auto overwrite = runCli("render" + weave + " --mesh quad --size 16x16 -o " + quoted(sidecar));
    SKIP_WITHOUT_GL(overwrite);
    EXPECT_EQ(overwrite.exitCode, 1) << overwrite.output;
    EXPECT_NE(overwrite.output.find("cannot write .json"), std::string::npos) << overwrite.output;
    EXPECT_EQ(fs::file_size(sidecar), before);
}

}  // namespace
}  // namespace strata
