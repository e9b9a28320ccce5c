// The GDM verification scene in OpenGL (strata/gl/gdm_renderer.h) against its CPU twin, emulateGdm: the same
// algorithm in float on the GPU must give the same pictures (issue 18: identical hit / miss on >= 99.5 % of
// the pixels), raw and SVD, and against the exact reference as closely as the CPU does.
#include "gl_test_support.h"

#include "strata/core/error.h"
#include "strata/gdm/gdm_analytic.h"
#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/gl/program.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/scene/scene.h"

#include <gtest/gtest.h>
#include <glm/matrix.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace strata {
namespace {

using test::GlTest;

class GdmRendererGl : public GlTest {};

struct Baked {
    SolidMesh solid;
    Gdm gdm;
};

const Baked& weave() {
    static const Baked baked = [] {
        Baked b;
        b.solid = meshMesostructure(makeMesostructure("weave"), 32);
        b.gdm = bakeGdm(b.solid, GdmDims{32, 32, 8, 16, 32});
        return b;
    }();
    return baked;
}

Camera viewAt(double degrees) {
    return gdmSceneView(degrees);
}

const glm::dvec3 kLight(0.5, -0.6, 1.1);
constexpr int kSize = 128;

TEST_F(GdmRendererGl, RawMatchesTheCpuEmulation) {
    const Gdm& gdm = weave().gdm;
    const double voxel = gdm.height / gdm.dims.nz;
    for (const double degrees : {5.0, 45.0, 75.0}) {
        const Camera camera = viewAt(degrees);
        const GdmSceneImages cpu = emulateGdm(gdm, camera, kLight, kSize, kSize);
        const GdmSceneImages gpu = gl::renderGdmScene(gdm, camera, kLight, kSize, kSize);
        const GdmSceneAccuracy same = compareGdmScenes(cpu, gpu, gdm.height, voxel);
        // The bound: the shader and the emulation share the lookup (shaders/shared/gdm_lookup.h, in
        // float) but not the segment (the CPU's in double, by planes; the GPU's in float, by triangles);
        // where they disagree a lookup sits on the d < dt edge within float rounding.
        EXPECT_LE(same.hitMissDisagreePercent, 0.5) << degrees;
        // Where both hit, the hit points agree to float rounding of distances of a tile width or so, far
        // below a voxel, except where a rounding flip of d < dt in one prism moves the hit on.
        EXPECT_LT(same.uvwMeanVoxels, 0.01) << degrees;
        EXPECT_GE(same.shadowAgreePercent, 99.5) << degrees;
        EXPECT_GT(same.bothHitPixels, std::size_t(kSize * kSize / 5)) << degrees;
    }
}

TEST_F(GdmRendererGl, SvdMatchesTheCpuEmulationAndTheReference) {
    const Gdm& gdm = weave().gdm;
    const double voxel = gdm.height / gdm.dims.nz;
    const GdmSvd svd = compressGdm(gdm, 8);
    const Camera camera = viewAt(45.0);
    const GdmSceneImages cpu = emulateGdm(svd, camera, kLight, kSize, kSize);
    const GdmSceneImages gpu = gl::renderGdmScene(svd, camera, kLight, kSize, kSize);
    const GdmSceneAccuracy same = compareGdmScenes(cpu, gpu, gdm.height, voxel);
    EXPECT_LE(same.hitMissDisagreePercent, 0.5);
    EXPECT_LT(same.uvwMeanVoxels, 0.01);
    // Against the exact reference the GPU is as good as the CPU (within the pixels they disagree on).
    const GdmSceneImages reference = renderGdmReference(weave().solid, camera, kLight, kSize, kSize);
    const GdmSceneAccuracy cpuError = compareGdmScenes(reference, cpu, gdm.height, voxel);
    const GdmSceneAccuracy gpuError = compareGdmScenes(reference, gpu, gdm.height, voxel);
    EXPECT_NEAR(gpuError.hitMissDisagreePercent, cpuError.hitMissDisagreePercent, 0.5);
    EXPECT_NEAR(gpuError.uvwMeanVoxels, cpuError.uvwMeanVoxels, 0.05);
}

TEST_F(GdmRendererGl, ShadedShowsTheAlbedoWhereItHitsAndDarkensShadows) {
    const Gdm& gdm = weave().gdm;
    gl::GdmRenderer renderer;
    renderer.setGdm(gdm);
    renderer.setMesh(makeBuiltinMesh("quad"), {});
    const Mesostructure meso = makeMesostructure("weave");
    renderer.setVolumes(gdmOccupancy(gdm), mesostructureAlbedo(meso, gdm.dims));
    const Camera camera = viewAt(45.0);
    const GdmSceneImages plain = renderer.render(camera, kLight, kSize, kSize);
    const Image shaded = renderer.renderShaded(camera, kLight, kSize, kSize);
    double litSum = 0.0, shadowSum = 0.0;
    int lit = 0, shadowed = 0, blue = 0, cream = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            // The same pixels hit: the shaded pass is the uvw pass with another output.
            ASSERT_EQ(shaded.at(x, y, 3), plain.mask.at(x, y)) << x << " " << y;
            if (plain.mask.at(x, y) == 0.0f) continue;
            const float r = shaded.at(x, y, 0), g = shaded.at(x, y, 1), b = shaded.at(x, y, 2);
            // The weave's two yarns: indigo warps (blue above red), cream wefts (red above blue).
            blue += b > r;
            cream += r > b;
            const double luminance = 0.2126 * double(r) + 0.7152 * double(g) + 0.0722 * double(b);
            if (plain.shadow.at(x, y) > 0.5f) {
                litSum += luminance;
                ++lit;
            } else {
                shadowSum += luminance;
                ++shadowed;
            }
        }
    EXPECT_GT(blue, kSize * kSize / 20);
    EXPECT_GT(cream, kSize * kSize / 20);
    ASSERT_GT(lit, 0);
    ASSERT_GT(shadowed, 0);
    // Shadowed pixels keep only the ambient fifth of their light.
    EXPECT_GT(litSum / lit, 1.5 * shadowSum / shadowed);
    // Without the volumes there is nothing to shade with.
    gl::GdmRenderer bare;
    bare.setGdm(gdm);
    bare.setMesh(makeBuiltinMesh("quad"), {});
    EXPECT_THROW(bare.renderShaded(camera, kLight, 8, 8), Error);
}

