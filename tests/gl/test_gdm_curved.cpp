// GDM on curved bases (issue 18, "Curved bases"): the GL renderer's paper algorithm (raw GDM and rank 8) on a
// coarse torus and an open cylinder against the exact reference (strata/gdm/gdm_mesh_reference.h), by the
// silhouette measures; and relief mapping of the same mesostructure's height field on the same views, which
// has no silhouettes and must score clearly worse.
//
// Pictures for docs/gdm.md: STRATA_GDM_CURVED_PICTURES=<folder> runs the same cases at 256 x 256, prints
// their numbers and writes per case <folder>/gdm_curved_<mesh>.png (8-bit): reference uvw | GL raw uvw |
// GL rank 8 uvw | relief mask, and <folder>/gdm_curved_<mesh>_masks.png, the reference's and GL raw's
// masks against each other (white both, red reference only, green GL only).
#include "../gdm/test_solids.h"
#include "gl_test_support.h"

#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_mesh_reference.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/image/image_io.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/relief_texture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace strata {
namespace {

using test::GlTest;

class GdmCurvedGl : public GlTest {};

// The built-in cylinder without its caps (their planar uvs meet the side's at a seam): the triangles whose
// corners all have a side normal.
Mesh openCylinder(int tessellation) {
    Mesh mesh = makeBuiltinMesh("cylinder", {tessellation});
    std::vector<std::uint32_t> side;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        bool isSide = true;
        for (std::size_t k = 0; k < 3; ++k)
            isSide = isSide && std::abs(mesh.vertices[mesh.indices[t + k]].normal.z) < 0.5f;
        if (isSide)
            side.insert(side.end(), mesh.indices.begin() + std::ptrdiff_t(t),
                        mesh.indices.begin() + std::ptrdiff_t(t + 3));
    }
    mesh.indices = side;
    mesh.name = "open cylinder";
    return mesh;
}

// The mesostructure's top height field as a relief depth map (CONVENTIONS §1-§2, d = 1 - z_top / H): per
// texel centre, the first solid point straight down from z = H (sphere tracing on its distance bound, which
// never oversteps); d = 1 where the column is empty.
Image topDepth(const Mesostructure& meso, int size) {
    Image depth(size, size, 1);
    const double height = meso.height();
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const double u = (i + 0.5) / size, v = 1.0 - (j + 0.5) / size;
            double z = height;
            while (z > 0.0) {
                const double d = meso.distance({u, v, z});
                if (d < 1e-5) break;
                z -= std::max(d, 1e-5);
            }
            depth.at(i, j) = float(1.0 - std::max(z, 0.0) / height);
        }
    return depth;
}

// The mesh as the relief renderer draws it: the shell's top (each vertex moved to its shell vertex's top,
// so that the relief's d = 0 is the GDM's w = 1 and, at depth scale H, d = 1 is its base), uvs times the
// tiling (the relief renderer's tiling is one number; it draws at 1).
Mesh reliefMesh(const Mesh& mesh, const PrismShellOptions& options) {
    const PrismShell shell = buildPrismShell(mesh, options);
    Mesh top = mesh;
    for (std::size_t p = 0; p < shell.prisms.size(); ++p)
        for (std::size_t i = 0; i < 3; ++i)
            top.vertices[shell.corners[p][i]].position = shell.top[shell.prisms[p][i]];
    for (MeshVertex& v : top.vertices)
        v.uv = glm::vec2(float(options.tiling.x) * v.uv.x, float(options.tiling.y) * v.uv.y);
    return top;
}

struct Case {
    std::string name;
    Mesh mesh;
    std::string meso;
    PrismShellOptions shell;
    Camera camera;
    glm::dvec3 light;
};

