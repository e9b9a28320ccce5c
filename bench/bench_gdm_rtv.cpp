// The diffuse radiance transfer volume (strata/gdm/gdm_rtv.h): its bake, and its error against the path
// tracer (strata/gdm/gdm_path_trace.h).
//
// BM_GdmRtvBake: the built-in `weave` (makeMesostructure defaults) meshed by meshMesostructure at 64, its
// GDM (bakeGdm) and signed distance (bakeGdmDistance) at 64 x 64 x 16 x 16 x 32, all outside the timing;
// timed: bakeGdmRtv with albedo mesostructureLinearAlbedo, bounces 0, 1, 2 (the argument). Counters:
// MiB = the RTV's memory (transfer, 16 x 3 floats per voxel, and the distance volume, 1 float per voxel).
//
// BM_GdmRtvError: the error table. The built-in `weave` (argument 0) or `chain` (1), meshed at 64, GDM and
// distance at 64 x 64 x 16 x 16 x 32, the RTV with 0, 1, 2 bounces, shaded (shadeGdmSceneRtv) at the hits of
// renderGdmReference, against pathTraceGdm of the same scene (same mesh, albedo, camera), 256 x 256,
// 256 paths per pixel (seed 1; the noise from a second render with seed 2). Lighting: the built-in
// environment `sky-overcast` (makeEnvironment at 64 x 32) through its SH: the RTV gets Environment::sh(),
// the path tracer the band-limited radiance max(shReconstruct(sh, direction), 0) (positive everywhere for
// this sky: the clamp is a no-op). Camera: looking at (0.5, 0.5, 0) from distance 1.6 at 45 degrees from
// the normal (eye (0.5, 0.5 - 1.6 sin 45, 1.6 cos 45)), vertical field of view 45 degrees. Counters: relN =
// the relative RMSE sqrt(sum |a - b|^2 / sum |b|^2) over the surface hits (gdmSurfaceHitMask: the box's cut
// faces left out) with N bounces; allN the same over every pixel where both hit; sigmaN the path tracer's
// own noise in the surface measure (the relative RMSE of two seeds / sqrt 2). The iteration times the whole
// table (bakes, shading and path tracing), once.
//
// BM_GdmRtvSvd: the weave's RTV as above with 1 bounce, compressed (compressGdmRtv) at the rank of the
// argument; timed: the compression. Counters: frob = the relative Frobenius error (from the singular
// values), shade = the relative RMSE of the compressed RTV's shading against the full RTV's over the surface
// hits (same scene, camera and lighting as BM_GdmRtvError, 256 x 256), MiB = W, E and the distance volume.
// Run: build/ci/bench/bench_gdm_rtv --benchmark_min_time=0.01
#include "strata/environment/environment.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_rtv.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"

#include <benchmark/benchmark.h>
#include <glm/common.hpp>

#include <cmath>
#include <map>
#include <numbers>
#include <string>

