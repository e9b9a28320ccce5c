// The GDM path tracer (strata/gdm/gdm_path_trace.h) on the built-in weave under a sky.
//
// Conditions: the built-in `weave` (makeMesostructure defaults), meshMesostructure at 64, meshed once,
// outside the timing; albedo mesostructureLinearAlbedo. Camera: looking at the quad's centre (0.5, 0.5, 0)
// from distance 1.6 at 45 degrees from the normal (eye (0.5, 0.5 - 1.6 sin 45, 1.6 cos 45)), vertical field
// of view 45 degrees, 128 x 128, 16 paths per pixel, seed 1; bounces 0, 1 and 2 (the argument). Sky (the
// picture's): a blue gradient from the horizon (0.9, 0.95, 1.0) to the zenith (0.25, 0.45, 0.9), black
// below the horizon, and a sun lobe 6 (1, 0.9, 0.75) max(0, cos)^8 around normalize(0.4, -0.5, 0.75).
// Counters: mean = the mean radiance (green) over the pixels that hit.
// With STRATA_GDM_PATH_TRACE_IMAGE=<file.png>, it also writes the picture of
// docs/img/gdm_path_trace_weave.png: the same view at 256 x 256 with 256 paths per pixel, bounces 0 (left)
// and 2 (right), tone-mapped (exposure 1, Reinhard x / (1 + x) per channel, then sRGB), 8-bit. Run:
// build/ci/bench/bench_gdm_path_trace --benchmark_min_time=0.01
#include "strata/gdm/gdm_path_trace.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/image/image_io.h"
#include "strata/image/srgb.h"

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

namespace {

struct Weave {
    strata::Mesostructure meso = strata::makeMesostructure("weave");
    strata::SolidMesh solid = strata::meshMesostructure(meso, 64);
};

const Weave& weave() {
    static const Weave w;
    return w;
}

glm::dvec3 sky(const glm::dvec3& d) {
    if (d.z <= 0.0) return glm::dvec3(0.0);
    const glm::dvec3 horizon(0.9, 0.95, 1.0), zenith(0.25, 0.45, 0.9);
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.4, -0.5, 0.75));
    const double lobe = std::pow(std::max(0.0, glm::dot(d, sun)), 8.0);
    return horizon + (zenith - horizon) * d.z + 6.0 * lobe * glm::dvec3(1.0, 0.9, 0.75);
}

strata::Camera camera() {
    return strata::gdmSceneView(45.0);
}

strata::GdmPathTraceImages render(int size, int samples, int bounces) {
    strata::GdmPathTraceOptions options;
    options.samplesPerPixel = samples;
    options.bounces = bounces;
    options.seed = 1;
    return strata::pathTraceGdm(weave().solid, strata::mesostructureLinearAlbedo(weave().meso), sky, camera(),
                                size, size, options);
}

void writePicture(const std::string& path) {
    constexpr int kSize = 256;
    const strata::GdmPathTraceImages direct = render(kSize, 256, 0);
    const strata::GdmPathTraceImages bounced = render(kSize, 256, 2);
    strata::Image out(3 * kSize, kSize, 3);
    const auto toneMapped = [](double x) { return strata::linearToSrgb(x / (1.0 + x)); };
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i)
            for (int c = 0; c < 3; ++c) {
                const bool hit = direct.mask.at(i, j) > 0.0f;
                // Where the ray misses: a dark gray, to tell the background from a black shadow.
                const double b0 = double(direct.radiance.at(i, j, c)),
                             b2 = double(bounced.radiance.at(i, j, c));
                out.at(i, j, c) = float(hit ? toneMapped(b0) : 0.12);
                out.at(kSize + i, j, c) = float(hit ? toneMapped(b2) : 0.12);
                out.at(2 * kSize + i, j, c) = float(hit ? strata::linearToSrgb(10.0 * (b2 - b0)) : 0.12);
            }
    strata::writePng(path, out, {strata::PngBitDepth::Eight, false});
}

void BM_GdmPathTrace(benchmark::State& state) {
    const int bounces = int(state.range(0));
    weave();
    strata::GdmPathTraceImages images;
    for (auto _ : state) images = render(128, 16, bounces);
    double sum = 0.0;
    int hits = 0;
    for (int j = 0; j < 128; ++j)
        for (int i = 0; i < 128; ++i)
            if (images.mask.at(i, j) > 0.0f) {
                sum += double(images.radiance.at(i, j, 1));
                ++hits;
            }
    state.counters["mean"] = hits ? sum / hits : 0.0;
    static bool written = false;
    if (const char* path = std::getenv("STRATA_GDM_PATH_TRACE_IMAGE"); path && !written) {
        written = true;
        writePicture(path);
    }
}
BENCHMARK(BM_GdmPathTrace)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