// Coarse meshes seen low over their outline, so that much of each picture is silhouette: the torus (8 x 8
// quads) with chain mail, the open cylinder (8 sides) with the grid of rods.
std::vector<Case> cases() {
    std::vector<Case> result(2);
    result[0].name = "torus";
    result[0].mesh = makeBuiltinMesh("torus", {2});
    result[0].meso = "chain";
    result[0].shell.tiling = {8.0, 4.0};
    result[0].camera.eye = {0.0, -2.0, 0.5};
    result[1].name = "cylinder";
    result[1].mesh = openCylinder(2);
    result[1].meso = "grid";
    result[1].shell.tiling = {8.0, 3.0};
    result[1].camera.eye = {0.0, -2.6, 0.3};
    for (Case& c : result) {
        c.camera.target = {0.0, 0.0, 0.0};
        c.camera.fovYDegrees = 32.0;
        c.light = {1.0, -2.0, 3.0};
    }
    return result;
}

struct Measured {
    GdmSceneImages reference, raw, rank8;
    Image relief;  // mask
    double iouRaw, iouRank8, iouRelief;
    double hausdorffRaw, hausdorffRank8, hausdorffRelief;
    // Against the reference without hits through a base (GdmMeshReferenceOptions::throughBase = false).
    double iouRawAbove, hausdorffRawAbove;
    // GL raw without entries through the base (GdmRenderer::setBaseEntry(false), the paper's shell).
    double iouRawNoBase, hausdorffRawNoBase;
    // Refine on the signed distance volume.
    double iouRefine, hausdorffRefine;
    // Shadow agreement with the reference over the pixels both hit: the light direction in the surface's
    // tangent frame (the paper's) and mapped by each prism's Jacobian, for GL raw and refine.
    double shadowTangent, shadowJacobian, shadowRefineTangent, shadowRefineJacobian;
    GdmMeshReferenceStats stats;
};

