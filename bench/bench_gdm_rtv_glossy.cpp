// The glossy radiance transfer volume (strata/gdm/gdm_rtv_glossy.h): its bake, its SVD, and its error
// against the path tracer's glossy term (strata/gdm/gdm_path_trace.h).
//
// Every case: the built-in `weave` (makeMesostructure defaults) meshed by meshMesostructure at 64, its GDM
// (bakeGdm) and signed distance (bakeGdmDistance) at 64 x 64 x 16 voxels x 16 x 32 directions (so 8 x 32 =
// 256 view directions), outside the timing; Phong exponent s = 8.
//
// BM_GdmGlossyBake: timed: bakeGdmGlossyRtv with the method of the argument (0: ShadowedMatrix, G = M b;
// 1: DirectSum). Counters: MiB = the uncompressed glossy RTV (16 x 256 floats per voxel and the distance
// volume).
//
// BM_GdmGlossySvd: the ShadowedMatrix RTV compressed (compressGdmGlossyRtv) at the rank of the argument;
// timed: the compression (16 Gram matrices of 256 x 256 and their eigenvectors). Counters: frob = the
// relative Frobenius error (from the singular values), MiB = W, E and the distance volume, shade = the
// relative RMSE of the compressed RTV's glossy shading against the uncompressed one's over the surface hits
// (scene as in BM_GdmGlossyError).
//
// BM_GdmGlossyError: the RTV's glossy term (shadeGdmSceneGlossy, uncompressed and rank 4) and with the
// diffuse RTV (bakeGdmRtv, 0 bounces) against pathTraceGdm with specular 0.5, s = 8, 0 bounces, 128 x 128
// pixels, 256 paths per pixel (seed 1; its glossy term alone: the render minus the render without it, same
// seed; the noise from a second render with seed 2). Lighting: `sky-overcast` (makeEnvironment at 64 x 32)
// through its SH; the path tracer gets the band-limited radiance max(shReconstruct(sh, d), 0) (positive for
// this sky). Camera: gdmSceneView(45). Counters: glossy, glossy4 = the relative RMSE of the glossy term
// (uncompressed, rank 4) over the surface hits (gdmSurfaceHitMask); total, total4 = the same for diffuse +
// glossy; sigma = the path tracer's own noise in the total (the relative RMSE of two seeds / sqrt 2). The
// iteration times the whole comparison once.
// Run: build/ci/bench/bench_gdm_rtv_glossy --benchmark_min_time=0.01
#include "strata/environment/environment.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_rtv.h"
#include "strata/gdm/gdm_rtv_glossy.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"

#include <benchmark/benchmark.h>
#include <glm/common.hpp>

#include <cmath>
#include <memory>

