// Frame time of the GL relief renderer (strata/gl/relief_renderer.h).
//
// Conditions: Mesa llvmpipe (OpenGL 4.5 core through EGL surfaceless, no GPU) on the 2 shared CPU cores of
// the development machine; the numbers measure the CPU rasteriser, not a GPU. Relief technique, shaded
// output with self-shadowing and depth correction, 1 sample per pixel, the `stone-bricks` pattern
// at 512^2 with S = 0.08, linear + binary steps 10 + 5 (the paper's shader) and 64 + 8 (the verification
// setting), pictures of 256^2 and 512^2. Meshes: the unit quad filling most of the picture (camera 45
// degrees from its normal) and the teapot (tessellation 16, 16384 triangles, tiling 4) seen from the side.
// One frame = render(): draw and the read-back of the picture into a strata::Image (the
// read-back is a few percent of a frame at these sizes). Reported as time per frame.
// Run: build/release/bench/bench_render
#include "strata/compose/compose.h"
#include "strata/gl/context.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/patterns.h"
#include "strata/scene/camera.h"
#include "strata/scene/render_settings.h"
#include "strata/scene/scene.h"
#include "strata/trace/heightfield_tracer.h"
#include "strata/trace/shader_loops.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

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

// The default scene of `strata render` (the main job: teapot, Shaped Fabric 1024^2, 1280x720, 4 samples =
// 2 x 2 supersampling, 10 + 5 steps, shadows, AO) per technique. Arg: Technique. A frame is a second or two
// on llvmpipe, so one iteration each, after one untimed frame that builds the program (and, for cone, the
// cone map: bench_cone_map times that).
void BM_DefaultScene(benchmark::State& state) {
    BenchScene& s = scene();
    if (!s.failure.empty()) {
        state.SkipWithError(s.failure.c_str());
        return;
    }
    static const Scene defaults;
    static const gl::GpuMesh mesh = gl::uploadMesh(loadSceneMesh(defaults));
    static const ReliefTexture texture = loadSceneMaterial(defaults);
    static const gl::GpuMaterial material = gl::uploadMaterial(texture, texture.depthScale);
    static const Bounds bounds = meshBounds(loadSceneMesh(defaults));
    gl::RenderRequest request;
    request.objects.push_back({&mesh, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
    request.camera = frameCamera(bounds, 1280.0 / 720.0);
    request.relief = defaults.relief;
    request.relief.technique = static_cast<Technique>(state.range(0));
    request.lighting = defaults.lighting;
    request.picture = defaults.picture;
    s.renderer->render(request);
    for (auto _ : state) {
        Image image = s.renderer->render(request);
        benchmark::DoNotOptimize(image);
    }
    state.SetLabel(std::string(toString(request.relief.technique)) + " 1280x720 x4");
}
BENCHMARK(BM_DefaultScene)->DenseRange(0, 5)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// Live meta-relief (gl::uploadLiveMaterial: layers combined per fragment) against the same layers baked into
// one texture (compose()), on the teapot at 512^2 with the paper's 10 + 5 steps, shadows and depth
// correction, no AO. Layers, in order: base 512^2 x 1 (w 1), fabric 256^2 x 4 (0.3), stone-bricks 256^2 x 2
// (0.3), metal 256^2 x 8 (0.15), scales 128^2 x 8 (0.15); the first `layers` of them, composed at 512^2.
// Args: layer count, live (1) or baked (0). The goal: live <= 1.5x baked with 3 layers.
void BM_LiveMetaRelief(benchmark::State& state) {
    BenchScene& s = scene();
    if (!s.failure.empty()) {
        state.SkipWithError(s.failure.c_str());
        return;
    }
    const int count = static_cast<int>(state.range(0));
    const bool live = state.range(1) == 1;
    const struct {
        const char* pattern;
        int size;
        double tiling;
        double weight;
    } spec[] = {{"base", 512, 1.0, 1.0},
                {"fabric", 256, 4.0, 0.3},
                {"stone-bricks", 256, 2.0, 0.3},
                {"metal", 256, 8.0, 0.15},
                {"scales", 128, 8.0, 0.15}};
    std::vector<CompositionLayer> layers;
    for (int i = 0; i < count; ++i) {
        CompositionLayer layer;
        layer.texture = makePattern(spec[i].pattern, {spec[i].size, 1, 0.08});
        layer.tiling = spec[i].tiling;
        layer.weightDepth = layer.weightNormal = spec[i].weight;
        layers.push_back(std::move(layer));
    }
    ComposeParams params;
    params.resolution = 512;
    params.depthScale = 0.08;
    params.colorFrom = 0;
    const gl::GpuMaterial material = live ? gl::uploadLiveMaterial(layers, params, std::nullopt, AoParams{})
                                          : gl::uploadMaterial(compose(layers, params).texture, 0.08);
    gl::RenderRequest request;
    request.objects.push_back({&s.teapot, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
    request.camera.eye = {0.4, -2.6, 1.5};
    request.camera.target = {0.08, 0.0, 0.45};
    request.camera.fovYDegrees = 35.0;
    request.relief.tiling = 2.0;
    request.picture.width = request.picture.height = 512;
    request.picture.samples = 1;
    s.renderer->render(request);  // compile the program outside the timing
    for (auto _ : state) {
        Image image = s.renderer->render(request);
        benchmark::DoNotOptimize(image);
    }
    state.SetLabel(std::string(live ? "live " : "baked ") + std::to_string(count) + " layers, teapot 512^2");
}
BENCHMARK(BM_LiveMetaRelief)->ArgsProduct({{2, 3, 5}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

// Texture fetches per pixel on the verification scene (CONVENTIONS §7), counted on the CPU by running the
// shaders' own search loops (shaders/shared/relief_search.h: reliefIntersect and reliefLit, in float, through
// strata/trace/shader_loops.h) on the same rays with relief.frag.glsl's step rule (reliefLinearSteps),
// against the base-level bilinear height field:
// unit quad, `stone-bricks` 256^2, S = 0.1, 256^2 pixels, camera 45 degrees from the normal at distance 1.6,
// light at (1.5, 0, 1.5), shaded output with self-shadowing. Counted: every fetch of the packed relief
// texture and of the colour texture. Args: Technique, linear steps, binary steps. Reported as counters
// mean / p95 / max over the pixels that show the quad; the time is that of the CPU count, not of a render.
void BM_FetchesPerPixel(benchmark::State& state) {
    static const ReliefTexture texture = makePattern("stone-bricks", {256, 1, 0.1});
    static const HeightFieldTracer tracer(texture.depth, 0.1);
    const double S = 0.1;
    const auto technique = static_cast<Technique>(state.range(0));
    const int linear = static_cast<int>(state.range(1));
    const int binary = static_cast<int>(state.range(2));
    Camera camera;
    const double a = 45.0 * 3.14159265358979 / 180.0;
    camera.target = {0.5, 0.5, 0.0};
    camera.eye = camera.target + 1.6 * glm::dvec3(0.0, -std::sin(a), std::cos(a));
    camera.fovYDegrees = 40.0;
    const glm::dvec3 light(1.5, 0.0, 1.5);
    std::vector<int> counts;
    CpuReliefSearch search(tracer);
    // relief.frag.glsl's step count: reliefLinearSteps of the angle, clamped to [1, 4 N].
    const auto steps = [&](double cosTheta) {
        return std::clamp(shared::reliefLinearSteps(linear, static_cast<float>(cosTheta)), 1, 4 * linear);
    };
    for (auto _ : state) {
        counts.clear();
        for (int py = 0; py < 256; ++py) {
            for (int px = 0; px < 256; ++px) {
                const glm::dvec3 dir = pixelRayDirection(camera, 256, 256, px + 0.5, py + 0.5);
                if (dir.z >= 0.0) continue;
                const double t = -camera.eye.z / dir.z;
                const glm::dvec2 entry(camera.eye.x + t * dir.x, camera.eye.y + t * dir.y);
                if (entry.x < 0.0 || entry.x > 1.0 || entry.y < 0.0 || entry.y > 1.0) continue;
                int fetches = technique == Technique::Texture ? 1 : 2;  // colour (+ the packed texel)
                shared::vec2 hitUv(entry);  // the shaded point's uv and depth (relief.frag.glsl)
                float hitDepth = 0.0f;
                float bracket = 0.0f;
                const shared::vec2 ds(glm::dvec2(dir.x, dir.y) * S / -dir.z);
                search.resetFetches();
                if (technique == Technique::Parallax) {
                    ++fetches;  // d at the fragment's uv
                    hitUv += ds * static_cast<float>(tracer.depthAt(entry.x, entry.y));
                }
                if (technique == Technique::Relief) {
                    const int n = steps(dir.z);
                    hitDepth = search.reliefIntersect(hitUv, ds, n, binary);
                    bracket = 1.0f / (static_cast<float>(n) *
                                      std::exp2(static_cast<float>(std::max(binary - 1, 0))));
                    hitUv += ds * hitDepth;
                } else {
                    // The other techniques test the relief point under the uv they shade.
                    ++fetches;
                    hitDepth = static_cast<float>(
                        tracer.depthAt(static_cast<double>(hitUv.x), static_cast<double>(hitUv.y)));
                }
                // reliefLit, with the shaded output's bias (relief_search.glsl's kShadowBias).
                const glm::dvec3 hitPoint(static_cast<double>(hitUv.x), static_cast<double>(hitUv.y),
                                          -S * static_cast<double>(hitDepth));
                const glm::dvec3 toLight = light - hitPoint;
                search.reliefLit(hitUv, hitDepth, bracket, shared::vec3(toLight), static_cast<float>(S),
                                 steps(toLight.z / glm::length(toLight)), 0.02f);
                counts.push_back(fetches + search.fetches());
            }
        }
    }
    std::sort(counts.begin(), counts.end());
    double sum = 0.0;
    for (int c : counts) sum += c;
    state.counters["mean"] = sum / static_cast<double>(counts.size());
    state.counters["p95"] = counts[counts.size() * 95 / 100];
    state.counters["max"] = counts.back();
    state.SetLabel(std::string(toString(technique)) +
                   (technique == Technique::Relief
                        ? " " + std::to_string(linear) + "+" + std::to_string(binary)
                        : std::string()));
}
BENCHMARK(BM_FetchesPerPixel)
    ->Args({0, 10, 5})
    ->Args({1, 10, 5})
    ->Args({2, 10, 5})
    ->Args({3, 10, 5})
    ->Args({3, 64, 8})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