Measured measure(const Case& c, int size) {
    Measured m;
    const Mesostructure meso = makeMesostructure(c.meso);
    const SolidMesh solid = meshMesostructure(meso, 32);
    // 32 voxels per tile width along z too (chain: H = 0.5, 16 layers), 16 x 32 directions (§8's default).
    const int layers = int(std::lround(32.0 * meso.height()));
    const Gdm gdm = bakeGdm(solid, GdmDims{32, 32, layers, 16, 32});
    const GdmSvd svd = compressGdm(gdm, 8);
    PrismShellOptions shell = c.shell;
    shell.height = solid.height;
    m.reference = renderGdmMeshReference(solid, c.mesh, shell, c.camera, c.light, size, size, {}, &m.stats);
    GdmMeshReferenceOptions above;
    above.throughBase = false;
    const GdmSceneImages referenceAbove =
        renderGdmMeshReference(solid, c.mesh, shell, c.camera, c.light, size, size, above);
    gl::GdmRenderer renderer;
    renderer.setGdm(gdm);
    renderer.setMesh(c.mesh, shell);
    m.raw = renderer.render(c.camera, c.light, size, size);
    const double voxel = solid.height / layers;
    m.shadowTangent = compareGdmScenes(m.reference, m.raw, solid.height, voxel).shadowAgreePercent;
    renderer.setLightFrame(GdmLightFrame::Jacobian);
    m.shadowJacobian =
        compareGdmScenes(m.reference, renderer.render(c.camera, c.light, size, size), solid.height, voxel)
            .shadowAgreePercent;
    renderer.setLightFrame(GdmLightFrame::Tangent);
    renderer.setBaseEntry(false);
    const GdmSceneImages noBase = renderer.render(c.camera, c.light, size, size);
    renderer.setBaseEntry(true);
    m.iouRawNoBase = silhouetteIoU(m.reference.mask, noBase.mask);
    m.hausdorffRawNoBase = silhouetteHausdorff(m.reference.mask, noBase.mask);
    renderer.setVolumes(gdmOccupancy(gdm), {});
    renderer.setDistance(bakeGdmDistance(solid, GdmDims{32, 32, layers, 16, 32}));
    const GdmSceneImages refine =
        renderer.render(c.camera, c.light, size, size, GdmDirectionLookup::Nearest, gl::GdmTechnique::Refine);
    m.iouRefine = silhouetteIoU(m.reference.mask, refine.mask);
    m.hausdorffRefine = silhouetteHausdorff(m.reference.mask, refine.mask);
    m.shadowRefineTangent = compareGdmScenes(m.reference, refine, solid.height, voxel).shadowAgreePercent;
    renderer.setLightFrame(GdmLightFrame::Jacobian);
    m.shadowRefineJacobian =
        compareGdmScenes(m.reference,
                         renderer.render(c.camera, c.light, size, size, GdmDirectionLookup::Nearest,
                                         gl::GdmTechnique::Refine),
                         solid.height, voxel)
            .shadowAgreePercent;
    renderer.setGdm(svd);
    renderer.setMesh(c.mesh, shell);
    m.rank8 = renderer.render(c.camera, c.light, size, size);

    ReliefTexture texture;
    texture.depth = topDepth(meso, 128);
    texture.depthScale = meso.height();
    texture.normal = normalsFromDepth(texture.depth, texture.depthScale);
    const gl::GpuMaterial material = gl::uploadMaterial(texture, texture.depthScale);
    const gl::GpuMesh top = gl::uploadMesh(reliefMesh(c.mesh, shell));
    gl::RenderRequest request;
    request.objects.push_back({&top, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
    request.camera = c.camera;
    request.relief.linearSteps = 32;
    request.relief.binarySteps = 8;
    request.relief.depthScale = meso.height();
    request.lighting.lightPosition = c.light;
    request.picture.width = size;
    request.picture.height = size;
    request.picture.output = RenderOutput::Uv;
    gl::ReliefRenderer relief;
    const Image uv = relief.render(request);
    m.relief = Image(size, size, 1);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) m.relief.at(x, y) = uv.at(x, y, 2) > 0.5f ? 1.0f : 0.0f;

    m.iouRaw = silhouetteIoU(m.reference.mask, m.raw.mask);
    m.iouRank8 = silhouetteIoU(m.reference.mask, m.rank8.mask);
    m.iouRelief = silhouetteIoU(m.reference.mask, m.relief);
    m.hausdorffRaw = silhouetteHausdorff(m.reference.mask, m.raw.mask);
    m.hausdorffRank8 = silhouetteHausdorff(m.reference.mask, m.rank8.mask);
    m.hausdorffRelief = silhouetteHausdorff(m.reference.mask, m.relief);
    m.iouRawAbove = silhouetteIoU(referenceAbove.mask, m.raw.mask);
    m.hausdorffRawAbove = silhouetteHausdorff(referenceAbove.mask, m.raw.mask);
    return m;
}

void writePictures(const std::filesystem::path& folder, const Case& c, const Measured& m) {
    const int size = m.reference.mask.width();
    Image strip(4 * size, size, 3);
    const Image* panels[3] = {&m.reference.uvw, &m.raw.uvw, &m.rank8.uvw};
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            for (int p = 0; p < 3; ++p)
                for (int ch = 0; ch < 3; ++ch) strip.at(p * size + x, y, ch) = panels[p]->at(x, y, ch);
            for (int ch = 0; ch < 3; ++ch) strip.at(3 * size + x, y, ch) = m.relief.at(x, y);
        }
    Image masks(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float a = m.reference.mask.at(x, y), b = m.raw.mask.at(x, y);
            masks.at(x, y, 0) = a;
            masks.at(x, y, 1) = b;
            masks.at(x, y, 2) = std::min(a, b);
        }
    PngWriteOptions eight;
    eight.bitDepth = PngBitDepth::Eight;
    eight.dither = false;
    std::filesystem::create_directories(folder);
    writePng(folder / ("gdm_curved_" + c.name + ".png"), strip, eight);
    writePng(folder / ("gdm_curved_" + c.name + "_masks.png"), masks, eight);
}