namespace {

constexpr double kSpecular = 0.5;
constexpr int kSize = 128;

struct Baked {
    strata::Mesostructure meso = strata::makeMesostructure("weave");
    strata::SolidMesh solid = strata::meshMesostructure(meso, 64);
    strata::Gdm gdm = strata::bakeGdm(solid, strata::GdmDims{64, 64, 16, 16, 32});
    std::vector<float> distance = strata::bakeGdmDistance(solid, gdm.dims);
};

const Baked& weave() {
    static const Baked baked;
    return baked;
}

// The ShadowedMatrix RTV, baked once for the SVD and error cases.
const strata::GdmGlossyRtv& glossyRtv() {
    static const strata::GdmGlossyRtv rtv = strata::bakeGdmGlossyRtv(weave().gdm, weave().distance);
    return rtv;
}

strata::ShColor lighting() {
    return strata::makeEnvironment("sky-overcast", 64, 32).sh();
}

const strata::GdmSceneImages& hits() {
    static const strata::GdmSceneImages images =
        strata::renderGdmReference(weave().solid, strata::gdmSceneView(45.0), {0.5, 0.5, 3.0}, kSize, kSize);
    return images;
}

void BM_GdmGlossyBake(benchmark::State& state) {
    const Baked& scene = weave();
    strata::GdmGlossyOptions options;
    options.method =
        state.range(0) == 0 ? strata::GdmGlossyMethod::ShadowedMatrix : strata::GdmGlossyMethod::DirectSum;
    std::size_t bytes = 0;
    for (auto _ : state) {
        const strata::GdmGlossyRtv rtv = strata::bakeGdmGlossyRtv(scene.gdm, scene.distance, options);
        bytes = rtv.bytes();
    }
    state.counters["MiB"] = double(bytes) / (1024.0 * 1024.0);
}
BENCHMARK(BM_GdmGlossyBake)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_GdmGlossySvd(benchmark::State& state) {
    const strata::GdmGlossyRtv& rtv = glossyRtv();
    const int rank = int(state.range(0));
    strata::GdmGlossyRtvSvd svd;
    for (auto _ : state) svd = strata::compressGdmGlossyRtv(rtv, rank);
    const strata::Camera camera = strata::gdmSceneView(45.0);
    const strata::Image surface = strata::gdmSurfaceHitMask(hits());
    const strata::Image full = strata::shadeGdmSceneGlossy(hits(), rtv, camera, lighting(), kSpecular);
    const strata::Image compressed = strata::shadeGdmSceneGlossy(hits(), svd, camera, lighting(), kSpecular);
    state.counters["frob"] = svd.relativeError();
    state.counters["shade"] = strata::gdmRelativeRmse(compressed, surface, full, surface);
    state.counters["MiB"] = double(svd.bytes()) / (1024.0 * 1024.0);
}
BENCHMARK(BM_GdmGlossySvd)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Arg(8)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

void BM_GdmGlossyError(benchmark::State& state) {
    const Baked& scene = weave();
    const strata::ShColor sh = lighting();
    const strata::EnvironmentRadiance sky = [&sh](const glm::dvec3& d) {
        return glm::max(strata::shReconstruct(sh, d), glm::dvec3(0.0));
    };
    const strata::GdmAlbedo albedo = strata::mesostructureLinearAlbedo(scene.meso);
    const strata::Camera camera = strata::gdmSceneView(45.0);
    for (auto _ : state) {
        const strata::Image surface = strata::gdmSurfaceHitMask(hits());
        strata::GdmRtvOptions rtvOptions;
        rtvOptions.bounces = 0;
        const strata::GdmRtv rtv = strata::bakeGdmRtv(scene.gdm, scene.distance, albedo, rtvOptions);
        const strata::GdmGlossyRtvSvd svd = strata::compressGdmGlossyRtv(glossyRtv(), 4);
        const strata::Image diffuse = strata::shadeGdmSceneRtv(hits(), rtv, sh, albedo);
        const strata::Image glossy = strata::shadeGdmSceneGlossy(hits(), glossyRtv(), camera, sh, kSpecular);
        const strata::Image glossy4 = strata::shadeGdmSceneGlossy(hits(), svd, camera, sh, kSpecular);
        strata::GdmPathTraceOptions options;
        options.samplesPerPixel = 256;
        options.bounces = 0;
        options.seed = 1;
        const strata::GdmPathTraceImages plain =
            strata::pathTraceGdm(scene.solid, albedo, sky, camera, kSize, kSize, options);
        options.specular = kSpecular;
        options.shininess = 8.0;
        const strata::GdmPathTraceImages a =
            strata::pathTraceGdm(scene.solid, albedo, sky, camera, kSize, kSize, options);
        options.seed = 2;
        const strata::GdmPathTraceImages b =
            strata::pathTraceGdm(scene.solid, albedo, sky, camera, kSize, kSize, options);
        strata::Image reference(kSize, kSize, 3), total(kSize, kSize, 3), total4(kSize, kSize, 3);
        for (int j = 0; j < kSize; ++j)
            for (int i = 0; i < kSize; ++i)
                for (int c = 0; c < 3; ++c) {
                    reference.at(i, j, c) = a.radiance.at(i, j, c) - plain.radiance.at(i, j, c);
                    total.at(i, j, c) = diffuse.at(i, j, c) + glossy.at(i, j, c);
                    total4.at(i, j, c) = diffuse.at(i, j, c) + glossy4.at(i, j, c);
                }
        state.counters["glossy"] = strata::gdmRelativeRmse(glossy, surface, reference, a.mask);
        state.counters["glossy4"] = strata::gdmRelativeRmse(glossy4, surface, reference, a.mask);
        state.counters["total"] = strata::gdmRelativeRmse(total, surface, a.radiance, a.mask);
        state.counters["total4"] = strata::gdmRelativeRmse(total4, surface, a.radiance, a.mask);
        state.counters["sigma"] =
            strata::gdmRelativeRmse(b.radiance, surface, a.radiance, a.mask) / std::sqrt(2.0);
    }
}
BENCHMARK(BM_GdmGlossyError)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
