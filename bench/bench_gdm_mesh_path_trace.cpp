// The GDM path tracer on curved bases (strata/gdm/gdm_mesh_path_trace.h): the chain on the torus under the
// overcast sky, the reference for the GL renderer's 0, 1 and 2 bounces on a mesh.
//
// Conditions: the scene of examples/scenes/gdm_torus_chain.json: the built-in `torus` (tessellation 12),
// tiling 6 (T the shell's default, H times a tile's world length), the built-in `chain` (makeMesostructure
// defaults) meshed by meshMesostructure at 64, once, outside the timing; albedo mesostructureLinearAlbedo.
// Camera: eye (1.05, -1.45, 1.05), target (0, 0, -0.05), vertical field of view 30 degrees, up +z.
// Lighting: the built-in environment `sky-overcast` (makeEnvironment at 64 x 32) through its SH, the
// band-limited radiance max(shReconstruct(sh, direction), 0) (as bench_gdm_rtv). Macro occlusion on (the
// torus shadows itself).
//
// BM_GdmMeshPathTrace: 128 x 96, 64 paths per pixel, seed 1, bounces 0, 1 and 2 (the argument); timed: one
// pathTraceGdmMesh call, the warped scene's build included. Counters: mean = the mean radiance (green) over
// the pixels that hit, hits = their number.
// BM_GdmMeshPathTraceScene: the same call at 1 x 1 pixel and 1 path: the warped scene's build alone.
// Counters: prisms, solidTriangles (the warped solid's flat triangles, GdmMeshReferenceStats) and
// meshTriangles (the chain's SolidMesh).
//
// With STRATA_GDM_MESH_PATH_TRACE_IMAGE=<file.png>, it also writes a picture: the same view at 256 x 192
// with 256 paths per pixel, bounces 0 (left), 2 (middle), and 10 times their difference (right, the light
// of the two interreflections), tone-mapped (exposure 1, Reinhard x / (1 + x) per channel, then sRGB),
// 8-bit, dark gray where the camera ray misses. Run:
// STRATA_GDM_MESH_PATH_TRACE_IMAGE=/tmp/torus_chain.png build/ci/bench/bench_gdm_mesh_path_trace
//     --benchmark_min_time=0.01
#include "strata/environment/environment.h"
#include "strata/gdm/gdm_mesh_path_trace.h"
#include "strata/gdm/gdm_mesh_reference.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/image/image_io.h"
#include "strata/image/srgb.h"
#include "strata/mesh/builtin_meshes.h"

#include <benchmark/benchmark.h>
#include <glm/common.hpp>

#include <cstdlib>
#include <string>

namespace {

struct Scene {
    strata::Mesostructure meso = strata::makeMesostructure("chain");
    strata::SolidMesh solid = strata::meshMesostructure(meso, 64);
    strata::Mesh torus = strata::makeBuiltinMesh("torus", {12});
    strata::ShColor lighting = strata::makeEnvironment("sky-overcast", 64, 32).sh();
};

const Scene& scene() {
    static const Scene s;
    return s;
}

strata::Camera camera() {
    strata::Camera c;
    c.eye = {1.05, -1.45, 1.05};
    c.target = {0.0, 0.0, -0.05};
    c.fovYDegrees = 30.0;
    return c;
}

strata::GdmPathTraceImages render(int width, int height, int samples, int bounces) {
    const Scene& s = scene();
    strata::PrismShellOptions shell;
    shell.tiling = {6.0, 6.0};
    strata::GdmMeshPathTraceOptions options;
    options.samplesPerPixel = samples;
    options.bounces = bounces;
    options.seed = 1;
    const strata::ShColor& lighting = s.lighting;
    const strata::EnvironmentRadiance sky = [&lighting](const glm::dvec3& d) {
        return glm::max(strata::shReconstruct(lighting, d), glm::dvec3(0.0));
    };
    return strata::pathTraceGdmMesh(s.solid, s.torus, shell, strata::mesostructureLinearAlbedo(s.meso), sky,
                                    camera(), width, height, options);
}

void writePicture(const std::string& path) {
    constexpr int kWidth = 256, kHeight = 192, kSamples = 256;
    const strata::GdmPathTraceImages direct = render(kWidth, kHeight, kSamples, 0);
    const strata::GdmPathTraceImages bounced = render(kWidth, kHeight, kSamples, 2);
    strata::Image out(3 * kWidth, kHeight, 3);
    const auto toneMapped = [](double x) { return strata::linearToSrgb(x / (1.0 + x)); };
    for (int j = 0; j < kHeight; ++j)
        for (int i = 0; i < kWidth; ++i)
            for (int c = 0; c < 3; ++c) {
                const bool hit = direct.mask.at(i, j) > 0.0f;
                const double b0 = double(direct.radiance.at(i, j, c)),
                             b2 = double(bounced.radiance.at(i, j, c));
                out.at(i, j, c) = float(hit ? toneMapped(b0) : 0.12);
                out.at(kWidth + i, j, c) = float(hit ? toneMapped(b2) : 0.12);
                out.at(2 * kWidth + i, j, c) = float(hit ? strata::linearToSrgb(10.0 * (b2 - b0)) : 0.12);
            }
    strata::writePng(path, out, {strata::PngBitDepth::Eight, false});
}

void BM_GdmMeshPathTrace(benchmark::State& state) {
    constexpr int kWidth = 128, kHeight = 96;
    const int bounces = int(state.range(0));
    scene();
    strata::GdmPathTraceImages images;
    for (auto _ : state) images = render(kWidth, kHeight, 64, bounces);
    double sum = 0.0;
    int hits = 0;
    for (int j = 0; j < kHeight; ++j)
        for (int i = 0; i < kWidth; ++i)
            if (images.mask.at(i, j) > 0.0f) {
                sum += double(images.radiance.at(i, j, 1));
                ++hits;
            }
    state.counters["mean"] = hits ? sum / hits : 0.0;
    state.counters["hits"] = hits;
    static bool written = false;
    if (const char* path = std::getenv("STRATA_GDM_MESH_PATH_TRACE_IMAGE"); path && !written) {
        written = true;
        writePicture(path);
    }
}
BENCHMARK(BM_GdmMeshPathTrace)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GdmMeshPathTraceScene(benchmark::State& state) {
    const Scene& s = scene();
    for (auto _ : state) benchmark::DoNotOptimize(render(1, 1, 1, 0));
    // The scene's size, from the curved reference that builds the same one.
    strata::PrismShellOptions shell;
    shell.tiling = {6.0, 6.0};
    strata::GdmMeshReferenceStats stats;
    strata::renderGdmMeshReference(s.solid, s.torus, shell, camera(), {0.0, 0.0, 3.0}, 1, 1, {}, &stats);
    state.counters["prisms"] = double(stats.prisms);
    state.counters["solidTriangles"] = double(stats.solidTriangles);
    state.counters["meshTriangles"] = double(s.solid.triangles.size());
}
BENCHMARK(BM_GdmMeshPathTraceScene)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
