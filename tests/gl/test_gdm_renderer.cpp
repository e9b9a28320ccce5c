// The GDM verification scene in OpenGL (strata/gl/gdm_renderer.h) against its CPU twin, emulateGdm: the same
// algorithm in float on the GPU must give the same pictures (issue 18: identical hit / miss on >= 99.5 % of
// the pixels), raw and SVD, and against the exact reference as closely as the CPU does.
#include "gl_test_support.h"

#include "strata/core/error.h"
#include "strata/gdm/gdm_analytic.h"
#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/gl/program.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

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
    const double a = degrees * 3.14159265358979323846 / 180.0;
    Camera camera;
    camera.eye = glm::dvec3(0.5, 0.5 - 1.6 * std::sin(a), 1.6 * std::cos(a));
    camera.target = glm::dvec3(0.5, 0.5, 0.0);
    camera.fovYDegrees = 45.0;
    return camera;
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
        // The bound: the float shader and the double emulation agree on hit / miss almost
        // everywhere; where they disagree a lookup sits on the d < dt edge within float rounding.
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

TEST_F(GdmRendererGl, RefusesOtherLayouts) {
    const GdmSvd svd = compressGdm(weave().gdm, 2, GdmLayout::XyzByThetaPhi);
    EXPECT_THROW(gl::renderGdmScene(svd, viewAt(45.0), kLight, 16, 16), Error);
}

}  // namespace
}  // namespace strata