TEST_F(GdmCurvedGl, SilhouettesAgainstTheExactReference) {
    const char* pictures = std::getenv("STRATA_GDM_CURVED_PICTURES");
    // 160 x 160 keeps the test to a few seconds on llvmpipe; the docs' table is at 256 x 256.
    const int size = pictures ? 256 : 160;
    for (const Case& c : cases()) {
        const Measured m = measure(c, size);
        std::printf(
            "%s + %s at %d: IoU raw %.3f rank 8 %.3f relief %.3f | Hausdorff raw %.1f rank 8 %.1f relief "
            "%.1f | raw vs the reference without hits through a base: IoU %.3f Hausdorff %.1f | "
            "reference: %zu flat triangles, %zu hits through a base\n",
            c.name.c_str(), c.meso.c_str(), size, m.iouRaw, m.iouRank8, m.iouRelief, m.hausdorffRaw,
            m.hausdorffRank8, m.hausdorffRelief, m.iouRawAbove, m.hausdorffRawAbove,
            m.stats.solidTriangles + m.stats.boundaryTriangles, m.stats.hitsFromBelow);
        std::printf(
            "%s: without base entries IoU %.3f Hausdorff %.1f | refine IoU %.3f Hausdorff %.1f | shadow "
            "agreement gdm raw tangent %.1f%% jacobian %.1f%%, refine tangent %.1f%% jacobian %.1f%%\n",
            c.name.c_str(), m.iouRawNoBase, m.hausdorffRawNoBase, m.iouRefine, m.hausdorffRefine,
            m.shadowTangent, m.shadowJacobian, m.shadowRefineTangent, m.shadowRefineJacobian);
        if (pictures) writePictures(pictures, c, m);
        // No camera ray slipped into the warped solid through a crack.
        EXPECT_EQ(m.stats.exitFaceCrossings, 0u) << c.name;
        // Measured at 160 x 160 (torus / cylinder): IoU raw 0.759 / 0.860, rank 8 0.686 / 0.755; Hausdorff
        // raw 7.1 / 5.0, rank 8 12.0 / 10.4 pixels. Most of the IoU's loss is the GDM's own hit / miss error
        // on thin links and rods (the flat scene's, docs/gdm.md), not the silhouette; the Hausdorff distance
        // is set by the farthest lone speck or hole, so its bounds are loose. About 0.05 of IoU and 50 % of
        // Hausdorff below / above the measurements.
        EXPECT_GT(m.iouRaw, 0.70) << c.name;
        EXPECT_GT(m.iouRank8, 0.63) << c.name;
        EXPECT_LT(m.hausdorffRaw, 12.0) << c.name;
        EXPECT_LT(m.hausdorffRank8, 18.0) << c.name;
        // Entering prisms through the base from below shows what the reference sees through the holes:
        // without it (the paper's shell) IoU raw 0.723 / 0.748. At least 0.015 better (measured 0.036 /
        // 0.112).
        EXPECT_GT(m.iouRaw, m.iouRawNoBase + 0.015) << c.name;
        // Refine on the distance volume (here at 32 voxels per tile: the chain's links are 2-3 voxels thick,
        // so its trilinear distance loses some): measured IoU 0.742 / 0.948, Hausdorff 5.1 / 4.0.
        EXPECT_GT(m.iouRefine, 0.69) << c.name;
        EXPECT_LT(m.hausdorffRefine, 8.0) << c.name;
        // Shadows: the reference's are the whole shell's (a ray to the light may meet another part of the
        // mesh's mesostructure), the GDM's the tile slab's along one direction, so agreement is far from
        // complete. Measured tangent frame (the paper's) / Jacobian: 56.8 / 55.2 % (torus) and 81.1 / 80.0 %
        // (cylinder) for the lookup, 60.2 / 60.5 % and 84.3 / 85.3 % for refine; the world direction taken
        // literally as the texture one gave 54.5 and 67.1 % for the lookup. The two frames are within 3
        // points of each other here (these tiles are about square), and each is at least 5 points under its
        // measurement.
        EXPECT_NEAR(m.shadowJacobian, m.shadowTangent, 3.0) << c.name;
        EXPECT_NEAR(m.shadowRefineJacobian, m.shadowRefineTangent, 3.0) << c.name;
        EXPECT_GT(m.shadowTangent, c.name == "torus" ? 51.0 : 76.0) << c.name;
        EXPECT_GT(m.shadowRefineTangent, c.name == "torus" ? 55.0 : 79.0) << c.name;
        // Relief mapping fills the shell's whole outline (no silhouette, no holes): measured IoU 0.588 /
        // 0.596 and Hausdorff 45.8 / 59.0 pixels. The measures must tell it from the GDM by a clear margin:
        // 0.08 of IoU below GL raw (measured 0.171 / 0.264) and 0.04 below rank 8 (0.098 / 0.159), and 3
        // times the GL's Hausdorff distance (measured 3.8 and 5.7 times).
        EXPECT_LT(m.iouRelief, m.iouRaw - 0.08) << c.name;
        EXPECT_LT(m.iouRelief, m.iouRank8 - 0.04) << c.name;
        EXPECT_GT(m.hausdorffRelief, 3.0 * std::max(m.hausdorffRaw, m.hausdorffRank8)) << c.name;
    }
}

