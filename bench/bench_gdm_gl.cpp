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
// `technique`: the quad at 512 x 512 with each technique (gdm on the rank-8 SVD; refine on the occupancy;
// march; refine on the signed distance volume, bakeGdmDistance at the GDM's voxels) at depth resolutions 16
// and 32 (the weave baked at 64 x 64 x 32 as well): the paper's gdm / slice-based ratio (60 vs 32 fps at
// 64 x 64 x 16, 57 vs 15 at 64 x 64 x 32) is the march / gdm time ratio here, and refine's cost is its
// time over gdm's.
// `accuracy`: the accuracy table (docs/gdm.md): weave, chain and scales baked as `strata gdm bake --meso`
// bakes them (64 x 64 x 16 x 16 x 32), views 5, 45 and 75 degrees from the normal at distance 1.6, each row
// against the exact reference on the §8 quad at 256 x 256: gdm raw and rank 8, refine (distance volume)
// with the raw GDM and rank 8, march, and refine with a distance volume at twice the voxels per axis.
// Counters only, times not meaningful (they include the reference render).
// Run: build/ci/bench/bench_gdm_gl --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
//      build/ci/bench/bench_gdm_gl --benchmark_filter=technique --benchmark_repetitions=3
//      build/ci/bench/bench_gdm_gl --benchmark_filter=accuracy --benchmark_counters_tabular=true
#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gl/context.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/scene/scene.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

const strata::SolidMesh& weaveSolid() {
    static const strata::SolidMesh solid = strata::meshMesostructure(strata::makeMesostructure("weave"), 64);
    return solid;
}

const strata::Gdm& weave(int depth = 16) {
    static const strata::Gdm gdm16 = strata::bakeGdm(weaveSolid(), strata::GdmDims{});
    static const strata::Gdm gdm32 = strata::bakeGdm(weaveSolid(), strata::GdmDims{64, 64, 32, 16, 32});
    return depth == 32 ? gdm32 : gdm16;
}

strata::Camera quadView(double degrees = 45.0) {
    return strata::gdmSceneView(degrees);
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
        camera = quadView();
    }
    const glm::dvec3 light(0.5, -0.6, 1.1);
    for (auto _ : state) benchmark::DoNotOptimize(renderer.render(camera, light, kSize, kSize));
    state.SetLabel(std::string(teapot ? "teapot" : "quad") + (state.range(1) == 0 ? ", rank 8" : ", raw"));
}

constexpr strata::gl::GdmTechnique kTechniques[] = {
    strata::gl::GdmTechnique::Gdm, strata::gl::GdmTechnique::Refine, strata::gl::GdmTechnique::March,
    strata::gl::GdmTechnique::Refine};
constexpr const char* kTechniqueNames[] = {"gdm", "refine (occupancy)", "march", "refine (distance)"};

// range(0): technique (3: refine on the distance volume); range(1): depth resolution 16 or 32.
void technique(benchmark::State& state) {
    context().makeCurrent();
    const strata::Gdm& gdm = weave(int(state.range(1)));
    strata::gl::GdmRenderer renderer;
    renderer.setGdm(strata::compressGdm(gdm, 8));
    renderer.setVolumes(strata::gdmOccupancy(gdm), {});
    if (state.range(0) == 3) renderer.setDistance(strata::bakeGdmDistance(weaveSolid(), gdm.dims));
    renderer.setMesh(strata::makeBuiltinMesh("quad"), {});
    const strata::gl::GdmTechnique which = kTechniques[state.range(0)];
    for (auto _ : state)
        benchmark::DoNotOptimize(renderer.render(quadView(), glm::dvec3(0.5, -0.6, 1.1), 512, 512,
                                                 strata::GdmDirectionLookup::Nearest, which));
    state.SetLabel(std::string(kTechniqueNames[state.range(0)]) + ", depth " +
                   std::to_string(state.range(1)));
}

