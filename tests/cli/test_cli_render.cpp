// `strata render` and `strata compare` end to end: the verification scene's 16-bit outputs (CONVENTIONS §7)
// against the exact CPU reference, and the documented errors with nothing written. These run the GL renderer
// (headless EGL; llvmpipe without a GPU); where no context can be made the CLI exits 5 and they skip.
#include "test_support.h"

#include "strata/image/image_io.h"
#include "strata/scene/camera.h"
#include "strata/trace/heightfield_tracer.h"
#include "strata/trace/quad_reference.h"
#include "strata/trace/render_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace strata {
namespace {

using test::runCli;

using test::quoted;

// Skips the test when the CLI reports that it has no OpenGL 4.5 context (exit 5, Unsupported).
#define SKIP_WITHOUT_GL(result) \
    if ((result).exitCode == 5) GTEST_SKIP() << "no OpenGL context: " << (result).output

// A 64^2 depth map: a ramp in u plus a raised square (sharp edges and a slope).
Image testDepth() {
    Image depth(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            depth.at(x, y) =
                (x >= 20 && x < 40 && y >= 20 && y < 40) ? 0.1f : 0.3f + 0.6f * static_cast<float>(x) / 63.0f;
    return depth;
}

// The exact reference of the verification scenes below: S = 0.1, target (0.5, 0.5, 0), 45 degrees, 96^2
// pixels, light at (1.5, 0.2, 1.2), for the 16-bit depth map the CLI read.
QuadReferenceImages exactReference(const std::filesystem::path& depthFile, glm::dvec3 eye) {
    const HeightFieldTracer tracer(readImage(depthFile), 0.1);
    Camera camera;
    camera.eye = eye;
    camera.target = {0.5, 0.5, 0.0};
    camera.fovYDegrees = 45.0;
    return renderQuadReference(tracer, camera, 96, 96, {glm::dvec3(1.5, 0.2, 1.2), std::nullopt});
}

TEST(CliRender, VerificationSceneMatchesTheExactReference) {
    test::ScratchDir dir("cli-render-verify");
    writePng(dir / "d.png", testDepth());
    const std::string view =
        " --mesh quad --depth-map " + quoted(dir / "d.png") +
        " --depth-scale 0.1 --technique relief --linear-steps 64 --binary-steps 8"
        " --eye 0.5,-0.3,1.4 --target 0.5,0.5,0 --fov 45 --size 96x96 --light 1.5,0.2,1.2";
    const auto uvRun = runCli("render" + view + " --output uv -o " + quoted(dir / "uv.png"));
    SKIP_WITHOUT_GL(uvRun);
    ASSERT_EQ(uvRun.exitCode, 0) << uvRun.output;
    ASSERT_EQ(runCli("render" + view + " --output shadow -o " + quoted(dir / "shadow.png")).exitCode, 0);
    ASSERT_EQ(runCli("render" + view + " --output depth -o " + quoted(dir / "depth.png")).exitCode, 0);

    // 16-bit files, one value per pixel (CONVENTIONS §7).
    EXPECT_EQ(readImageInfo(dir / "uv.png").bitDepth, 16);
    EXPECT_EQ(readImageInfo(dir / "depth.png").bitDepth, 16);
    const Image uv = readImage(dir / "uv.png");
    const Image shadow = readImage(dir / "shadow.png");
    const Image depth = readImage(dir / "depth.png");
    ASSERT_EQ(uv.channels(), 3);
    ASSERT_EQ(shadow.channels(), 1);

    // The reference sees the same 16-bit depth the CLI read.
    const QuadReferenceImages reference = exactReference(dir / "d.png", {0.5, -0.3, 1.4});
    const UvComparison result = compareUv(reference.uv, uv, 64, 64);
    EXPECT_GT(result.referenceHits, 3000);
    // The issue's thresholds at moderate angles: 0.5 % hit/miss, p99 within 1 texel.
    EXPECT_LE(result.mismatchFraction, 0.005);
    EXPECT_LE(result.p99, 1.0);
    // >= 97 % shadow agreement where both hit (the issue's threshold).
    EXPECT_GE(compareShadow(reference.shadow, shadow, reference.uv, uv).fraction, 0.97);
    // depth holds d of the hit: within the search's last bracket (1/8192 of the range) plus 16-bit rounding,
    // except where the hit lies on the raised square's vertical edge, where d jumps by 0.2 within a texel.
    long close = 0, both = 0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x)
            if (uv.at(x, y, 2) > 0.5f && reference.uv.at(x, y, 2) > 0.5f) {
                ++both;
                close += std::abs(depth.at(x, y) - reference.depth.at(x, y)) < 2e-3f;
            }
    EXPECT_GE(static_cast<double>(close) / static_cast<double>(both), 0.97);
}

TEST(CliRender, ErrorsHaveTheirCodesAndWriteNothing) {
    test::ScratchDir dir("cli-render-errors");
    writePng(dir / "d.png", testDepth());
    const std::string small = " --size 32x32 -o " + quoted(dir / "out.png");
    // Usage: malformed vectors and sizes, an unknown technique, eye without target.
    EXPECT_EQ(runCli("render --mesh quad --eye 1,2 --target 0,0,0" + small).exitCode, 1);
    EXPECT_EQ(runCli("render --mesh quad --size 32by32 -o " + quoted(dir / "out.png")).exitCode, 1);
    EXPECT_EQ(runCli("render --technique bump" + small).exitCode, 1);
    EXPECT_EQ(runCli("render --eye 1,2,3" + small).exitCode, 1);
    // I/O: a material that is neither a file nor a built-in.
    const auto missing = runCli("render --mesh quad --material no-such-material" + small);
    EXPECT_EQ(missing.exitCode, 2) << missing.output;
    EXPECT_NE(missing.output.find("no-such-material"), std::string::npos) << missing.output;
    // Invalid input: a mesh file without texture coordinates, a scene with an unknown key.
    test::writeBytes(dir / "nouv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const auto noUv =
        runCli("render --mesh " + quoted(dir / "nouv.obj") + " --depth-map " + quoted(dir / "d.png") + small);
    if (noUv.exitCode != 5) {
        EXPECT_EQ(noUv.exitCode, 3) << noUv.output;
        EXPECT_NE(noUv.output.find("texture coordinates"), std::string::npos) << noUv.output;
    }
    test::writeBytes(dir / "scene.json", "{ \"techniqe\": \"relief\" }");
    const auto badScene = runCli("render " + quoted(dir / "scene.json") + small);
    EXPECT_EQ(badScene.exitCode, 3) << badScene.output;
    EXPECT_NE(badScene.output.find("techniqe"), std::string::npos) << badScene.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
    // An input is never overwritten.
    const auto overwrite = runCli("render --mesh quad --depth-map " + quoted(dir / "d.png") +
                                  " --size 32x32 -o " + quoted(dir / "d.png"));
    if (overwrite.exitCode != 5) {
        EXPECT_EQ(overwrite.exitCode, 2) << overwrite.output;
    }
    EXPECT_LT(test::maxAbsDiff(readImage(dir / "d.png"), testDepth()), 1.0 / 65535.0);
}

TEST(CliRender, CompareWritesThreePanels) {
    test::ScratchDir dir("cli-compare");
    const auto result =
        runCli("compare --material stone-bricks --size 64x48 --samples 1 -o " + quoted(dir / "c.png"));
    SKIP_WITHOUT_GL(result);
    ASSERT_EQ(result.exitCode, 0) << result.output;
    const ImageInfo info = readImageInfo(dir / "c.png");
    EXPECT_EQ(info.width, 3 * 64 + 2 * 6);  // three panels and two 6-pixel gaps
    EXPECT_EQ(info.height, 48);
    // The panels differ: normal, parallax and relief mapping do not draw the same picture.
    const Image sheet = readImage(dir / "c.png");
    double difference = 0.0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            difference += static_cast<double>(std::abs(sheet.at(x, y) - sheet.at(2 * 70 + x, y)));
    EXPECT_GT(difference / (64 * 48), 0.01);
}

// --meta live against --meta baked on the verification quad with integer tilings whose lattices line up
// (64^2 x 2 and 128^2 x 1 on a 128^2 composition): the issue's bound, hit/miss <= 0.5 % and p99 <= 1 texel.
// A texture set has no layers: --meta live is an error (3) for it.
TEST(CliRender, LiveMetaReliefMatchesTheBakedOne) {
    test::ScratchDir dir("cli-render-live");
    test::writeBytes(dir / "two.json", R"({ "resolution": 128, "depth_scale": 0.1, "normals": "consistent",
      "color_from": -1, "ao": "none", "layers": [
        { "pattern": "stone-bricks", "size": 128, "tiling": 1, "weight_depth": 1.0, "weight_normal": 1.0 },
        { "pattern": "scales", "size": 64, "tiling": 2, "weight_depth": 0.4, "weight_normal": 0.4 } ] })");
    const std::string view =
        " --mesh quad --material " + quoted(dir / "two.json") +
        " --technique relief --linear-steps 64 --binary-steps 8 --eye 0.5,-0.3,1.4"
        " --target 0.5,0.5,0 --fov 45 --size 96x96 --samples 1 --output uv --bit-depth 16";
    const auto baked = runCli("render" + view + " --meta baked -o " + quoted(dir / "baked.png"));
    SKIP_WITHOUT_GL(baked);
    ASSERT_EQ(baked.exitCode, 0) << baked.output;
    const auto live = runCli("render" + view + " --meta live -o " + quoted(dir / "live.png"));
    ASSERT_EQ(live.exitCode, 0) << live.output;
    EXPECT_NE(live.output.find("live meta-relief"), std::string::npos) << live.output;
    const UvComparison result =
        compareUv(readImage(dir / "baked.png"), readImage(dir / "live.png"), 128, 128);
    EXPECT_GT(result.referenceHits, 3000);
    EXPECT_LE(result.mismatchFraction, 0.005);
    EXPECT_LE(result.p99, 1.0);

    const auto noLayers =
        runCli("render --meta live --material stone-bricks --size 32x32 -o " + quoted(dir / "out.png"));
    EXPECT_EQ(noLayers.exitCode, 3) << noLayers.output;
    EXPECT_NE(noLayers.output.find("no layers"), std::string::npos) << noLayers.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

// --technique cone on the verification scene with a 60x40 map (no power of two: maxmip refuses it, cone
// does not) is exact: uv p99 within 0.05 texel of the exact reference (16-bit uv output rounds to 1/65535 of
// the tile, 0.001 texel here; 0.05 leaves room for the hits on the raised square's vertical edges), hit/miss
// within 0.2 %, and shadows >= 99 %. A live material cannot be drawn with cone: exit 3, nothing written.
TEST(CliRender, ConeIsExactOnAnyMapSize) {
    test::ScratchDir dir("cli-render-cone");
    Image depth(60, 40, 1);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 60; ++x)
            depth.at(x, y) =
                (x >= 20 && x < 40 && y >= 10 && y < 30) ? 0.1f : 0.3f + 0.6f * static_cast<float>(x) / 59.0f;
    writePng(dir / "d.png", depth);
    const std::string view = " --mesh quad --depth-map " + quoted(dir / "d.png") +
                             " --depth-scale 0.1 --technique cone --eye 0.5,-0.6,0.9 --target 0.5,0.5,0"
                             " --fov 45 --size 96x96 --light 1.5,0.2,1.2";
    const auto uvRun = runCli("render" + view + " --output uv -o " + quoted(dir / "uv.png"));
    SKIP_WITHOUT_GL(uvRun);
    ASSERT_EQ(uvRun.exitCode, 0) << uvRun.output;
    ASSERT_EQ(runCli("render" + view + " --output shadow -o " + quoted(dir / "shadow.png")).exitCode, 0);
    const Image uv = readImage(dir / "uv.png");
    const QuadReferenceImages reference = exactReference(dir / "d.png", {0.5, -0.6, 0.9});
    const UvComparison result = compareUv(reference.uv, uv, 60, 40);
    std::printf("cone via the CLI: mismatch %.3f %%, p99 %.4f texel\n", 100.0 * result.mismatchFraction,
                result.p99);
    EXPECT_GT(result.referenceHits, 3000);
    EXPECT_LE(result.mismatchFraction, 0.002);
    EXPECT_LE(result.p99, 0.05);
    EXPECT_GE(compareShadow(reference.shadow, readImage(dir / "shadow.png"), reference.uv, uv).fraction,
              0.99);

    test::writeBytes(dir / "one.json", R"({ "resolution": 64, "depth_scale": 0.1, "ao": "none",
      "layers": [ { "pattern": "scales", "size": 64 } ] })");
    const auto live = runCli("render --technique cone --meta live --material " + quoted(dir / "one.json") +
                             " --size 32x32 -o " + quoted(dir / "live.png"));
    EXPECT_EQ(live.exitCode, 3) << live.output;
    EXPECT_NE(live.output.find("cone needs a baked material"), std::string::npos) << live.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "live.png"));
}

}  // namespace
}  // namespace strata