// A slab filling every tile up to half the shell warps into the shell's middle surface, which the reference
// traces exactly. Refine on its signed distance (a plane: trilinear interpolation holds it exactly) must find
// that surface wherever it is seen: what is left is the texture-space ray's straightness within a prism (the
// paper's Sec. 3.2: "the texture distortion could be made arbitrarily small by more finely tessellating"),
// which shrinks as the torus is tessellated more finely.
TEST_F(GdmCurvedGl, RefineFindsAHalfSlabOnATorusToTheTessellationsDistortion) {
    constexpr int kSize = 128;
    constexpr double kHeight = 0.25;
    const SolidMesh slab = boxMesh({-0.25f, -0.25f, 0.0f}, {1.25f, 1.25f, float(kHeight / 2)}, kHeight);
    const GdmDims dims{16, 16, 8, 8, 16};
    const Gdm gdm = bakeGdm(slab, dims);
    const std::vector<float> distance = bakeGdmDistance(slab, dims);
    const double voxel = kHeight / dims.nz;
    Camera camera;
    camera.eye = {0.3, -1.6, 0.9};
    camera.target = {0.0, 0.0, 0.0};
    camera.fovYDegrees = 40.0;
    const glm::dvec3 light{1.0, -1.0, 2.0};
    double meanError[2] = {0.0, 0.0};
    const int tessellations[2] = {2, 8};
    for (int n = 0; n < 2; ++n) {
        const Mesh torus = makeBuiltinMesh("torus", {tessellations[n]});
        PrismShellOptions options;
        options.height = kHeight;
        options.tiling = {8.0, 4.0};
        const GdmSceneImages reference =
            renderGdmMeshReference(slab, torus, options, camera, light, kSize, kSize);
        gl::GdmRenderer renderer;
        renderer.setGdm(gdm);
        renderer.setMesh(torus, options);
        renderer.setVolumes(gdmOccupancy(gdm), {});
        renderer.setDistance(distance);
        const GdmSceneImages gl = renderer.render(camera, light, kSize, kSize, GdmDirectionLookup::Nearest,
                                                  gl::GdmTechnique::Refine);
        const GdmSceneAccuracy accuracy = compareGdmScenes(reference, gl, kHeight, voxel);
        const double iou = silhouetteIoU(reference.mask, gl.mask);
        std::printf(
            "half slab on a torus (tessellation %d) at %d: IoU %.4f, hit/miss %.3f %%, uvw mean %.3f p99 "
            "%.3f voxels\n",
            tessellations[n], kSize, iou, accuracy.hitMissDisagreePercent, accuracy.uvwMeanVoxels,
            accuracy.uvwP99Voxels);
        // Measured: IoU 1 and no hit / miss disagreement at both; uvw mean 0.459 / 0.172, p99 1.645 / 0.525
        // voxels (at tessellation 2 / 8).
        EXPECT_GT(iou, 0.999) << tessellations[n];
        EXPECT_LT(accuracy.hitMissDisagreePercent, 0.1) << tessellations[n];
        EXPECT_LT(accuracy.uvwP99Voxels, n == 0 ? 2.5 : 0.8) << tessellations[n];
        meanError[n] = accuracy.uvwMeanVoxels;
    }
    // Four times the segments per quarter turn: the distortion at least halves (measured 0.37 times).
    EXPECT_LT(meanError[1], 0.5 * meanError[0]);
}

}  // namespace
}  // namespace strata