TEST_F(GdmRendererGl, RefineAndMarchAgainstTheReference) {
    // The flat scene at 45 degrees against the exact reference, per technique (docs/gdm.md's table).
    const Gdm& gdm = weave().gdm;
    const double voxel = gdm.height / gdm.dims.nz;
    gl::GdmRenderer renderer;
    renderer.setGdm(gdm);
    renderer.setMesh(makeBuiltinMesh("quad"), {});
    renderer.setVolumes(gdmOccupancy(gdm), {});
    const Camera camera = viewAt(45.0);
    const GdmSceneImages reference = renderGdmReference(weave().solid, camera, kLight, kSize, kSize);
    GdmSceneAccuracy accuracy[3];
    const gl::GdmTechnique techniques[3] = {gl::GdmTechnique::Gdm, gl::GdmTechnique::Refine,
                                            gl::GdmTechnique::March};
    for (int n = 0; n < 3; ++n) {
        accuracy[n] = compareGdmScenes(
            reference,
            renderer.render(camera, kLight, kSize, kSize, GdmDirectionLookup::Nearest, techniques[n]),
            gdm.height, voxel);
    }
    // Measured at 32 x 32 x 8 voxels, 128 x 128: gdm 3.46 % hit / miss, uvw mean 0.62 voxels; refine 3.46 %,
    // 0.30 (it moves hits onto the occupancy's crossing, and keeps the lookup's misses); march 1.09 %, 0.29.
    // Refine must at least halve the lookup's uvw error less 10 %, and march must disagree on hit / miss less
    // than the lookup, or they do nothing of what they are for.
    EXPECT_LT(accuracy[1].uvwMeanVoxels, 0.55 * accuracy[0].uvwMeanVoxels);
    EXPECT_NEAR(accuracy[1].hitMissDisagreePercent, accuracy[0].hitMissDisagreePercent, 0.1);
    EXPECT_LT(accuracy[2].hitMissDisagreePercent, 0.5 * accuracy[0].hitMissDisagreePercent);
    EXPECT_LT(accuracy[2].uvwMeanVoxels, 0.55 * accuracy[0].uvwMeanVoxels);
    // Without the occupancy volume neither can run.
    gl::GdmRenderer bare;
    bare.setGdm(gdm);
    bare.setMesh(makeBuiltinMesh("quad"), {});
    EXPECT_THROW(bare.render(camera, kLight, 8, 8, GdmDirectionLookup::Nearest, gl::GdmTechnique::March),
                 Error);
}

