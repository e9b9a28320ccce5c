// Meta-relief composition speed (paper Eq. 1 and 2): 3 layers composed into 2048^2.
//
// Conditions: the layers are built-in patterns generated once outside the timed loop: base 1024^2
// at tiling 1, stone-bricks 512^2 at tiling 5.5, metal 512^2 at tiling 14.5 (the paper's Fig. 8 and
// 13 right). Timed: compose() alone (sampling, weighting, normalising; colour from layer 1), on all
// cores oneTBB gives it. Goal (issue 2): <= 0.2 s on the 2-core development machine.
// Run: build/release/bench/bench_compose --benchmark_min_time=2
#include "strata/compose/compose.h"
#include "strata/relief/patterns.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

namespace {

std::vector<strata::CompositionLayer> threeLayers() {
    std::vector<strata::CompositionLayer> layers;
    layers.push_back({strata::makePattern("base", {1024, 1, 0.08}), 1.0, 1.0, 1.0, "base"});
    layers.push_back({strata::makePattern("stone-bricks", {512, 1, 0.08}), 5.5, 0.35, 0.35, "stone-bricks"});
    layers.push_back({strata::makePattern("metal", {512, 1, 0.08}), 14.5, 0.15, 0.15, "metal"});
    return layers;
}

void composeThreeLayers(benchmark::State& state) {
    const auto mode = static_cast<strata::NormalMode>(state.range(0));
    const int threads = static_cast<int>(state.range(1));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    static const std::vector<strata::CompositionLayer> layers = threeLayers();
    strata::ComposeParams params;
    params.resolution = 2048;
    params.normals = mode;
    params.colorFrom = 1;
    const bool reuse = state.range(2) != 0;
    strata::Composition result;
    for (auto _ : state) {
        if (reuse) {
            strata::composeInto(layers, params, result);  // the viewer's case: buffers from the last frame
        } else {
            result = strata::compose(layers, params);  // the CLI's case: 112 MB of fresh memory
        }
        benchmark::DoNotOptimize(result.texture.depth.pixels().data());
    }
    state.SetItemsProcessed(state.iterations() * 2048 * 2048);
    state.SetLabel(std::string(strata::toString(mode)) + ", " + std::to_string(threads) + " thread(s), " +
                   (reuse ? "reused buffers" : "fresh result"));
}

}  // namespace

BENCHMARK(composeThreeLayers)
    ->ArgsProduct({{static_cast<int>(strata::NormalMode::Paper),
                    static_cast<int>(strata::NormalMode::Consistent)},
                   {1, 2},
                   {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
