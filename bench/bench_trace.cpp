// Exact ray / bilinear height-field tracing (strata/trace/heightfield_tracer.h).
//
// Conditions: a 64^2 map (the `stone-bricks` pattern resampled, and white noise), S = 0.1; rays leave
// every texel centre in cosine-weighted directions (a fixed low-discrepancy set of 256 per texel)
// and are tested for occlusion up to R = 1 tile: the workload of the AO Monte-Carlo ground truth.
// One thread. Reported as rays per second.
// Run: build/release/bench/bench_trace
#include "strata/image/image_ops.h"
#include "strata/relief/patterns.h"
#include "strata/trace/heightfield_tracer.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace {

strata::Image benchMap(int which) {
    if (which == 0)
        return strata::resample(strata::makePattern("stone-bricks", {256, 1, 0.08}).depth, 64, 64);
    strata::Image noise(64, 64, 1);
    unsigned state = 12345u;
    for (float& value : noise.pixels()) {
        state = state * 1664525u + 1013904223u;
        value = static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
    }
    return noise;
}

// Cosine-weighted hemisphere directions from a 16 x 16 stratified grid (Malley's method).
std::vector<glm::dvec3> cosineDirections() {
    std::vector<glm::dvec3> directions;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j) {
            const double r = std::sqrt((i + 0.5) / 16.0);
            const double phi = 2.0 * std::numbers::pi * (j + 0.5) / 16.0;
            const double x = r * std::cos(phi);
            const double y = r * std::sin(phi);
            directions.emplace_back(x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y)));
        }
    return directions;
}

void occludedFromSurface(benchmark::State& state) {
    const strata::Image depth = benchMap(static_cast<int>(state.range(0)));
    const strata::HeightFieldTracer tracer(depth, 0.1);
    const std::vector<glm::dvec3> directions = cosineDirections();
    std::int64_t rays = 0;
    for (auto _ : state) {
        int open = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                for (const glm::dvec3& direction : directions)
                    open += !tracer.occludedFromSurface(depth.texelU(x), depth.texelV(y), direction, 1.0);
        benchmark::DoNotOptimize(open);
        rays += 64 * 64 * static_cast<std::int64_t>(directions.size());
    }
    state.counters["rays_per_second"] =
        benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
    state.SetLabel(state.range(0) == 0 ? "stone-bricks 64^2" : "white noise 64^2");
}

}  // namespace

BENCHMARK(occludedFromSurface)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
