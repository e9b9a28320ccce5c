// The macro transfer of bi-scale PRT (strata/gdm/macro_transfer.h): baking the 16 x 16 matrix of every
// vertex, the mesh's self-occlusion traced with Embree along the 2560 directions of shQuadrature().
//
// Conditions: built-in meshes at their default tessellation (the teapot: 9248 vertices, 16256 triangles; the
// torus: 4225 vertices), shell thickness 0.05, all cores (strata::parallelFor; 2 on the build machine).
// `occlusion`: with the mesh's shadowing (23.7 M rays for the teapot); `rotation`: without (the pure
// rotation, the integration alone).
// Run: build/ci/bench/bench_macro_transfer --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include "strata/gdm/macro_transfer.h"
#include "strata/mesh/builtin_meshes.h"

#include <benchmark/benchmark.h>

#include <string>

namespace {

void bake(benchmark::State& state, const std::string& name, bool occlusion) {
    const strata::Mesh mesh = strata::makeBuiltinMesh(name);
    strata::MacroTransferOptions options;
    options.shellThickness = 0.05;
    options.occlusion = occlusion;
    for (auto _ : state) {
        const strata::MacroTransfer transfer = strata::bakeMacroTransfer(mesh, options);
        benchmark::DoNotOptimize(transfer.matrices.data());
    }
    state.counters["vertices"] = double(mesh.vertices.size());
    state.counters["MiB"] = double(mesh.vertices.size() * 256 * sizeof(float)) / double(1 << 20);
}

BENCHMARK_CAPTURE(bake, teapot_occlusion, std::string("teapot"), true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(bake, teapot_rotation, std::string("teapot"), false)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(bake, torus_occlusion, std::string("torus"), true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
