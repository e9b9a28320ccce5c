// The GDM bake (strata/gdm/gdm_bake.h), the paper's default sampling: 64 x 64 x 16 voxels x 16 x 32
// directions (33.5 M values, 134 MB), H = 0.25.
//
// Conditions: a weave-like stand-in solid built here (the built-in `weave` mesostructure was being written
// at the same time): four threads, two along u (v = 1/4, 3/4) and two along v (u = 1/4, 3/4), each a tube
// of radius 0.06 whose centre rises and falls as H/2 +- 0.05 cos(2 pi s) over and under the crossing
// threads (crossing threads interpenetrate by 0.02: the union), 192 rings of 24 vertices per tube, capped
// at the tile's sides, 37056 triangles. All the machine's threads (strata::parallelFor; 2 cores when
// written). Reported: wall time per bake, and rays per second (voxels outside the solid x directions).
// Peak memory: /usr/bin/time -v build/ci/bench/bench_gdm (maximum resident set size).
// BM_BakeBuiltinWeave bakes the built-in `weave` instead and reports its rank-8 SVD error as counters.
// Run: build/ci/bench/bench_gdm --benchmark_repetitions=5
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

namespace {

// One thread along u at v = v0, centre height H/2 + sign * A cos(2 pi (u - 1/4)); its rings lie in the
// planes u = const, and the end rings at u = 0 and u = 1 are the same ring one tile apart, each capped.
void addThreadAlongU(strata::SolidMesh& mesh, double v0, double sign, bool alongV) {
    constexpr int kRings = 192;
    constexpr int kAround = 24;
    constexpr double kRadius = 0.06;
    constexpr double kAmplitude = 0.05;
    const double centreZ = mesh.height / 2;
    const auto base = std::uint32_t(mesh.positions.size());
    const auto put = [&](double u, double v, double z) {
        // A thread along v is the thread along u mirrored in u = v; its triangles turn round below.
        mesh.positions.push_back(alongV ? glm::vec3(float(v), float(u), float(z))
                                        : glm::vec3(float(u), float(v), float(z)));
    };
    for (int n = 0; n <= kRings; ++n) {
        const double u = double(n) / kRings;
        // The last ring's height from the first's phase, so that the two caps coincide exactly.
        const double z = centreZ + sign * kAmplitude *
                                       std::cos(2 * std::numbers::pi * (double(n % kRings) / kRings - 0.25));
        for (int a = 0; a < kAround; ++a) {
            const double angle = 2 * std::numbers::pi * a / kAround;
            put(u, v0 + kRadius * std::cos(angle), z + kRadius * std::sin(angle));
        }
    }
    const std::uint32_t centres = std::uint32_t(mesh.positions.size());
    for (int end = 0; end < 2; ++end) {
        const double z = centreZ + sign * kAmplitude * std::cos(2 * std::numbers::pi * -0.25);
        put(end, v0, z);
    }
    const auto ring = [&](int n, int a) { return base + std::uint32_t(n * kAround + (a % kAround)); };
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (int n = 0; n < kRings; ++n)
        for (int a = 0; a < kAround; ++a) {
            triangles.push_back({ring(n, a), ring(n + 1, a + 1), ring(n + 1, a)});
            triangles.push_back({ring(n, a), ring(n, a + 1), ring(n + 1, a + 1)});
        }
    for (int a = 0; a < kAround; ++a) {
        triangles.push_back({centres, ring(0, a + 1), ring(0, a)});                // u = 0, facing -u
        triangles.push_back({centres + 1, ring(kRings, a), ring(kRings, a + 1)});  // u = 1, facing +u
    }
    for (auto& triangle : triangles) {
        if (alongV) std::swap(triangle[1], triangle[2]);
        mesh.triangles.push_back(triangle);
    }
}

strata::SolidMesh standInWeave() {
    strata::SolidMesh mesh;
    mesh.source = "stand-in weave";
    mesh.height = 0.25;
    addThreadAlongU(mesh, 0.25, 1.0, false);
    addThreadAlongU(mesh, 0.75, -1.0, false);
    addThreadAlongU(mesh, 0.25, -1.0, true);
    addThreadAlongU(mesh, 0.75, 1.0, true);
    return mesh;
}

void BM_BakeWeave(benchmark::State& state) {
    const strata::SolidMesh mesh = standInWeave();
    const strata::GdmDims dims;  // 64 x 64 x 16 x 16 x 32
    std::size_t rays = 0;
    strata::Gdm kept;
    for (auto _ : state) {
        strata::Gdm gdm = strata::bakeGdm(mesh, dims);
        benchmark::DoNotOptimize(gdm.values.data());
        // Timed: the bake alone. Counting and freeing the previous result are not.
        state.PauseTiming();
        rays = 0;
        for (std::size_t v = 0; v < gdm.values.size(); v += dims.directionCount())
            rays += gdm.values[v] != 0.0f;
        rays *= dims.directionCount();
        kept = std::move(gdm);
        state.ResumeTiming();
    }
    state.counters["triangles"] = double(mesh.triangles.size());
    state.counters["rays/s"] =
        benchmark::Counter(double(rays) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BakeWeave)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

// The built-in `weave` (strata/gdm/mesostructure.h), meshed at 64 per tile width (meshMesostructure), baked
// at the default sampling; then its rank-8 SVD in the paper's layout and the error against the raw bake.
void BM_BakeBuiltinWeave(benchmark::State& state) {
    const strata::SolidMesh mesh = strata::meshMesostructure(strata::makeMesostructure("weave"), 64);
    const strata::GdmDims dims;
    strata::Gdm gdm;
    for (auto _ : state) {
        strata::Gdm baked = strata::bakeGdm(mesh, dims);
        benchmark::DoNotOptimize(baked.values.data());
        state.PauseTiming();  // timed: the bake alone, not freeing the previous result
        gdm = std::move(baked);
        state.ResumeTiming();
    }
    const strata::GdmSvd svd = strata::compressGdm(gdm, 8, strata::GdmLayout::XyPhiByThetaZ);
    const strata::GdmSvdError error = strata::measureGdmSvd(gdm, svd);
    state.counters["triangles"] = double(mesh.triangles.size());
    state.counters["rank8_rmse_vox"] = error.rmseVoxels;
    state.counters["rank8_p99_vox"] = error.p99Voxels;
    state.counters["rank8_seg_false_hit_pct"] = error.segmentFalseHitPercent;
    state.counters["rank8_seg_false_miss_pct"] = error.segmentFalseMissPercent;
}
BENCHMARK(BM_BakeBuiltinWeave)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

}  // namespace

BENCHMARK_MAIN();