// A built-in meshed and baked at `strata gdm bake`'s defaults (64 x 64 x 16 voxels, meshed at 64 voxels per
// tile), with its distance volume: the accuracy table's scenes (docs/gdm.md, bench_gdm_gl's `accuracy`).
// `directions` is the GDM's (16 x 32 by default); refine on the distance volume reads the GDM only where it
// runs out of steps, so a test of refine alone bakes fewer, to save time.
struct BakedDefault {
    SolidMesh solid;
    Gdm gdm;
    std::vector<float> distance;
};

BakedDefault bakeDefault(const std::string& name, int ntheta = 16, int nphi = 32) {
    BakedDefault b;
    b.solid = meshMesostructure(makeMesostructure(name), 64);
    b.gdm = bakeGdm(b.solid, GdmDims{64, 64, 16, ntheta, nphi});
    b.distance = bakeGdmDistance(b.solid, GdmDims{});
    return b;
}

TEST_F(GdmRendererGl, RefineOnTheDistanceVolumeIsExactOnTheFlatWeave) {
    // Issue 18's goal for refine: <= 0.5 % hit / miss and uvw p99 <= 0.5 voxel on the flat scene (weave,
    // 45 degrees, 256 x 256); the other techniques' rows of the accuracy table beside it. (Rank 8 gives
    // refine's numbers to 4 digits, bench_gdm_gl; its SVD is left to the bench to save time.)
    const BakedDefault weave64 = bakeDefault("weave");
    const Gdm& gdm = weave64.gdm;
    const double voxel = gdm.height / gdm.dims.nz;
    const Camera camera = viewAt(45.0);
    constexpr int kTableSize = 256;
    const GdmSceneImages reference =
        renderGdmReference(weave64.solid, camera, kLight, kTableSize, kTableSize);
    gl::GdmRenderer renderer;
    auto measure = [&](gl::GdmTechnique technique) {
        return compareGdmScenes(
            reference,
            renderer.render(camera, kLight, kTableSize, kTableSize, GdmDirectionLookup::Nearest, technique),
            gdm.height, voxel);
    };
    renderer.setGdm(gdm);
    renderer.setMesh(makeBuiltinMesh("quad"), {});
    renderer.setVolumes(gdmOccupancy(gdm), {});
    const GdmSceneAccuracy lookup = measure(gl::GdmTechnique::Gdm);
    const GdmSceneAccuracy march = measure(gl::GdmTechnique::March);
    renderer.setDistance(weave64.distance);
    const GdmSceneAccuracy refine = measure(gl::GdmTechnique::Refine);
    // The shaded picture (normals from the distance's gradient) covers the same pixels as refine's.
    const GdmSceneImages refined = renderer.render(camera, kLight, kTableSize, kTableSize,
                                                   GdmDirectionLookup::Nearest, gl::GdmTechnique::Refine);
    const Image shaded = renderer.renderShaded(camera, kLight, kTableSize, kTableSize,
                                               GdmDirectionLookup::Nearest, gl::GdmTechnique::Refine);
    int differ = 0;
    for (int y = 0; y < kTableSize; ++y)
        for (int x = 0; x < kTableSize; ++x) differ += shaded.at(x, y, 3) != refined.mask.at(x, y);
    EXPECT_EQ(differ, 0);
    // Measured: refine 0.34 % hit / miss, uvw mean 0.024, p99 0.21 voxels, shadow 99.5 %. The issue's
    // bounds, as they are.
    EXPECT_LE(refine.hitMissDisagreePercent, 0.5);
    EXPECT_LE(refine.uvwP99Voxels, 0.5);
    // Its own shadow, traced on the distance volume, agrees where both hit; measured 99.5 %, a margin of
    // half a percent for the terminator's pixels (gradient normals against the mesh's).
    EXPECT_GE(refine.shadowAgreePercent, 99.0);
    // Measured: gdm 1.69 % / p99 2.91 voxels / shadow 96.4 %; march 0.65 % / 1.93 / 96.3 %. Bounds 20 %
    // above (another driver's float rounding flips a few lookups on the d < dt edge), so that a change that
    // makes them worse shows; refine must beat both by the margins it has.
    EXPECT_LE(lookup.hitMissDisagreePercent, 2.0);
    EXPECT_LE(lookup.uvwP99Voxels, 3.5);
    EXPECT_LE(march.hitMissDisagreePercent, 0.8);
    EXPECT_LE(march.uvwP99Voxels, 2.3);
    EXPECT_LT(refine.hitMissDisagreePercent, 0.6 * march.hitMissDisagreePercent);
    EXPECT_LT(refine.uvwMeanVoxels, 0.2 * march.uvwMeanVoxels);
}