// A built-in baked as `strata gdm bake --meso NAME` bakes it by default (64 x 64 x 16 x 16 x 32, the solid
// meshed at 64 voxels per tile), with its rank-8 SVD and its volumes.
struct Baked {
    strata::SolidMesh solid;
    strata::Gdm gdm;
    strata::GdmSvd svd;
    std::vector<std::uint8_t> occupancy;
    std::vector<float> distance;
    std::vector<float> fineDistance;  // at twice the voxels along each axis
};

constexpr const char* kMesoNames[] = {"weave", "chain", "scales"};

const Baked& baked(int meso) {
    static std::map<int, Baked> cache;
    auto found = cache.find(meso);
    if (found != cache.end()) return found->second;
    Baked b;
    b.solid = strata::meshMesostructure(strata::makeMesostructure(kMesoNames[meso]), 64);
    b.gdm = strata::bakeGdm(b.solid, strata::GdmDims{});
    b.svd = strata::compressGdm(b.gdm, 8);
    b.occupancy = strata::gdmOccupancy(b.gdm);
    b.distance = strata::bakeGdmDistance(b.solid, strata::GdmDims{});
    b.fineDistance = strata::bakeGdmDistance(b.solid, strata::GdmDims{128, 128, 32, 16, 32});
    return cache.emplace(meso, std::move(b)).first->second;
}

// The table's rows: what is drawn.
constexpr const char* kVariantNames[] = {"gdm raw",       "gdm rank 8", "refine raw",
                                         "refine rank 8", "march",      "refine raw, distance 2x"};

// range(0): mesostructure (kMesoNames); range(1): view angle from the normal, degrees; range(2): variant
// (kVariantNames). Against the exact reference on the §8 quad, 256 x 256, light (0.5, -0.6, 1.1).
void accuracy(benchmark::State& state) {
    context().makeCurrent();
    const Baked& b = baked(int(state.range(0)));
    const int variant = int(state.range(2));
    strata::gl::GdmRenderer renderer;
    if (variant == 1 || variant == 3)
        renderer.setGdm(b.svd);
    else
        renderer.setGdm(b.gdm);
    renderer.setVolumes(b.occupancy, {});
    if (variant == 5)
        renderer.setDistance(b.fineDistance, glm::ivec3(128, 128, 32));
    else
        renderer.setDistance(b.distance);
    renderer.setMesh(strata::makeBuiltinMesh("quad"), {});
    const strata::gl::GdmTechnique technique = variant <= 1   ? strata::gl::GdmTechnique::Gdm
                                               : variant == 4 ? strata::gl::GdmTechnique::March
                                                              : strata::gl::GdmTechnique::Refine;
    const glm::dvec3 light(0.5, -0.6, 1.1);
    const strata::Camera camera = quadView(double(state.range(1)));
    const strata::GdmSceneImages reference = strata::renderGdmReference(b.solid, camera, light, 256, 256);
    strata::GdmSceneAccuracy error;
    for (auto _ : state)
        error = strata::compareGdmScenes(
            reference,
            renderer.render(camera, light, 256, 256, strata::GdmDirectionLookup::Nearest, technique),
            b.gdm.height, b.gdm.height / b.gdm.dims.nz);
    state.counters["hitmiss%"] = error.hitMissDisagreePercent;
    state.counters["mean_vox"] = error.uvwMeanVoxels;
    state.counters["p95_vox"] = error.uvwP95Voxels;
    state.counters["p99_vox"] = error.uvwP99Voxels;
    state.counters["shadow%"] = error.shadowAgreePercent;
    state.SetLabel(std::string(kMesoNames[state.range(0)]) + " " + std::to_string(state.range(1)) + " deg, " +
                   kVariantNames[variant]);
}

}  // namespace

BENCHMARK(technique)->ArgsProduct({{0, 1, 2, 3}, {16, 32}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(accuracy)
    ->ArgsProduct({{0, 1, 2}, {5, 45, 75}, {0, 1, 2, 3, 4, 5}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(frame)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