namespace {

struct Baked {
    strata::Mesostructure meso;
    strata::SolidMesh solid;
    strata::Gdm gdm;
    std::vector<float> distance;
    explicit Baked(const std::string& name)
        : meso(strata::makeMesostructure(name)),
          solid(strata::meshMesostructure(meso, 64)),
          gdm(strata::bakeGdm(solid, strata::GdmDims{64, 64, 16, 16, 32})),
          distance(strata::bakeGdmDistance(solid, gdm.dims)) {}
};

const Baked& baked(const std::string& name) {
    static std::map<std::string, Baked> cache;
    auto it = cache.find(name);
    if (it == cache.end()) it = cache.emplace(name, Baked(name)).first;
    return it->second;
}

strata::Camera camera() {
    return strata::gdmSceneView(45.0);
}

void BM_GdmRtvBake(benchmark::State& state) {
    const Baked& weave = baked("weave");
    strata::GdmRtvOptions options;
    options.bounces = int(state.range(0));
    const strata::GdmAlbedo albedo = strata::mesostructureLinearAlbedo(weave.meso);
    strata::GdmRtv rtv;
    for (auto _ : state) rtv = strata::bakeGdmRtv(weave.gdm, weave.distance, albedo, options);
    state.counters["MiB"] = double(rtv.bytes()) / (1024.0 * 1024.0);
}
BENCHMARK(BM_GdmRtvBake)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_GdmRtvError(benchmark::State& state) {
    const std::string name = state.range(0) == 0 ? "weave" : "chain";
    const Baked& scene = baked(name);
    constexpr int kSize = 256, kSamples = 256;
    const strata::Environment environment = strata::makeEnvironment("sky-overcast", 64, 32);
    const strata::ShColor lighting = environment.sh();
    const strata::EnvironmentRadiance sky = [&lighting](const glm::dvec3& d) {
        return glm::max(strata::shReconstruct(lighting, d), glm::dvec3(0.0));
    };
    const strata::GdmAlbedo albedo = strata::mesostructureLinearAlbedo(scene.meso);
    for (auto _ : state) {
        const strata::GdmSceneImages hits =
            strata::renderGdmReference(scene.solid, camera(), {0.5, 0.5, 3.0}, kSize, kSize);
        const strata::Image surface = strata::gdmSurfaceHitMask(hits);
        for (int bounces = 0; bounces <= 2; ++bounces) {
            strata::GdmRtvOptions rtvOptions;
            rtvOptions.bounces = bounces;
            const strata::GdmRtv rtv = strata::bakeGdmRtv(scene.gdm, scene.distance, albedo, rtvOptions);
            const strata::Image shaded = strata::shadeGdmSceneRtv(hits, rtv, lighting, albedo);
            strata::GdmPathTraceOptions options;
            options.samplesPerPixel = kSamples;
            options.bounces = bounces;
            options.seed = 1;
            const strata::GdmPathTraceImages a =
                strata::pathTraceGdm(scene.solid, albedo, sky, camera(), kSize, kSize, options);
            options.seed = 2;
            const strata::GdmPathTraceImages b =
                strata::pathTraceGdm(scene.solid, albedo, sky, camera(), kSize, kSize, options);
            const std::string n = std::to_string(bounces);
            state.counters["rel" + n] = strata::gdmRelativeRmse(shaded, surface, a.radiance, a.mask);
            state.counters["all" + n] = strata::gdmRelativeRmse(shaded, hits.mask, a.radiance, a.mask);
            state.counters["sigma" + n] =
                strata::gdmRelativeRmse(b.radiance, surface, a.radiance, a.mask) / std::sqrt(2.0);
        }
    }
}
BENCHMARK(BM_GdmRtvError)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_GdmRtvSvd(benchmark::State& state) {
    const Baked& weave = baked("weave");
    const strata::GdmAlbedo albedo = strata::mesostructureLinearAlbedo(weave.meso);
    const strata::GdmRtv rtv = strata::bakeGdmRtv(weave.gdm, weave.distance, albedo);
    const int rank = int(state.range(0));
    strata::GdmRtvSvd svd;
    for (auto _ : state) svd = strata::compressGdmRtv(rtv, rank);
    const strata::ShColor lighting = strata::makeEnvironment("sky-overcast", 64, 32).sh();
    const strata::GdmSceneImages hits =
        strata::renderGdmReference(weave.solid, camera(), {0.5, 0.5, 3.0}, 256, 256);
    const strata::Image surface = strata::gdmSurfaceHitMask(hits);
    const strata::Image full = strata::shadeGdmSceneRtv(hits, rtv, lighting, albedo);
    const strata::Image compressed = strata::shadeGdmSceneRtv(hits, svd.reconstruct(), lighting, albedo);
    state.counters["frob"] = svd.relativeError();
    state.counters["shade"] = strata::gdmRelativeRmse(compressed, surface, full, surface);
    state.counters["MiB"] = double(svd.bytes()) / (1024.0 * 1024.0);
}
BENCHMARK(BM_GdmRtvSvd)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Arg(24)
    ->Arg(48)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
