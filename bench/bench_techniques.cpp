// Intersection techniques compared (issue 5, part 4): texture fetches per pixel and error against the exact
// CPU reference, per technique, view angle and map.
//
// Conditions: the verification quad (CONVENTIONS §7), 192^2 pixels, camera at distance 1.6 tilted 30, 60 or
// 80 degrees from the normal, S = 0.1, maps at 256^2 (16-bit depth): the built-in patterns, and `walls`
// (1-texel-wide walls at d = 0 every 16 texels over a floor at d = 1). Techniques: relief 32 + 8 and
// 64 + 8 (the paper's search, adaptive step count), parallax (one fetch), maxmip (exact traversal), cone
// (exact cone stepping).
// Fetches: of the view ray's intersection only (no shadow ray, no shading fetch), counted on the CPU by
// running each shader's own loop (shaders/shared/*.h, in float, through strata/trace/shader_loops.h) on the
// same rays: reliefIntersect (one fetch per step), maxMipIntersect (one fetch per node read, one
// textureGather per cell solved), coneIntersect (one fetch per cell visited, one textureGather per cell
// solved), each against the base level's height field. Errors: the GL renderer's
// uv and depth outputs against renderQuadReference: hit/miss disagreement, and uv error in texels over the
// pixels where both hit, split by the sign of (d - d_exact) along the ray: overshoot (the technique stopped
// beyond the exact hit: it skipped a feature) and undershoot (it stopped short).
// Counters: fetches mean / p95 / max, miss% (hit/miss disagreement), over% and under% (share of the pixels
// off by more than 0.05 texel each way), overP99 / underP99 (99th percentile uv error in texels among those
// pixels, 0 if none). The benchmark time is that of the whole measurement, not of a frame.
// Run: build/release/bench/bench_techniques
#include "strata/gl/context.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/cone_map.h"
#include "strata/relief/max_mip.h"
#include "strata/relief/patterns.h"
#include "strata/relief/relief_texture.h"
#include "strata/scene/camera.h"
#include "strata/scene/render_settings.h"
#include "strata/trace/heightfield_tracer.h"
#include "strata/trace/quad_reference.h"
#include "strata/trace/shader_loops.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace {

using namespace strata;

constexpr double kDepthScale = 0.1;
constexpr int kMapSize = 256;
constexpr int kPicture = 192;

struct Context {
    std::unique_ptr<gl::HeadlessContext> context;
    std::unique_ptr<gl::ReliefRenderer> renderer;
    gl::GpuMesh quad;
    std::string failure;
};

Context& context() {
    static Context instance = [] {
        Context c;
        try {
            c.context = gl::HeadlessContext::create();
            c.renderer = std::make_unique<gl::ReliefRenderer>();
            c.quad = gl::uploadMesh(makeBuiltinMesh("quad"));
        } catch (const std::exception& error) {
            c.failure = error.what();
        }
        return c;
    }();
    return instance;
}

Image quantised(Image depth) {
    for (float& d : depth.pixels()) d = static_cast<float>(std::round(double(d) * 65535.0) / 65535.0);
    return depth;
}

ReliefTexture makeMap(const std::string& name) {
    ReliefTexture texture;
    if (name == "walls") {
        texture.depth = Image(kMapSize, kMapSize, 1, 1.0f);
        for (int y = 0; y < kMapSize; ++y)
            for (int x = 0; x < kMapSize; ++x)
                if (x % 16 == 0 || y % 16 == 0) texture.depth.at(x, y) = 0.0f;
    } else {
        texture.depth = makePattern(name, {kMapSize, 1, kDepthScale}).depth;
    }
    texture.depth = quantised(texture.depth);
    texture.normal = normalsFromDepth(texture.depth, kDepthScale);
    texture.depthScale = kDepthScale;
    return texture;
}

Camera camera(double angleDegrees) {
    const double a = angleDegrees * 3.14159265358979323846 / 180.0;
    Camera c;
    c.target = {0.5, 0.5, 0.0};
    c.eye = c.target + 1.6 * glm::dvec3(0.0, -std::sin(a), std::cos(a));
    c.fovYDegrees = 40.0;
    return c;
}

const std::vector<std::string>& maps() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> list;
        for (const PatternInfo& info : patternList()) list.push_back(info.name);
        list.push_back("walls");
        return list;
    }();
    return names;
}

