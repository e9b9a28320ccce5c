// Texture-space AO bakes (strata/occlusion/ambient_occlusion.h).
//
// Conditions: the `stone-bricks` pattern, S = 0.08, M = 50 directions, R = 1 tile, on the 2 cores
// oneTBB gives the bake. `brute` walks every texel's own line cell by cell up to R (exact): its cost
// grows with R x resolution. `paper` adds the polygon area and the 3x3 filter on the same horizons.
// `sweep` (the default) is linear in texels x directions; the goals: 1024^2 in <= 0.5 s
// (>= 1e8 texel-directions/s), >= 100x brute at 256^2, 512^2 in <= 100 ms. `sweepKernel` runs each of
// the sweep's SIMD kernels that this CPU has (the default picks the widest): portable (SSE2, 4 lanes),
// avx2 (8 lanes), avx512 (16 lanes); they give the same AO bit for bit.
// Run: build/release/bench/bench_occlusion
#include "occlusion/horizon_search.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/relief/patterns.h"

#include <benchmark/benchmark.h>

namespace {

void bake(benchmark::State& state) {
    const int size = static_cast<int>(state.range(0));
    const auto method = static_cast<strata::AoMethod>(state.range(1));
    const strata::Image depth = strata::makePattern("stone-bricks", {size, 1, 0.08}).depth;
    strata::AoParams params;
    params.method = method;
    for (auto _ : state) {
        strata::Image ao = strata::bakeAo(depth, params);
        benchmark::DoNotOptimize(ao.pixels().data());
    }
    const double work = static_cast<double>(size) * size * params.directions;
    state.counters["texel_directions_per_second"] =
        benchmark::Counter(work * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.SetLabel(std::string(strata::toString(method)) + ", " + std::to_string(size) +
                   "^2 x 50 directions, R = 1");
}

void sweepKernel(benchmark::State& state) {
    const int size = static_cast<int>(state.range(0));
    const auto kernel = static_cast<strata::detail::SweepKernel>(state.range(1));
    if (!strata::detail::sweepKernelRuns(kernel)) {
        state.SkipWithError("this CPU does not run the kernel");
        return;
    }
    const strata::Image depth = strata::makePattern("stone-bricks", {size, 1, 0.08}).depth;
    const strata::AoParams params;
    for (auto _ : state) {
        strata::Image ao = strata::detail::sweepAo(depth, params, {kernel});
        benchmark::DoNotOptimize(ao.pixels().data());
    }
    const double work = static_cast<double>(size) * size * params.directions;
    state.counters["texel_directions_per_second"] =
        benchmark::Counter(work * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.SetLabel(std::string(strata::detail::toString(kernel)) + " kernel, " + std::to_string(size) +
                   "^2 x 50 directions, R = 1");
}

}  // namespace

BENCHMARK(bake)
    ->ArgsProduct({{128, 256},
                   {static_cast<int>(strata::AoMethod::Brute), static_cast<int>(strata::AoMethod::Paper)}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(bake)
    ->ArgsProduct({{256, 512, 1024}, {static_cast<int>(strata::AoMethod::Sweep)}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(sweepKernel)
    ->ArgsProduct({{512, 1024},
                   {static_cast<int>(strata::detail::SweepKernel::Portable),
                    static_cast<int>(strata::detail::SweepKernel::Avx2),
                    static_cast<int>(strata::detail::SweepKernel::Avx512)}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
