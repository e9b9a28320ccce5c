// The GDM in OpenGL (strata/gl/gdm_renderer.h): frame time of GdmRenderer::render, the paper's per-pixel
// algorithm in a fragment shader, at 512 x 512.
//
// Conditions: the built-in `weave` baked at the paper's 64 x 64 x 16 x 16 x 32 and compressed to rank 8 (the
// paper's layout), once per process; a headless OpenGL 4.5 context (llvmpipe on the 2-core build machine, or
// a GPU where there is one). A frame is both of render()'s passes (uvw, then shadow) and their read-backs;
// the program and the buffers are made once, outside the loop. Cases: the §8 quad at 45 degrees (`quad`),
// and the teapot at tiling 6 framed as `strata gdm trace --mesh` frames it (`teapot`), each with the rank-8
// SVD and with the raw GDM (134 MB in a storage buffer). GPU memory of the GDM: rank 8 4.0 MiB of maps,
// raw 128 MiB.
// Run: build/ci/bench/bench_gdm_gl --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gl/context.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/scene/scene.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

namespace {

const strata::Gdm& weave() {
    static const strata::Gdm gdm =
        strata::bakeGdm(strata::meshMesostructure(strata::makeMesostructure("weave"), 64), strata::GdmDims{});
    return gdm;
}

strata::gl::HeadlessContext& context() {
    static const std::unique_ptr<strata::gl::HeadlessContext> made = strata::gl::HeadlessContext::create();
    return *made;
}

// range(0): 0 quad, 1 teapot; range(1): 0 rank-8 SVD, 1 raw.
void frame(benchmark::State& state) {
    context().makeCurrent();
    constexpr int kSize = 512;
    const bool teapot = state.range(0) == 1;
    strata::gl::GdmRenderer renderer;
    if (state.range(1) == 0)
        renderer.setGdm(strata::compressGdm(weave(), 8));
    else
        renderer.setGdm(weave());
    const strata::Mesh mesh = strata::makeBuiltinMesh(teapot ? "teapot" : "quad");
    strata::PrismShellOptions shell;
    shell.tiling = glm::dvec2(teapot ? 6.0 : 1.0);
    renderer.setMesh(mesh, shell);
    strata::Camera camera;
    if (teapot) {
        camera = strata::frameCamera(strata::meshBounds(mesh), 1.0, 45.0);
    } else {
        const double a = 45.0 * 3.14159265358979323846 / 180.0;
        camera.eye = glm::dvec3(0.5, 0.5 - 1.6 * std::sin(a), 1.6 * std::cos(a));
        camera.target = glm::dvec3(0.5, 0.5, 0.0);
        camera.fovYDegrees = 45.0;
    }
    const glm::dvec3 light(0.5, -0.6, 1.1);
    for (auto _ : state) benchmark::DoNotOptimize(renderer.render(camera, light, kSize, kSize));
    state.SetLabel(std::string(teapot ? "teapot" : "quad") + (state.range(1) == 0 ? ", rank 8" : ", raw"));
}

}  // namespace

BENCHMARK(frame)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