// Args: technique (0 relief 32+8, 1 relief 64+8, 2 parallax, 3 maxmip, 4 cone), angle, map set (0 = the
// patterns, 1 = walls).
void BM_Technique(benchmark::State& state) {
    Context& c = context();
    if (!c.failure.empty()) {
        state.SkipWithError(c.failure.c_str());
        return;
    }
    const int which = static_cast<int>(state.range(0));
    const double angle = static_cast<double>(state.range(1));
    const bool walls = state.range(2) == 1;
    const Camera cam = camera(angle);
    std::vector<int> fetches;
    long referenceHits = 0, mismatches = 0, both = 0;
    std::vector<double> over, under;
    for (auto _ : state) {
        for (const std::string& name : maps()) {
            if ((name == "walls") != walls) continue;
            const ReliefTexture texture = makeMap(name);
            const HeightFieldTracer tracer(texture.depth, kDepthScale);
            CpuReliefSearch relief(tracer);
            const std::vector<Image> levels =
                which == 3 ? maxMipPyramid(texture.depth) : std::vector<Image>();
            std::optional<CpuMaxMipTraversal> maxMip =
                which == 3 ? std::optional<CpuMaxMipTraversal>(std::in_place, levels, texture.depth)
                           : std::nullopt;
            // The renderer's cone map (uploadMaterial): of the depth map's 16-bit values, which these are.
            const PackedConeMap packed = which == 4 ? packConeMap(texture.depth) : PackedConeMap();
            std::optional<CpuConeStepping> cone =
                which == 4 ? std::optional<CpuConeStepping>(std::in_place, packed.texels, packed.maxRatio,
                                                            texture.depth)
                           : std::nullopt;
            const gl::GpuMaterial material = gl::uploadMaterial(texture, kDepthScale);
            gl::RenderRequest request;
            request.objects.push_back({&c.quad, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
            request.camera = cam;
            request.relief.technique = which == 2   ? Technique::Parallax
                                       : which == 3 ? Technique::MaxMip
                                       : which == 4 ? Technique::Cone
                                                    : Technique::Relief;
            request.relief.linearSteps = which == 0 ? 32 : 64;
            request.relief.binarySteps = 8;
            request.relief.depthScale = kDepthScale;
            request.picture.width = request.picture.height = kPicture;
            request.picture.output = RenderOutput::Uv;
            const Image uv = c.renderer->render(request);
            request.picture.output = RenderOutput::Depth;
            const Image depth = c.renderer->render(request);
            const QuadReferenceImages reference = renderQuadReference(tracer, cam, kPicture, kPicture, {});
            for (int y = 0; y < kPicture; ++y) {
                for (int x = 0; x < kPicture; ++x) {
                    const bool refHit = reference.uv.at(x, y, 2) > 0.5f;
                    const bool testHit = uv.at(x, y, 2) > 0.5f;
                    referenceHits += refHit;
                    mismatches += refHit != testHit;
                    if (!refHit || !testHit) continue;
                    ++both;
                    // Wrapped uv difference in texels.
                    double error = 0.0;
                    for (int a = 0; a < 2; ++a) {
                        double du = static_cast<double>(uv.at(x, y, a)) -
                                    static_cast<double>(reference.uv.at(x, y, a));
                        du -= std::round(du);
                        error = std::max(error, std::abs(du) * kMapSize);
                    }
                    if (error > 0.05) {
                        (depth.at(x, y) > reference.depth.at(x, y) ? over : under).push_back(error);
                    }
                    // Fetches of this pixel's ray, as relief.frag.glsl sets it up (in float): entry tile
                    // coordinates and ds = s.xy S / s.z.
                    const glm::dvec3 dir = pixelRayDirection(cam, kPicture, kPicture, x + 0.5, y + 0.5);
                    const double t = -cam.eye.z / dir.z;
                    const shared::vec2 entry(glm::dvec2(cam.eye.x + t * dir.x, cam.eye.y + t * dir.y));
                    const shared::vec2 ds(glm::dvec2(dir.x, dir.y) * kDepthScale / -dir.z);
                    if (which == 3) {
                        maxMip->resetFetches();
                        maxMip->maxMipIntersect(entry, ds);
                        fetches.push_back(maxMip->fetches());
                    } else if (which == 4) {
                        cone->resetFetches();
                        cone->coneIntersect(entry, ds);
                        fetches.push_back(cone->fetches());
                    } else if (which == 2) {
                        fetches.push_back(1);
                    } else {
                        const int n = which == 0 ? 32 : 64;
                        const int steps =
                            std::clamp(shared::reliefLinearSteps(n, static_cast<float>(dir.z)), 1, 4 * n);
                        relief.resetFetches();
                        relief.reliefIntersect(entry, ds, steps, 8);
                        fetches.push_back(relief.fetches());
                    }
                }
            }
        }
    }
    std::sort(fetches.begin(), fetches.end());
    std::sort(over.begin(), over.end());
    std::sort(under.begin(), under.end());
    double sum = 0.0;
    for (const int f : fetches) sum += f;
    const auto p99 = [](const std::vector<double>& v) { return v.empty() ? 0.0 : v[v.size() * 99 / 100]; };
    state.counters["fetchMean"] = sum / static_cast<double>(std::max<std::size_t>(fetches.size(), 1));
    state.counters["fetchP95"] = fetches.empty() ? 0 : fetches[fetches.size() * 95 / 100];
    state.counters["fetchMax"] = fetches.empty() ? 0 : fetches.back();
    state.counters["miss%"] =
        100.0 * static_cast<double>(mismatches) / static_cast<double>(std::max(referenceHits, 1L));
    state.counters["over%"] =
        100.0 * static_cast<double>(over.size()) / static_cast<double>(std::max(both, 1L));
    state.counters["under%"] =
        100.0 * static_cast<double>(under.size()) / static_cast<double>(std::max(both, 1L));
    state.counters["overP99"] = p99(over);
    state.counters["underP99"] = p99(under);
    const char* names[] = {"relief 32+8", "relief 64+8", "parallax", "maxmip", "cone"};
    state.SetLabel(std::string(names[which]) + ", " + std::to_string(static_cast<int>(angle)) + " deg, " +
                   (walls ? "walls" : "patterns"));
}
BENCHMARK(BM_Technique)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {30, 60, 80}, {0, 1}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
