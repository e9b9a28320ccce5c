// SVD compression of a GDM (strata/gdm/gdm_svd.h, Wang et al. 2004, Sec. 4.1).
//
// Conditions: the GDM of the built-in `weave` (meshMesostructure at 64 per tile, bakeGdm at the paper's
// 64 x 64 x 16 voxels x 16 x 32 directions, H = 0.25, 128 MiB of floats), baked once per process, on the 2
// cores oneTBB gets here.
// `compress`: rank 8 in each layout; the goal: <= 0.3 s in the paper's layout (x, y, phi) x
// (theta, z). Wall time. The (x, y) x (z, theta, phi) layout's 4096 x 4096 Gram goes to Spectra's Lanczos
// solver (its 8 largest eigenpairs).
// `error`: docs/gdm.md's table, one compression and measureGdmSvd per (layout, rank), 2^20 segment queries;
// its counters are the table (times are not meaningful).
// `exitTolerance`: the exit rule's errors against its tolerance (0.5 to 8 voxels), rank 8, paper's layout.
// Run: build/ci/bench/bench_gdm_svd --benchmark_filter=compress --benchmark_repetitions=9
//      build/ci/bench/bench_gdm_svd --benchmark_filter='error|exitTolerance'
//      --benchmark_counters_tabular=true
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"

#include <benchmark/benchmark.h>

namespace {

constexpr strata::GdmLayout kLayouts[] = {strata::GdmLayout::XyPhiByThetaZ, strata::GdmLayout::XyzByThetaPhi,
                                          strata::GdmLayout::XyByZThetaPhi};

const strata::Gdm& weaveGdm() {
    static const strata::Gdm gdm =
        strata::bakeGdm(strata::meshMesostructure(strata::makeMesostructure("weave"), 64), strata::GdmDims{});
    return gdm;
}

void compress(benchmark::State& state) {
    const strata::GdmLayout layout = kLayouts[state.range(0)];
    const strata::Gdm& gdm = weaveGdm();
    for (auto _ : state) benchmark::DoNotOptimize(strata::compressGdm(gdm, 8, layout));
    state.SetLabel(strata::toString(layout));
}

void error(benchmark::State& state) {
    const strata::GdmLayout layout = kLayouts[state.range(0)];
    const int rank = static_cast<int>(state.range(1));
    const strata::Gdm& gdm = weaveGdm();
    strata::GdmSvdError error;
    for (auto _ : state) error = strata::measureGdmSvd(gdm, strata::compressGdm(gdm, rank, layout));
    state.SetLabel(strata::toString(layout));
    state.counters["rmse_vox"] = error.rmseVoxels;
    state.counters["p99_vox"] = error.p99Voxels;
    state.counters["exit_fh%"] = error.exitFalseHitPercent;
    state.counters["exit_fm%"] = error.exitFalseMissPercent;
    state.counters["seg_fh%"] = error.segmentFalseHitPercent;
    state.counters["seg_fm%"] = error.segmentFalseMissPercent;
    state.counters["MiB"] = error.memoryMiB;
}

// The exit rule's tolerance against its errors: rank 8 in the paper's layout on the table's GDM, the
// tolerance in voxels (H / Nz) along the ray.
void exitTolerance(benchmark::State& state) {
    const double voxels = double(state.range(0)) / 2.0;
    const strata::Gdm& gdm = weaveGdm();
    strata::GdmSvd svd = strata::compressGdm(gdm, 8, strata::GdmLayout::XyPhiByThetaZ);
    svd.exitTolerance = voxels * gdm.height / gdm.dims.nz;
    strata::GdmSvdError error;
    for (auto _ : state) error = strata::measureGdmSvd(gdm, svd);
    state.counters["tol_vox"] = voxels;
    state.counters["exit_fh%"] = error.exitFalseHitPercent;
    state.counters["exit_fm%"] = error.exitFalseMissPercent;
    state.counters["seg_fh%"] = error.segmentFalseHitPercent;
    state.counters["seg_fm%"] = error.segmentFalseMissPercent;
}

}  // namespace

BENCHMARK(compress)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(error)
    ->ArgsProduct({{0, 1, 2}, {2, 4, 8, 16, 32}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(exitTolerance)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