TEST_F(GdmRendererGl, RefineOnTheDistanceVolumeOnTheChain) {
    // The chain's links are thin (a few voxels): the accuracy table's hardest row for refine. At 128 x 128,
    // 45 degrees. Measured: 1.4 % hit / miss, uvw p95 0.31 voxels (at 256 x 256: 1.52 %, 0.29; the GDM
    // lookup there 12.6 %, p95 6.2 voxels).
    const BakedDefault chain = bakeDefault("chain", 2, 4);
    const Gdm& gdm = chain.gdm;
    const double voxel = gdm.height / gdm.dims.nz;
    const Camera camera = viewAt(45.0);
    const GdmSceneImages reference = renderGdmReference(chain.solid, camera, kLight, kSize, kSize);
    gl::GdmRenderer renderer;
    renderer.setGdm(gdm);
    renderer.setMesh(makeBuiltinMesh("quad"), {});
    renderer.setDistance(chain.distance);
    const GdmSceneImages refined =
        renderer.render(camera, kLight, kSize, kSize, GdmDirectionLookup::Nearest, gl::GdmTechnique::Refine);
    const GdmSceneAccuracy refine = compareGdmScenes(reference, refined, gdm.height, voxel);
    // A third above the measured numbers: fewer pixels than the 256 x 256 table, so more noise.
    EXPECT_LE(refine.hitMissDisagreePercent, 2.0);
    EXPECT_LE(refine.uvwP95Voxels, 0.4);
    // Refine with the distance volume needs no occupancy; march does, and sizes are checked.
    EXPECT_THROW(renderer.render(camera, kLight, 8, 8, GdmDirectionLookup::Nearest, gl::GdmTechnique::March),
                 Error);
    EXPECT_THROW(renderer.setDistance(std::vector<float>(7, 0.0f)), Error);
    EXPECT_THROW(renderer.setDistance(chain.distance, glm::ivec3(32, 32, 16)), Error);
    // A grid given explicitly is read as such: the GDM's own, the same picture.
    renderer.setDistance(chain.distance, glm::ivec3(64, 64, 16));
    const GdmSceneImages again =
        renderer.render(camera, kLight, kSize, kSize, GdmDirectionLookup::Nearest, gl::GdmTechnique::Refine);
    EXPECT_EQ(compareGdmScenes(refined, again, gdm.height, voxel).hitMissDisagreePercent, 0.0);
}

TEST(GdmPrismJacobian, IsTheAffineMapOfTheBaseAndTheMeanExtrusion) {
    // Corners P = O + M (u, v) on the base, each top = base + e: J = [M e / H] exactly.
    const glm::dvec3 origin(0.3, -1.0, 2.0), mu(2.0, 0.5, 0.0), mv(-0.25, 1.5, 0.75), e(0.1, 0.2, 0.4);
    const std::array<glm::dvec2, 3> tile = {glm::dvec2(1.0, 2.0), glm::dvec2(3.5, 2.25),
                                            glm::dvec2(0.5, 4.0)};
    std::array<glm::dvec3, 3> base, top;
    for (int c = 0; c < 3; ++c) {
        base[c] = origin + tile[c].x * mu + tile[c].y * mv;
        top[c] = base[c] + e;
    }
    const double height = 0.2;
    const glm::dmat3 j = gl::gdmPrismJacobian(base, top, tile, height);
    for (int r = 0; r < 3; ++r) {
        // Rounding of sums of a few terms of size ~10.
        EXPECT_NEAR(j[0][r], mu[r], 1e-12);
        EXPECT_NEAR(j[1][r], mv[r], 1e-12);
        EXPECT_NEAR(j[2][r], e[r] / height, 1e-12);
    }
    // The §8 quad: tile coordinates are world x, y and the shell is H thick, so J is the identity.
    const glm::dmat3 flat =
        gl::gdmPrismJacobian({glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(1, 1, 0)},
                             {glm::dvec3(0, 0, 0.25), glm::dvec3(1, 0, 0.25), glm::dvec3(1, 1, 0.25)},
                             {glm::dvec2(0, 0), glm::dvec2(1, 0), glm::dvec2(1, 1)}, 0.25);
    EXPECT_EQ(flat, glm::dmat3(1.0));
    // Degenerate tile coordinates: determinant 0.
    EXPECT_EQ(glm::determinant(gl::gdmPrismJacobian(base, top, {tile[0], tile[0], tile[1]}, height)), 0.0);
}

