// Dual-depth sampling speed (makeDualDepth, dual_depth.h): the CPU scan conversion of a closed mesh.
//
// Conditions: the mesh is built or loaded once outside the timed loop; timed is makeDualDepth alone along z
// (teapot: 16256 triangles at tessellation 16) and along y (the Stanford bunny, 75408 triangles, viewed from
// above), at 256^2 and 1024^2, on 1 thread and on all that oneTBB gives it. The bunny is bunny00.off from
// Debian's libcgal-demo: it is extracted from /usr/share/doc/libcgal-dev/data.tar.gz into a temporary
// directory at start-up; without that package the bunny cases report an error and are skipped.
// Run: build/release/bench/bench_dual_depth --benchmark_min_time=1
#include "strata/mesh/builtin_meshes.h"
#include "strata/mesh/mesh_loader.h"
#include "strata/relief/dual_depth.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <optional>

namespace {

namespace fs = std::filesystem;

const std::optional<strata::Mesh>& bunny() {
    static const std::optional<strata::Mesh> mesh = []() -> std::optional<strata::Mesh> {
        const fs::path archive = "/usr/share/doc/libcgal-dev/data.tar.gz";
        if (!fs::exists(archive)) return std::nullopt;
        const fs::path dir = fs::temp_directory_path() / ("strata-bench-bunny-" + std::to_string(::getpid()));
        fs::create_directories(dir);
        const std::string command =
            "tar -xzf " + archive.string() + " -C '" + dir.string() + "' data/meshes/bunny00.off";
        std::optional<strata::Mesh> loaded;
        if (std::system(command.c_str()) == 0) {
            strata::MeshLoadOptions options;
            options.requireUvs = false;
            loaded = strata::loadMesh(dir / "data/meshes/bunny00.off", options);
        }
        fs::remove_all(dir);
        return loaded;
    }();
    return mesh;
}

void sample(benchmark::State& state, const strata::Mesh& mesh, strata::Axis axis) {
    const int size = static_cast<int>(state.range(0));
    const int threads = static_cast<int>(state.range(1));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    for (auto _ : state) benchmark::DoNotOptimize(strata::makeDualDepth(mesh, axis, size));
    state.counters["triangles"] = static_cast<double>(mesh.indices.size() / 3);
    state.counters["threads"] = threads;
}

void teapot(benchmark::State& state) {
    static const strata::Mesh mesh = strata::makeBuiltinMesh("teapot");
    sample(state, mesh, strata::Axis::Z);
}

void stanfordBunny(benchmark::State& state) {
    if (!bunny()) {
        state.SkipWithError("bunny00.off not available (apt-get install libcgal-demo)");
        return;
    }
    sample(state, *bunny(), strata::Axis::Y);
}

void sizesAndThreads(benchmark::internal::Benchmark* b) {
    const int cores = tbb::info::default_concurrency();
    for (const int size : {256, 1024}) {
        b->Args({size, 1});
        if (cores > 1) b->Args({size, cores});
    }
    b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(teapot)->Apply(sizesAndThreads);
BENCHMARK(stanfordBunny)->Apply(sizesAndThreads);

}  // namespace

BENCHMARK_MAIN();
