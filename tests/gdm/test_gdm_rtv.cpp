// The diffuse radiance transfer volume (gdm_rtv.h): a flat slab under a constant sky (closed form), the
// bounces' monotonicity, bad input, and the error table against the path tracer (gdm_path_trace.h) on the
// weave lit by a band-limited sky.
#include "strata/core/error.h"
#include "strata/environment/environment.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_rtv.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"

#include "test_solids.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace strata {
namespace {

GdmAlbedo gray(double rho) {
    return [rho](const glm::dvec3&) { return glm::dvec3(rho); };
}

// The SH of a constant radiance l: only the band-0 coefficient, l sqrt(4 pi).
ShColor constantLighting(double l) {
    ShColor sh{};
    sh[0] = glm::dvec3(l * std::sqrt(4.0 * std::numbers::pi));
    return sh;
}

TEST(GdmRtv, FlatSlabUnderAConstantSkyIsAlbedoTimesSky) {
    const double height = 0.5, rho = 0.6, sky = 1.7;
    const SolidMesh slab = boxMesh({-0.25f, -0.25f, 0.0f}, {1.25f, 1.25f, float(height / 2)}, height);
    const GdmDims dims{4, 4, 8, 16, 32};
    const Gdm gdm = bakeGdm(slab, dims);
    const std::vector<float> distance = bakeGdmDistance(slab, dims);
    // The direction sum of cos(theta) dOmega over the upper hemisphere with 8 cells in theta (midpoint in
    // theta, exact cell solid angles): its relative error against pi, the only error on a flat top face.
    double cosineSum = 0.0;
    for (int t = 0; t < 8; ++t) {
        const double t0 = t * std::numbers::pi / 16, t1 = (t + 1) * std::numbers::pi / 16;
        cosineSum += std::cos((t + 0.5) * std::numbers::pi / 16) * 2.0 * std::numbers::pi *
                     (std::cos(t0) - std::cos(t1));
    }
    const double expected = rho * sky * cosineSum / std::numbers::pi;
    // 16 x 32 samples: the midpoint rule's error in theta, about 0.3%.
    EXPECT_NEAR(expected, rho * sky, 0.005 * rho * sky);
    for (int bounces : {0, 2}) {
        GdmRtvOptions options;
        options.bounces = bounces;
        const GdmRtv rtv = bakeGdmRtv(gdm, distance, gray(rho), options);
        EXPECT_EQ(rtv.transfer.size(), dims.voxelCount() * 48);
        // Points on the top face z = H / 2 (the voxels below it are inside and left out): nothing above it
        // in the slab, so no shadow and no interreflection. 1e-5 relative: float storage of the transfer.
        for (double u : {0.1, 0.37, 0.9}) {
            const glm::dvec3 radiance =
                rho * gdmRtvRadiance(rtv, {u, 0.6, height / 2}, constantLighting(sky));
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(radiance[c], expected, 1e-5 * expected) << bounces;
        }
        // Inside voxels hold 0.
        EXPECT_EQ(rtv.transfer[0], 0.0f);
    }
}

TEST(GdmRtv, RejectsBadInput) {
    const double height = 0.5;
    const SolidMesh slab = boxMesh({-0.25f, -0.25f, 0.0f}, {1.25f, 1.25f, float(height / 2)}, height);
    const GdmDims dims{2, 2, 2, 4, 4};
    const Gdm gdm = bakeGdm(slab, dims);
    const std::vector<float> distance = bakeGdmDistance(slab, dims);
    GdmRtvOptions options;
    options.bounces = GdmRtvOptions::kMaxBounces + 1;
    EXPECT_THROW(bakeGdmRtv(gdm, distance, gray(0.5), options), Error);
    EXPECT_THROW(bakeGdmRtv(gdm, std::vector<float>(3), gray(0.5)), Error);
    EXPECT_THROW(bakeGdmRtv(gdm, distance, GdmAlbedo{}), Error);
    Gdm broken = gdm;
    broken.values.pop_back();
    EXPECT_THROW(bakeGdmRtv(broken, distance, gray(0.5)), Error);
}

// The error table's scene: a built-in meshed at 64, baked at 32 x 32 x 8 x 16 x 32, seen from 45 degrees.
struct Scene {
    Mesostructure meso;
    SolidMesh solid;
    Gdm gdm;
    std::vector<float> distance;
    explicit Scene(const std::string& name)
        : meso(makeMesostructure(name)),
          solid(meshMesostructure(meso, 64)),
          gdm(bakeGdm(solid, GdmDims{32, 32, 8, 16, 32})),
          distance(bakeGdmDistance(solid, gdm.dims)) {}
};

Camera obliqueCamera() {
    return gdmSceneView(45.0);
}

TEST(GdmRtv, WeaveMatchesThePathTracerUnderABandLimitedSky) {
    const Scene scene("weave");
    const Environment environment = makeEnvironment("sky-overcast", 64, 32);
    const ShColor lighting = environment.sh();
    // The path tracer's sky is the same band-limited radiance, clamped >= 0 (a no-op where it is positive).
    const EnvironmentRadiance sky = [&lighting](const glm::dvec3& d) {
        return glm::max(shReconstruct(lighting, d), glm::dvec3(0.0));
    };
    // The overcast sky's band-3 reconstruction stays positive (checked on shProject's 2560 directions), so
    // the clamp changes nothing and both renderers see exactly the same sky.
    double lowest = 1e30;
    for (const glm::dvec3& d : shQuadrature().directions) {
        const glm::dvec3 l = shReconstruct(lighting, d);
        lowest = std::min({lowest, l.x, l.y, l.z});
    }
    EXPECT_GT(lowest, 0.0);
    const GdmAlbedo albedo = mesostructureLinearAlbedo(scene.meso);
    constexpr int kSize = 64, kSamples = 512;
    const Camera camera = obliqueCamera();
    const GdmSceneImages hits = renderGdmReference(scene.solid, camera, {0.5, 0.5, 3.0}, kSize, kSize);
    const Image surface = gdmSurfaceHitMask(hits);
    for (int bounces : {0, 1, 2}) {
        GdmRtvOptions rtvOptions;
        rtvOptions.bounces = bounces;
        const GdmRtv rtv = bakeGdmRtv(scene.gdm, scene.distance, albedo, rtvOptions);
        const Image shaded = shadeGdmSceneRtv(hits, rtv, lighting, albedo);
        GdmPathTraceOptions options;
        options.samplesPerPixel = kSamples;
        options.bounces = bounces;
        options.seed = 3;
        const GdmPathTraceImages a = pathTraceGdm(scene.solid, albedo, sky, camera, kSize, kSize, options);
        options.seed = 4;
        const GdmPathTraceImages b = pathTraceGdm(scene.solid, albedo, sky, camera, kSize, kSize, options);
        const double error = gdmRelativeRmse(shaded, surface, a.radiance, a.mask);
        const double errorAll = gdmRelativeRmse(shaded, hits.mask, a.radiance, a.mask);
        // The path tracer's own noise in the same measure: two independent renders differ by sqrt(2) sigma.
        const double noise = gdmRelativeRmse(b.radiance, surface, a.radiance, a.mask) / std::sqrt(2.0);
        // The relative RMSE over the surface hits (gdmSurfaceHitMask: the box's cut faces left out) with
        // 16 x 32 directions and 32 x 32 x 8 voxels; measured 7.0%, 8.0%, 7.9% for 0, 1, 2 bounces (with
        // the cut faces 24%). The path tracer's own noise in the same measure, sigma = 1.5% (two
        // independent renders differ by sqrt(2) sigma), inflates it by sqrt(e^2 + sigma^2) - e < 0.2%.
        std::printf(
            "weave, %d bounces: relative RMSE %.4f (with the cut faces %.4f), path tracer sigma %.4f\n",
            bounces, error, errorAll, noise);
        EXPECT_LT(noise, 0.02);  // 512 paths per pixel: 1.5% measured; well below the error
        // The number: <= 10% with one bounce; 0 and 2 bounces measure the same (7.0%, 7.9%).
        EXPECT_LE(error, 0.10);
    }
}

TEST(GdmRtv, SvdErrorFallsWithRankAndFullRankIsExact) {
    const Scene scene("weave");
    const GdmRtv rtv = bakeGdmRtv(scene.gdm, scene.distance, mesostructureLinearAlbedo(scene.meso));
    double previous = 2.0;
    for (int rank : {1, 2, 4, 8, 16, 48}) {
        const GdmRtvSvd svd = compressGdmRtv(rtv, rank);
        ASSERT_EQ(svd.singularValues.size(), 48u);
        const GdmRtv back = svd.reconstruct();
        double error = 0.0, norm = 0.0;
        for (std::size_t n = 0; n < rtv.transfer.size(); ++n) {
            const double a = rtv.transfer[n], b = back.transfer[n];
            error += (a - b) * (a - b);
            norm += a * a;
        }
        const double measured = std::sqrt(error / norm);
        std::printf("RTV SVD rank %d: relative Frobenius error %.5f (from the singular values %.5f)\n", rank,
                    measured, svd.relativeError());
        // The truncation error is the discarded singular values' share (Eckart-Young); 1e-4: the float
        // storage of W and E (relative rounding about 1e-7 per product, summed over 48 columns) and the Gram
        // matrix's squaring of the conditioning.
        EXPECT_NEAR(measured, svd.relativeError(), 1e-4) << rank;
        EXPECT_LE(svd.relativeError(), previous) << rank;
        previous = svd.relativeError();
    }
    EXPECT_LT(previous, 1e-6);  // rank 48 keeps every singular value
    EXPECT_THROW(compressGdmRtv(rtv, 0), Error);
    EXPECT_THROW(compressGdmRtv(rtv, 49), Error);
}

}  // namespace
}  // namespace strata
