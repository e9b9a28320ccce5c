// Frame time of the GL relief renderer (strata/gl/relief_renderer.h).
//
// Conditions: Mesa llvmpipe (OpenGL 4.5 core through EGL surfaceless, no GPU) on the 2 shared CPU cores of
// the development machine; the numbers measure the CPU rasteriser, not a GPU. Relief technique, shaded
// output with self-shadowing and depth correction, 1 sample per pixel (llvmpipe's 4x MSAA takes minutes
// per frame on the teapot: docs/renderer.md), the `stone-bricks` pattern
// at 512^2 with S = 0.08, linear + binary steps 10 + 5 (the paper's shader) and 64 + 8 (the verification
// setting), pictures of 256^2 and 512^2. Meshes: the unit quad filling most of the picture (camera 45
// degrees from its normal) and the teapot (tessellation 16, 16384 triangles, tiling 4) seen from the side.
// One frame = render(): draw and the read-back of the picture into a strata::Image (the
// read-back is a few percent of a frame at these sizes). Reported as time per frame.
// Run: build/release/bench/bench_render
#include "strata/gl/context.h"
#include "strata/gl/relief_renderer.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/patterns.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>

namespace {

using namespace strata;

struct BenchScene {
    std::unique_ptr<gl::HeadlessContext> context;
    std::string failure;
    std::unique_ptr<gl::ReliefRenderer> renderer;
    gl::GpuMesh quad;
    gl::GpuMesh teapot;
    gl::GpuMaterial material;
};

BenchScene& scene() {
    static BenchScene instance = [] {
        BenchScene s;
        try {
            s.context = gl::HeadlessContext::create();
            s.renderer = std::make_unique<gl::ReliefRenderer>();
            s.quad = gl::uploadMesh(makeBuiltinMesh("quad"));
            s.teapot = gl::uploadMesh(makeBuiltinMesh("teapot"));
            const ReliefTexture texture = makePattern("stone-bricks", {512, 1, 0.08});
            s.material = gl::uploadMaterial(texture, texture.depthScale);
        } catch (const std::exception& error) {
            s.failure = error.what();
        }
        return s;
    }();
    return instance;
}

// Args: picture size, linear steps, binary steps, mesh (0 = quad, 1 = teapot).
void BM_RenderRelief(benchmark::State& state) {
    BenchScene& s = scene();
    if (!s.failure.empty()) {
        state.SkipWithError(s.failure.c_str());
        return;
    }
    const int size = static_cast<int>(state.range(0));
    const bool teapot = state.range(3) == 1;
    gl::RenderRequest request;
    request.objects.push_back({teapot ? &s.teapot : &s.quad, glm::dmat4(1.0), &s.material, glm::dvec3(0.8)});
    if (teapot) {
        request.camera.eye = {0.4, -2.6, 1.5};
        request.camera.target = {0.08, 0.0, 0.45};
        request.camera.fovYDegrees = 35.0;
        request.relief.tiling = 4.0;
    } else {
        const double a = 45.0 * 3.14159265358979 / 180.0;
        request.camera.target = {0.5, 0.5, 0.0};
        request.camera.eye = request.camera.target + 1.6 * glm::dvec3(0.0, -std::sin(a), std::cos(a));
        request.camera.fovYDegrees = 40.0;
    }
    request.relief.linearSteps = static_cast<int>(state.range(1));
    request.relief.binarySteps = static_cast<int>(state.range(2));
    request.relief.aoRescale = AoRescale::Off;
    request.picture.width = size;
    request.picture.height = size;
    request.picture.samples = 1;
    s.renderer->render(request);  // compile the program and make the framebuffers outside the timing
    for (auto _ : state) {
        Image image = s.renderer->render(request);
        benchmark::DoNotOptimize(image);
    }
    state.SetLabel(std::string(teapot ? "teapot" : "quad") + " " + std::to_string(size) + "^2 " +
                   std::to_string(state.range(1)) + "+" + std::to_string(state.range(2)));
}

BENCHMARK(BM_RenderRelief)
    ->ArgsProduct({{256, 512}, {10}, {5}, {0, 1}})
    ->ArgsProduct({{256, 512}, {64}, {8}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