// The percentage of pixels hit in both whose shadows differ.
double shadowDifference(const GdmSceneImages& a, const GdmSceneImages& b) {
    int both = 0, differ = 0;
    for (int y = 0; y < a.mask.height(); ++y)
        for (int x = 0; x < a.mask.width(); ++x) {
            if (a.mask.at(x, y) == 0.0f || b.mask.at(x, y) == 0.0f) continue;
            ++both;
            differ += a.shadow.at(x, y) != b.shadow.at(x, y);
        }
    return both == 0 ? 0.0 : 100.0 * differ / both;
}

TEST_F(GdmRendererGl, JacobianLightFrameIsTheTangentOneWhereTheTextureFrameIsUnscaled) {
    const Gdm& gdm = weave().gdm;
    gl::GdmRenderer renderer;
    renderer.setGdm(gdm);
    const Camera camera = viewAt(45.0);
    auto both = [&](const Mesh& mesh, const PrismShellOptions& options, const Camera& view) {
        renderer.setMesh(mesh, options);
        renderer.setLightFrame(gl::GdmLightFrame::Tangent);
        const GdmSceneImages tangent = renderer.render(view, kLight, kSize, kSize);
        renderer.setLightFrame(gl::GdmLightFrame::Jacobian);
        const GdmSceneImages jacobian = renderer.render(view, kLight, kSize, kSize);
        // The light frame only changes the shadow.
        EXPECT_EQ(compareGdmScenes(tangent, jacobian, gdm.height, 1.0).hitMissDisagreePercent, 0.0);
        return shadowDifference(tangent, jacobian);
    };
    // The §8 quad: J = I, the same direction to float rounding (a pixel may flip on the exit rule's edge).
    EXPECT_LE(both(makeBuiltinMesh("quad"), {}, camera), 0.1);
    // Tiling 2: the texture frame is world scaled by 2 in u, v and (T = H / 2) in w H alike: J = I / 2,
    // the same direction once normalised.
    PrismShellOptions twice;
    twice.tiling = {2.0, 2.0};
    EXPECT_LE(both(makeBuiltinMesh("quad"), twice, camera), 0.1);
    // Tiling 2 x 1 stretches u alone: the light's direction in texture space changes, and so do shadows.
    PrismShellOptions stretched;
    stretched.tiling = {2.0, 1.0};
    // Measured 0.93 % of the pixels (most shadow rays' outcomes do not change with a tilt of the light).
    EXPECT_GT(both(makeBuiltinMesh("quad"), stretched, camera), 0.5);
    // A curved base (a sphere at tiling 4): the tangent frame follows the surface, the Jacobian also the
    // tiles' stretch, 2 : 1 here (u runs 3.14 around, v 1.57 pole to pole, 4 tiles each).
    PrismShellOptions sphere;
    sphere.tiling = {4.0, 4.0};
    const Mesh ball = makeBuiltinMesh("sphere", {2});
    const double curved = both(ball, sphere, frameCamera(meshBounds(ball), 1.0, 40.0));
    // Measured 9.7 % (25 % before the tangent frame, when the paper's direction was taken as world).
    EXPECT_GT(curved, 5.0);
}

// Pixels the base covers and the shell does not: where a ray reaches the mesh without crossing the shell.
int cracks(const Mesh& mesh, const PrismShellOptions& options, int size) {
    const Camera camera = frameCamera(meshBounds(mesh), 1.0, 40.0);
    gl::GdmRenderer renderer;
    renderer.setGdm(makeEmptyGdm(GdmDims{4, 4, 2, 2, 4}, options.height));
    renderer.setMesh(mesh, options);
    const Image base = renderer.renderPrismIds(camera, size, size, gl::PrismFaces::Base);
    const Image shell = renderer.renderPrismIds(camera, size, size, gl::PrismFaces::Shell);
    int count = 0, covered = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            covered += base.at(x, y) > 0.0f;
            count += base.at(x, y) > 0.0f && shell.at(x, y) == 0.0f;
        }
    EXPECT_GT(covered, size * size / 10) << mesh.name;  // the mesh is in the picture
    return count;
}

