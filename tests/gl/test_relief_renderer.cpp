// The relief renderer against the exact CPU reference of the verification scene (CONVENTIONS §7,
// strata/trace/quad_reference.h), plus determinism, interpenetration and a shaded sanity check.
#include "gl_test_support.h"
#include "strata/core/error.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/image/srgb.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/patterns.h"
#include "strata/trace/quad_reference.h"
#include "strata/trace/render_compare.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace strata::gl {
namespace {

using test::GlTest;

class RendererGl : public GlTest {};

constexpr double kDepthScale = 0.1;
constexpr int kPatternSize = 256;
constexpr int kPicture = 192;

// Camera above the quad's centre at distance 1.6, tilted by `angle` degrees from the normal towards -y.
// A 40 degree field of view: the quad fills most of the picture at every angle.
Camera quadCamera(double angleDegrees) {
    const double a = glm::radians(angleDegrees);
    Camera camera;
    camera.target = {0.5, 0.5, 0.0};
    camera.eye = camera.target + 1.6 * glm::dvec3(0.0, -std::sin(a), std::cos(a));
    camera.fovYDegrees = 40.0;
    return camera;
}

// Depth rounded to 16 bits, as the RGBA16 upload stores it, so that the reference traces the same field.
ReliefTexture quantisedPattern(const std::string& name, int size) {
    ReliefTexture texture = makePattern(name, {size, 1, kDepthScale});
    for (float& d : texture.depth.pixels()) d = static_cast<float>(std::round(double(d) * 65535.0) / 65535.0);
    return texture;
}

RenderRequest quadRequest(const GpuMesh& quad, const GpuMaterial& material, const Camera& camera,
                          RenderOutput output) {
    RenderRequest request;
    request.objects.push_back({&quad, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
    request.camera = camera;
    request.relief.linearSteps = 64;
    request.relief.binarySteps = 8;
    request.relief.depthScale = kDepthScale;
    request.relief.selfShadow = true;
    request.lighting.lightPosition = {1.5, 0.0, 1.5};
    request.picture.width = kPicture;
    request.picture.height = kPicture;
    request.picture.output = output;
    return request;
}

TEST_F(RendererGl, RenderingIsDeterministic) {
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    const GpuMaterial material =
        uploadMaterial(makePattern("stone-bricks", {128, 1, kDepthScale}), kDepthScale);
    for (const RenderOutput output : {RenderOutput::Shaded, RenderOutput::Uv, RenderOutput::Shadow}) {
        const RenderRequest request = quadRequest(quad, material, quadCamera(45.0), output);
        const Image first = renderer.render(request);
        const Image second = renderer.render(request);
        EXPECT_TRUE(first == second) << toString(output);
    }
}

// One view of the quad with `technique` against the exact tracer: the uv output's agreement and the shadow
// output's, printed as a table row. Where `failed` says the result misses its bounds, the reference, test
// and difference pictures go to the test failure directory.
struct ViewResult {
    UvComparison uv;
    MaskAgreement shadow;
};
template <typename Failed>
ViewResult compareView(ReliefRenderer& renderer, const GpuMesh& quad, const std::string& name,
                       const ReliefTexture& texture, const GpuMaterial& material, Technique technique,
                       double angle, const Failed& failed) {
    const HeightFieldTracer tracer(texture.depth, kDepthScale);
    const Camera camera = quadCamera(angle);
    const QuadReferenceImages reference =
        renderQuadReference(tracer, camera, kPicture, kPicture, {glm::dvec3(1.5, 0.0, 1.5), std::nullopt});
    RenderRequest request = quadRequest(quad, material, camera, RenderOutput::Uv);
    request.relief.technique = technique;
    const Image uv = renderer.render(request);
    request.picture.output = RenderOutput::Shadow;
    const Image shadow = renderer.render(request);
    const int w = texture.depth.width(), h = texture.depth.height();
    const ViewResult result{compareUv(reference.uv, uv, w, h),
                            compareShadow(reference.shadow, shadow, reference.uv, uv)};
    std::printf("%-14s %5.0f %10.3f %8.4f %8.4f %8.2f\n", name.c_str(), angle,
                100.0 * result.uv.mismatchFraction, result.uv.p50, result.uv.p99,
                100.0 * result.shadow.fraction);
    if (failed(result)) {
        const std::string stem =
            std::string(toString(technique)) + "_" + name + "_" + std::to_string(static_cast<int>(angle));
        const std::filesystem::path dir = test::failureDirectory("quad_reference");
        const Image difference = uvDiffImage(reference.uv, uv, w, h);
        writeComparisonImages(dir, stem + "_uv", reference.uv, uv, difference);
        writeComparisonImages(dir, stem + "_shadow", reference.shadow, shadow, difference);
        std::printf("  wrote %s/%s_*.png\n", dir.c_str(), stem.c_str());
    }
    return result;
}

const char* const kViewTableHeader = "%-14s %5s %10s %8s %8s %8s\n";

// The uv and shadow outputs of relief 64 + 8 against the exact tracer, on every pattern at 5, 45 and 75
// degrees from the normal.
TEST_F(RendererGl, QuadMatchesExactReference) {
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    std::printf(kViewTableHeader, "pattern", "angle", "mismatch%", "p50", "p99", "shadow%");
    for (const PatternInfo& info : patternList()) {
        const ReliefTexture texture = quantisedPattern(info.name, kPatternSize);
        const GpuMaterial material = uploadMaterial(texture, kDepthScale);
        for (const double angle : {5.0, 45.0, 75.0}) {
            // Hit/miss: every ray that enters the quad hits the relief, so a disagreement is a pixel whose
            // centre lies within rounding of the quad's edge: 0.5 % of ~25k hit pixels is ~120, the length
            // of the quad's outline is ~700 pixels; at 75 degrees the outline is steeper in perspective.
            // p99 uv error: the search brackets the hit to 1/8192 of the depth range, ~0.01 texel at 45
            // degrees; 1 texel leaves room for thin features the 64-step linear search steps over (the
            // paper's Sec. 5 aliasing). At 75 degrees the ray crosses 4x more texels per step.
            const bool grazing = angle > 60.0;
            const double maxMismatch = grazing ? 0.02 : 0.005;
            // At 75 degrees the 64-step search runs 247 steps (adaptiveLinearSteps keeps the step length
            // along the ray constant), ~0.4 texel apart in uv at S = 0.1 on a 256^2 map; a ridge thinner than
            // that can still be stepped over (the paper's Sec. 5 aliasing), hence 3 texels there.
            const double maxP99 = grazing ? 3.0 : 1.0;
            // Shadows: the light-ray search is a linear search only (paper Sec. 3.1), and the exact test
            // counts any grazing touch; 97 % of the pixels where both hit.
            const double minShadow = 0.97;
            const ViewResult result = compareView(renderer, quad, info.name, texture, material,
                                                  Technique::Relief, angle, [&](const ViewResult& r) {
                                                      return r.uv.mismatchFraction > maxMismatch ||
                                                             r.uv.p99 > maxP99 ||
                                                             r.shadow.fraction < minShadow;
                                                  });
            EXPECT_LE(result.uv.mismatchFraction, maxMismatch) << info.name << " at " << angle;
            EXPECT_LE(result.uv.p99, maxP99) << info.name << " at " << angle;
            EXPECT_GE(result.shadow.fraction, minShadow) << info.name << " at " << angle;
        }
    }
}

// A map of 1-texel-wide walls (d = 0) every 16 texels in both directions over a floor at d = 1: the thin
// features a stepping search jumps over at grazing angles.
ReliefTexture wallMap(int size) {
    ReliefTexture texture;
    texture.depth = Image(size, size, 1, 1.0f);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            if (x % 16 == 0 || y % 16 == 0) texture.depth.at(x, y) = 0.0f;
    texture.normal = normalsFromDepth(texture.depth, kDepthScale);
    texture.depthScale = kDepthScale;
    return texture;
}

// An exact technique (maxmip, cone) on every pattern and the wall map, at 5, 45 and 75 degrees: its uv
// output is the exact reference's to the bounds (hit/miss <= 0.2 %, p99 <= 0.25 texel), with no
// step count; its shadows (the same traversal along the light ray) agree on >= 99 % of the pixels.
// `extraMaps`: more maps for a technique that takes sizes maxmip does not.
void expectExact(Technique technique, std::vector<std::pair<std::string, ReliefTexture>> extraMaps = {}) {
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    std::vector<std::pair<std::string, ReliefTexture>> maps;
    for (const PatternInfo& info : patternList())
        maps.emplace_back(info.name, quantisedPattern(info.name, kPatternSize));
    maps.emplace_back("walls", wallMap(kPatternSize));
    // Not square: the top half of stone-bricks (its wrap is a cut, still a valid wrap-around field), so the
    // pyramid's v side reaches 1 a level before its u side.
    {
        const ReliefTexture full = quantisedPattern("stone-bricks", kPatternSize);
        ReliefTexture half;
        half.depth = Image(kPatternSize, kPatternSize / 2, 1);
        for (int y = 0; y < kPatternSize / 2; ++y)
            for (int x = 0; x < kPatternSize; ++x) half.depth.at(x, y) = full.depth.at(x, y);
        half.normal = normalsFromDepth(half.depth, kDepthScale);
        half.depthScale = kDepthScale;
        maps.emplace_back("bricks-256x128", std::move(half));
    }
    for (auto& map : extraMaps) maps.push_back(std::move(map));
    std::printf("%s\n", toString(technique));
    std::printf(kViewTableHeader, "map", "angle", "mismatch%", "p50", "p99", "shadow%");
    for (const auto& [name, texture] : maps) {
        const GpuMaterial material = uploadMaterial(texture, kDepthScale);
        for (const double angle : {5.0, 45.0, 75.0}) {
            const ViewResult result = compareView(
                renderer, quad, name, texture, material, technique, angle, [](const ViewResult& r) {
                    return r.uv.mismatchFraction > 0.002 || r.uv.p99 > 0.25 || r.shadow.fraction < 0.99;
                });
            EXPECT_LE(result.uv.mismatchFraction, 0.002) << name << " at " << angle;
            EXPECT_LE(result.uv.p99, 0.25) << name << " at " << angle;
            EXPECT_GE(result.shadow.fraction, 0.99) << name << " at " << angle;
        }
    }
}

TEST_F(RendererGl, MaxMipIsExact) {
    expectExact(Technique::MaxMip);
}

// Cone stepping needs no power-of-two sides: a 200x120 cut of stone-bricks besides the maps above.
TEST_F(RendererGl, ConeIsExact) {
    const ReliefTexture full = quantisedPattern("stone-bricks", kPatternSize);
    ReliefTexture cut;
    cut.depth = Image(200, 120, 1);
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 200; ++x) cut.depth.at(x, y) = full.depth.at(x, y);
    cut.normal = normalsFromDepth(cut.depth, kDepthScale);
    cut.depthScale = kDepthScale;
    std::vector<std::pair<std::string, ReliefTexture>> extra;
    extra.emplace_back("bricks-200x120", std::move(cut));
    expectExact(Technique::Cone, std::move(extra));
}

// On a mesh, in the shaded output (mip-mapped shading, self-shadows, depth correction), cone and maxmip draw
// the same picture: both find the exact first hit of the same bilinear field, so they can differ only where
// float rounding moves a hit across an edge of the relief.
TEST_F(RendererGl, ConeAndMaxMipShadeTheTeapotAlike) {
    ReliefRenderer renderer;
    const Mesh teapot = makeBuiltinMesh("teapot");
    const GpuMesh mesh = uploadMesh(teapot);
    const ReliefTexture texture = quantisedPattern("stone-bricks", kPatternSize);
    const GpuMaterial material = uploadMaterial(texture, kDepthScale);
    RenderRequest request;
    request.objects.push_back({&mesh, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
    request.camera.eye = {0.4, -2.6, 1.5};
    request.camera.target = {0.08, 0.0, 0.45};
    request.camera.fovYDegrees = 35.0;
    request.relief.tiling = 2.0;
    request.relief.depthScale = 0.08;
    request.relief.depthCorrection = true;
    request.picture.width = 160;
    request.picture.height = 120;
    request.picture.samples = 1;
    request.relief.technique = Technique::MaxMip;
    const Image maxmip = renderer.render(request);
    request.relief.technique = Technique::Cone;
    const Image cone = renderer.render(request);
    std::vector<double> differences;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
            double d = 0.0;
            for (int c = 0; c < 3; ++c)
                d = std::max(d, static_cast<double>(std::abs(cone.at(x, y, c) - maxmip.at(x, y, c))));
            differences.push_back(d);
        }
    std::sort(differences.begin(), differences.end());
    double sum = 0.0;
    for (const double d : differences) sum += d;
    const double mean = sum / static_cast<double>(differences.size());
    const double p99 = differences[differences.size() * 99 / 100];
    std::printf("|cone - maxmip| (sRGB): mean %.5f, p99 %.4f, max %.4f\n", mean, p99, differences.back());
    // Identical hits give identical pixels: at most a mean of 1/1000 and one 8-bit step at the 99th
    // percentile leave room for rounding only (measured: mean 0.00000, p99 0, max 0.0004).
    EXPECT_LE(mean, 1e-3);
    EXPECT_LE(p99, 1.0 / 255.0);
    // And the teapot is there: a fifth of the picture differs from the background at its corner.
    int covered = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) covered += std::abs(cone.at(x, y, 1) - cone.at(0, 0, 1)) > 0.02f;
    EXPECT_GT(covered, 160 * 120 / 5);
}

// Rendering `material` on the quad with `technique` throws Error(InvalidInput) whose message has `reason`,
// and draws nothing.
void expectRefused(const GpuMaterial& material, Technique technique, const std::string& reason) {
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    RenderRequest request = quadRequest(quad, material, quadCamera(45.0), RenderOutput::Uv);
    request.relief.technique = technique;
    try {
        renderer.render(request);
        ADD_FAILURE() << toString(technique) << " rendered; expected: " << reason;
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
    }
}

// A live material has no single depth map to make a cone map of: cone refuses it with the reason.
TEST_F(RendererGl, ConeRefusesLiveMaterials) {
    std::vector<CompositionLayer> layers(1);
    layers[0].texture = quantisedPattern("stone-bricks", 64);
    ComposeParams compose;
    compose.depthScale = kDepthScale;
    const GpuMaterial material = uploadLiveMaterial(layers, compose, std::nullopt, AoParams{});
    EXPECT_EQ(material.coneTexture(), 0u);
    expectRefused(material, Technique::Cone, "cone needs a baked material");
}

// maxmip's pyramid needs power-of-two sides: another map is refused with the reason, not drawn wrong.
TEST_F(RendererGl, MaxMipRefusesOtherSizes) {
    ReliefTexture odd;
    odd.depth = Image(100, 64, 1, 0.5f);
    odd.normal = normalsFromDepth(odd.depth, kDepthScale);
    odd.depthScale = kDepthScale;
    const GpuMaterial material = uploadMaterial(odd, kDepthScale);
    EXPECT_EQ(material.maxMipTexture(), 0u);
    expectRefused(material, Technique::MaxMip, "powers of two, got 100x64");
}

// Normal and parallax mapping have no ray / relief intersection; their shadows are the light-ray test from
// the relief point under the uv they shade (relief.frag.glsl). The CPU model of that point, per pixel: the
// view ray enters the quad at tile = (x, y); normal mapping shades tile, parallax mapping tile + (d(tile) S)
// dir.xy / -dir.z; the point is (uv, -S d(uv)), lit when the exact tracer finds nothing of the relief
// between it and the light.
TEST_F(RendererGl, EveryTechniqueShadowsItsReliefPoint) {
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    const glm::dvec3 light(1.5, 0.0, 1.5);
    for (const std::string pattern : {"stone-bricks", "scales"}) {
        const ReliefTexture texture = quantisedPattern(pattern, kPatternSize);
        const GpuMaterial material = uploadMaterial(texture, kDepthScale);
        const HeightFieldTracer tracer(texture.depth, kDepthScale);
        for (const Technique technique : {Technique::Normal, Technique::Parallax}) {
            const Camera camera = quadCamera(45.0);
            RenderRequest request = quadRequest(quad, material, camera, RenderOutput::Uv);
            request.relief.technique = technique;
            const Image uv = renderer.render(request);
            request.picture.output = RenderOutput::Shadow;
            const Image shadow = renderer.render(request);
            int compared = 0, agree = 0, shadowed = 0;
            double maxUvError = 0.0;
            for (int y = 0; y < kPicture; ++y) {
                for (int x = 0; x < kPicture; ++x) {
                    const glm::dvec3 dir = pixelRayDirection(camera, kPicture, kPicture, x + 0.5, y + 0.5);
                    const double t = -camera.eye.z / dir.z;
                    glm::dvec2 tile = glm::dvec2(camera.eye) + t * glm::dvec2(dir);
                    // Pixels near the quad's outline may round either way: compare the interior only.
                    if (tile.x < 0.01 || tile.x > 0.99 || tile.y < 0.01 || tile.y > 0.99) continue;
                    if (uv.at(x, y, 2) < 0.5f) {
                        ADD_FAILURE() << "no hit at pixel " << x << ", " << y;
                        continue;
                    }
                    if (technique == Technique::Parallax)
                        tile += glm::dvec2(dir) * (tracer.depthAt(tile.x, tile.y) * kDepthScale / -dir.z);
                    const glm::dvec2 wrapped = tile - glm::floor(tile);
                    maxUvError = std::max(
                        {maxUvError, std::abs(static_cast<double>(uv.at(x, y, 0)) - wrapped.x) * kPatternSize,
                         std::abs(static_cast<double>(uv.at(x, y, 1)) - wrapped.y) * kPatternSize});
                    const glm::dvec3 point(tile, tracer.surfaceZ(tile.x, tile.y));
                    const bool lit = !tracer.occludedFromSurface(tile.x, tile.y, light - point, 1.0);
                    ++compared;
                    if (!lit) ++shadowed;
                    if (lit == (shadow.at(x, y) > 0.5f)) ++agree;
                }
            }
            const double fraction = static_cast<double>(agree) / compared;
            std::printf("%-13s %-9s shadowed %5.1f %%  agreement %6.2f %%  max uv error %.3f texel\n",
                        pattern.c_str(), toString(technique), 100.0 * shadowed / compared, 100.0 * fraction,
                        maxUvError);
            // The model is the renderer's (measured: 0.001 texel at most). GL's bilinear filter weighs with
            // 8-bit sub-texel fractions, which moves d, hence the parallax offset, by up to 1/256 of a
            // texel's depth step times S / cos: 0.05 texel bounds that on these patterns.
            EXPECT_LT(maxUvError, 0.05) << pattern << " " << toString(technique);
            // The patterns shadow a real part of the quad from this light (the test is not vacuous).
            EXPECT_GT(shadowed, compared / 20) << pattern << " " << toString(technique);
            // The same bound as the relief technique's shadow output (QuadMatchesExactReference).
            EXPECT_GE(fraction, 0.97) << pattern << " " << toString(technique);
        }
    }
}

// A flat relief (d = 0, n = +z) under an overhead light: every pixel is the Blinn-Phong formula of the
// plane z = 0 seen from the eye.
TEST_F(RendererGl, ShadedFlatReliefMatchesBlinnPhong) {
    ReliefTexture flat;
    flat.depth = Image(16, 16, 1, 0.0f);
    flat.normal = normalsFromDepth(flat.depth, kDepthScale);
    flat.color = Image(16, 16, 3, 0.5f);
    flat.depthScale = kDepthScale;
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    const GpuMaterial material = uploadMaterial(flat, kDepthScale);
    RenderRequest request;
    request.objects.push_back({&quad, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
    request.camera.eye = {0.5, 0.4, 1.5};
    request.camera.target = {0.5, 0.5, 0.0};
    request.camera.fovYDegrees = 30.0;
    request.lighting.lightPosition = {0.5, 0.5, 2.0};
    request.lighting.ambient = 0.2;
    request.lighting.specular = 0.3;
    request.lighting.shininess = 16.0;
    request.picture.width = 128;
    request.picture.height = 128;
    request.picture.samples = 4;  // interior pixels are covered by all samples: MSAA does not change them
    const Image image = renderer.render(request);
    // The colour texture is 8-bit sRGB: 0.5 is stored as 128 / 255.
    const double albedo = srgbToLinear(128.0 / 255.0);
    int checked = 0;
    for (int y = 8; y < 128; y += 10) {
        for (int x = 8; x < 128; x += 10) {
            const glm::dvec3 direction = pixelRayDirection(request.camera, 128, 128, x + 0.5, y + 0.5);
            const glm::dvec3 p = request.camera.eye - direction * (request.camera.eye.z / direction.z);
            if (p.x < 0.02 || p.x > 0.98 || p.y < 0.02 || p.y > 0.98) continue;  // away from the quad's edge
            const glm::dvec3 l = glm::normalize(request.lighting.lightPosition - p);
            const glm::dvec3 v = glm::normalize(request.camera.eye - p);
            const glm::dvec3 h = glm::normalize(l + v);
            const double diffuse = std::max(l.z, 0.0);
            const double linear = request.lighting.ambient * albedo + diffuse * albedo +
                                  request.lighting.specular * std::pow(std::max(h.z, 0.0), 16.0);
            for (int c = 0; c < 3; ++c) {
                // 2e-3: half-float storage (11-bit mantissa) and float shading, after the sRGB encoding;
                // the 10 + 5 search puts the hit at d = 1/160 (6e-4 world units below z = 0), which moves
                // the light and view vectors by ~1e-4.
                EXPECT_NEAR(image.at(x, y, c), linearToSrgb(linear), 2e-3) << x << ", " << y;
            }
            ++checked;
        }
    }
    EXPECT_GT(checked, 60);
}

// A sphere through a relief-mapped quad: with depth correction the visible object per pixel follows the
// relief surface, as in the exact reference (paper Sec. 5, Fig. 18); without it the boundary is at the
// polygon z = 0.
TEST_F(RendererGl, InterpenetrationFollowsTheRelief) {
    ReliefTexture texture = quantisedPattern("base", 128);
    texture.color = Image(128, 128, 3, 0.0f);
    for (int y = 0; y < 128; ++y) {
        for (int x = 0; x < 128; ++x) texture.color.at(x, y, 0) = 1.0f;  // pure red relief
    }
    const HeightFieldTracer tracer(texture.depth, kDepthScale);
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    const GpuMesh sphere = uploadMesh(makeBuiltinMesh("sphere", {64}));
    const GpuMaterial material = uploadMaterial(texture, kDepthScale);
    const glm::dvec3 centre(0.45, 0.5, -0.02);
    const double radius = 0.25;
    const Camera camera = quadCamera(50.0);
    const int size = 160;
    const QuadReferenceImages reference =
        renderQuadReference(tracer, camera, size, size, {std::nullopt, ReferenceSphere{centre, radius}});

    const auto visibleObjects = [&](bool depthCorrection) {
        RenderRequest request;
        request.objects.push_back({&quad, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
        const glm::dmat4 model =
            glm::scale(glm::translate(glm::dmat4(1.0), centre), glm::dvec3(2.0 * radius));
        request.objects.push_back({&sphere, model, nullptr, glm::dvec3(0.0, 1.0, 0.0)});  // pure green
        request.camera = camera;
        request.relief.linearSteps = 64;
        request.relief.binarySteps = 8;
        request.relief.depthCorrection = depthCorrection;
        request.relief.selfShadow = false;
        request.lighting.ambient = 1.0;
        request.lighting.specular = 0.0;
        request.picture.width = size;
        request.picture.height = size;
        request.picture.samples = 1;
        request.picture.background = glm::dvec3(0.0);
        const Image shaded = renderer.render(request);
        Image object(size, size, 1, 0.0f);
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const float r = shaded.at(x, y, 0);
                const float g = shaded.at(x, y, 1);
                object.at(x, y) = r > g + 0.1f ? 1.0f : (g > r + 0.1f ? 2.0f : 0.0f);
            }
        }
        return object;
    };
    // Pixels further than 2 px from any change of object in the reference: the tessellated sphere (64
    // segments per quarter turn) lies inside the analytic one by at most r (1 - cos(pi / 128)) = 8e-5.
    const auto disagreement = [&](const Image& object) {
        long differ = 0;
        long compared = 0;
        for (int y = 2; y < size - 2; ++y) {
            for (int x = 2; x < size - 2; ++x) {
                const float expected = reference.object.at(x, y);
                bool interior = true;
                for (int dy = -2; dy <= 2 && interior; ++dy) {
                    for (int dx = -2; dx <= 2; ++dx)
                        interior = interior && reference.object.at(x + dx, y + dy) == expected;
                }
                if (!interior) continue;
                ++compared;
                if (object.at(x, y) != expected) ++differ;
            }
        }
        return static_cast<double>(differ) / static_cast<double>(std::max(compared, 1L));
    };
    const Image corrected = visibleObjects(true);
    const Image uncorrected = visibleObjects(false);
    const double correctedError = disagreement(corrected);
    const double uncorrectedError = disagreement(uncorrected);
    std::printf(
        "interpenetration: %.3f %% of interior pixels differ with depth correction, %.3f %% without\n",
        100.0 * correctedError, 100.0 * uncorrectedError);
    // With depth correction every interior pixel agrees (a few may sit where the relief itself has a
    // sharp silhouette near the boundary): 0.1 %.
    EXPECT_LE(correctedError, 0.001);
    // Without it the sphere is cut at z = 0 instead of at the relief (up to S = 0.1 lower): a band a few
    // pixels wide along the intersection curve, measured 0.7 % of the interior pixels; at least 0.3 % and
    // ten times the corrected error.
    EXPECT_GE(uncorrectedError, std::max(10.0 * correctedError, 0.003));
    if (correctedError > 0.001) {
        const std::filesystem::path dir = test::failureDirectory("interpenetration");
        Image scaledReference = reference.object;
        Image scaledActual = corrected;
        for (float& v : scaledReference.pixels()) v *= 0.5f;
        for (float& v : scaledActual.pixels()) v *= 0.5f;
        Image diff(size, size, 1, 0.0f);
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x)
                diff.at(x, y) = corrected.at(x, y) != reference.object.at(x, y) ? 1.0f : 0.0f;
        }
        writeComparisonImages(dir, "object", scaledReference, scaledActual, diff);
        std::printf("  wrote %s/object_*.png\n", dir.c_str());
    }
}

}  // namespace
}  // namespace strata::gl
