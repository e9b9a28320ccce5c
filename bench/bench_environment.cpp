// Environments and their spherical harmonics (strata/environment/).
//
// Conditions: the CI build (release, -O3), on the 2 cores oneTBB gets here; wall time.
// `projectEquirect`: a 512 x 256 RGB map (the built-in sky-clear, rendered once) projected to 16 RGB SH
// coefficients (parallel over rows); reported per map.
// `rotationBuild`, `rotationApplyRgb`, `rotationPerVertex`: one vertex's work when an environment is carried
// into its tangent frame: building the Ivanic-Ruedenberg blocks from a 3 x 3 rotation, applying them to 16
// RGB coefficients, and both; a different rotation per iteration (1024 precomputed ones, cycled).
// `shEvaluate`: the 16 basis functions at one direction.
// Run: build/ci/bench/bench_environment --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "strata/environment/environment.h"
#include "strata/environment/sh_rotation.h"

#include <benchmark/benchmark.h>
#include <glm/gtc/quaternion.hpp>

#include <random>
#include <vector>

namespace {

std::vector<glm::dmat3> rotations() {
    std::mt19937 random(1);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<glm::dmat3> result;
    for (int i = 0; i < 1024; ++i) {
        const glm::dvec3 axis =
            glm::normalize(glm::dvec3(uniform(random), uniform(random), uniform(random) + 0.01));
        result.push_back(glm::mat3_cast(glm::angleAxis(3.0 * uniform(random), axis)));
    }
    return result;
}

void projectEquirect(benchmark::State& state) {
    const strata::Image map = strata::makeEnvironment("sky-clear", 512, 256).map();
    for (auto _ : state) benchmark::DoNotOptimize(strata::projectEquirect(map));
    state.SetLabel("512x256 RGB");
}
BENCHMARK(projectEquirect)->Unit(benchmark::kMillisecond);

void rotationBuild(benchmark::State& state) {
    const std::vector<glm::dmat3> all = rotations();
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(strata::ShRotation(all[i]));
        i = (i + 1) & 1023;
    }
}
BENCHMARK(rotationBuild);

void rotationApplyRgb(benchmark::State& state) {
    const strata::ShRotation rotation(rotations()[3]);
    const strata::ShColor sh = strata::makeEnvironment("studio", 64, 32).sh();
    for (auto _ : state) benchmark::DoNotOptimize(rotation.apply(sh));
}
BENCHMARK(rotationApplyRgb);

void rotationPerVertex(benchmark::State& state) {
    const std::vector<glm::dmat3> all = rotations();
    const strata::ShColor sh = strata::makeEnvironment("studio", 64, 32).sh();
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(strata::shRotate(sh, all[i]));
        i = (i + 1) & 1023;
    }
}
BENCHMARK(rotationPerVertex);

void shEvaluate(benchmark::State& state) {
    glm::dvec3 direction(0.3, -0.5, 0.8);
    for (auto _ : state) {
        benchmark::DoNotOptimize(strata::shEvaluate(direction));
        direction.x += 1e-9;
    }
}
BENCHMARK(shEvaluate);

}  // namespace

BENCHMARK_MAIN();