TEST_F(GdmRendererGl, TheShellHasNoCracks) {
    // Issue 18's crack test: prism ids on the teapot and a coarse sphere (and the cube's creases); no pixel
    // where the mesh shows without an entry face of the shell in front of it. Each prism is closed and its
    // faces face out (PrismShell tests), so this checks the GL side: the shell's faces drawn as the GDM pass
    // draws them (culled, with the shared fins' identical corners rasterised without gaps).
    PrismShellOptions options;
    options.height = 0.25;
    options.tiling = {4.0, 4.0};
    EXPECT_EQ(cracks(makeBuiltinMesh("teapot", {4}), options, 192), 0);
    EXPECT_EQ(cracks(makeBuiltinMesh("sphere", {2}), options, 192), 0);
    EXPECT_EQ(cracks(makeBuiltinMesh("cube", {2}), options, 192), 0);
}

// Mesa compiles what stricter drivers refuse; the reference compiler holds the GDM program to the GLSL 4.50
// specification, as ProgramVariants.PassGlslangValidator does the relief programs.
TEST(GdmProgram, PassesGlslangValidator) {
    const std::string validator = STRATA_GLSLANG_VALIDATOR;
    if (validator.empty())
        FAIL() << "glslangValidator not found (glslang-tools); run scripts/install-deps.sh";
    const std::filesystem::path dir = test::failureDirectory("glslang_gdm");
    std::filesystem::create_directories(dir);
    std::string command = "'" + validator + "'";
    for (const char* stage : {"vert", "frag"}) {
        const std::filesystem::path file = dir / (std::string("gdm.") + stage);
        std::ofstream(file)
            << gl::ShaderLibrary::embedded().preprocess(std::string("gdm/gdm.") + stage + ".glsl", {}).text;
        command += " '" + file.string() + "'";
    }
    EXPECT_EQ(std::system((command + " > '" + (dir / "log.txt").string() + "' 2>&1").c_str()), 0)
        << "see " << (dir / "log.txt").string();
}

TEST_F(GdmRendererGl, CountsTheMemoryItHolds) {
    const Gdm& gdm = weave().gdm;
    const GdmSvd svd = compressGdm(gdm, 8);
    gl::GdmRenderer renderer;
    // An unused storage buffer keeps 16 bytes (a zero-size one cannot be bound on every driver).
    constexpr std::size_t kEmpty = 16;
    renderer.setGdm(svd);
    EXPECT_EQ(renderer.gpuMemory().gdm, svd.mapBytes() + kEmpty);
    renderer.setGdm(gdm);
    EXPECT_EQ(renderer.gpuMemory().gdm, gdm.values.size() * sizeof(float) + 2 * kEmpty);
    // The volumes: a float per voxel of occupancy, three of linear albedo, one of signed distance.
    const std::size_t voxels = gdm.dims.voxelCount();
    renderer.setVolumes(gdmOccupancy(gdm), std::vector<std::uint8_t>(3 * voxels, 128));
    renderer.setDistance(std::vector<float>(voxels, 0.1f));
    EXPECT_EQ(renderer.gpuMemory().volumes, 5 * voxels * sizeof(float));
    // The shell: per prism 8 triangles x 3 corners x 2 vec4 of faces, 3 rows of its light frame, and its
    // vertices (7 entry triangles, the base twice: as the base and turned over).
    renderer.setMesh(makeBuiltinMesh("quad"), {});
    const gl::GdmGpuMemory memory = renderer.gpuMemory();
    EXPECT_GT(memory.shell, 2 * (48 + 3) * 16u);
    EXPECT_EQ(memory.total(), memory.gdm + memory.volumes + memory.shell);
}

TEST_F(GdmRendererGl, RefusesOtherLayouts) {
    const GdmSvd svd = compressGdm(weave().gdm, 2, GdmLayout::XyzByThetaPhi);
    EXPECT_THROW(gl::renderGdmScene(svd, viewAt(45.0), kLight, 16, 16), Error);
}

}  // namespace
}  // namespace strata
