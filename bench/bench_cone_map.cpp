// Cone map generation (strata/relief/cone_map.h): the conservative, whole-cell cone ratios the `cone`
// technique traces with, made once per baked material before its first draw.
//
// Conditions: the `stone-bricks` pattern's depth (made once, outside the timed loop), default cap
// (max(W, H)); K = 64 depth levels at 256^2, 512^2 and 1024^2, and K = 16 and 128 at 1024^2; on the cores
// oneTBB gives it (2 on the development machine). Timed is coneMap alone. The goal: a 1024^2 map in
// seconds, not minutes; this generator's target is well under a second at K = 64 on 2 cores.
// Run: build/release/bench/bench_cone_map
#include "strata/relief/cone_map.h"
#include "strata/relief/patterns.h"

#include <benchmark/benchmark.h>

#include <string>

namespace {

void generate(benchmark::State& state) {
    const int size = static_cast<int>(state.range(0));
    strata::ConeMapOptions options;
    options.depthLevels = static_cast<int>(state.range(1));
    const strata::Image depth = strata::makePattern("stone-bricks", {size, 1, 0.08}).depth;
    for (auto _ : state) {
        strata::Image cones = strata::coneMap(depth, options);
        benchmark::DoNotOptimize(cones.pixels().data());
    }
    state.counters["cells_per_second"] =
        benchmark::Counter(static_cast<double>(size) * size * static_cast<double>(state.iterations()),
                           benchmark::Counter::kIsRate);
    state.SetLabel("stone-bricks " + std::to_string(size) + "^2, K = " + std::to_string(options.depthLevels));
}

}  // namespace

BENCHMARK(generate)->ArgsProduct({{256, 512, 1024}, {64}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(generate)->Args({1024, 16})->Args({1024, 128})->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
