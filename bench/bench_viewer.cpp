// strata-view's material pipeline (apps/strata-view/material_pipeline.h): a layer weight change of the
// `shaped-fabric` material at the viewer's edit resolution 512^2, baked (compose + AO bake + upload) against
// live (GpuMaterial::setLayer), with the material AO `exact` and `multiply`.
//
// Conditions: a headless GL context (llvmpipe on the 2 shared cores here), the pipeline opened once outside
// the timing. One iteration = one weight change (layer 1's depth weight toggles between 0.3 and 0.45),
// timed until everything it starts has finished (updateAndWait: for live + exact the composed AO's
// background re-bake, for baked the whole bake and upload). Counter `update_ms`: until update() returns.
// Live, the next frame then draws the new weights; baked, it draws the old material until the bake is done.
// Args: live (1) or baked (0); AO exact (0) or multiply (1).
// Run: build/release/bench/bench_viewer
#include "material_document.h"
#include "material_pipeline.h"

#include "strata/gl/context.h"
#include "strata/scene/scene.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>
#include <optional>
#include <string>

namespace {

using namespace strata;

void BM_ViewerWeightChange(benchmark::State& state) {
    std::unique_ptr<gl::HeadlessContext> context;
    try {
        context = gl::HeadlessContext::create();
    } catch (const std::exception& error) {
        state.SkipWithError(error.what());
        return;
    }
    const bool live = state.range(0) == 1;
    const bool multiply = state.range(1) == 1;
    view::MaterialPipeline pipeline;
    view::BakeRequest request;
    request.material = view::openMaterial("shaped-fabric");
    request.material.ao = multiply ? MetaAoMode::Multiply : MetaAoMode::Exact;
    request.meta = live ? MetaPath::Live : MetaPath::Baked;
    pipeline.updateAndWait(request);
    double updating = 0.0;
    bool high = false;
    for (auto _ : state) {
        high = !high;
        request.material.layers[1].weightDepth = high ? 0.45 : 0.3;
        const auto start = std::chrono::steady_clock::now();
        pipeline.update(request);
        updating += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        pipeline.updateAndWait(request);
        state.SetIterationTime(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    state.counters["update_ms"] = 1e3 * updating / static_cast<double>(state.iterations());
    state.SetLabel(std::string(live ? "live" : "baked") + ", AO " + (multiply ? "multiply" : "exact"));
}
BENCHMARK(BM_ViewerWeightChange)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->UseManualTime()
    ->Iterations(4)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
