// The example GDM scenes (examples/scenes/gdm_*.json, docs/gdm.md): frame time of each scene with each
// technique at 512 x 512, and the GPU memory of what each draws.
//
// Conditions: each scene as `strata render` reads it (its mesh, GDM, rank, tiling, camera and light), its
// built-in mesostructure baked once per process at `strata gdm bake`'s defaults (64 x 64 x 16 voxels, 16 x 32
// directions, rank 8, the signed distance volume) before any timing; a headless OpenGL 4.5
// context (llvmpipe on the 2-core build machine, or a GPU where there is one). A frame is
// gl::renderGdmPicture of the shaded picture at 512 x 512 with one sample per pixel: the draw, its read-back
// and the conversion to sRGB. Counters: the buffers the GDM renderer holds for the scene
// (GdmRenderer::gpuMemory): the GDM (the SVD's maps, or the raw values), the volumes (occupancy, albedo,
// signed distance), the shell, and their total.
// Run: build/ci/bench/bench_gdm_scenes --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include "strata/gdm/prism_shell.h"
#include "strata/gdm/scene_gdm.h"
#include "strata/gl/context.h"
#include "strata/gl/gdm_picture.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/scene/scene.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

namespace {

constexpr const char* kScenes[] = {"gdm_torus_chain", "gdm_vase_grid", "gdm_teapot_weave",
                                   "gdm_sphere_scales", "gdm_patch_weave"};

strata::gl::HeadlessContext& context() {
    static const auto made = strata::gl::HeadlessContext::create();
    return *made;
}

struct Loaded {
    strata::Scene scene;
    strata::Mesh mesh;
    strata::SceneGdm gdm;
};

const Loaded& loaded(const std::string& name) {
    static std::map<std::string, std::unique_ptr<Loaded>> cache;
    auto& slot = cache[name];
    if (!slot) {
        slot = std::make_unique<Loaded>();
        slot->scene =
            strata::readScene(std::string(STRATA_SOURCE_DIR) + "/examples/scenes/" + name + ".json");
        slot->mesh = strata::loadSceneMesh(slot->scene);
        slot->gdm = strata::loadSceneGdm(slot->scene);
    }
    return *slot;
}

void frame(benchmark::State& state, const std::string& name, strata::GdmTechnique technique) {
    context();
    const Loaded& l = loaded(name);
    strata::gl::GdmRenderer renderer;
    const strata::PrismShellOptions shell = strata::gl::prepareGdmRenderer(renderer, l.gdm, l.mesh, l.scene);
    strata::PictureSettings picture = l.scene.picture;
    picture.width = picture.height = 512;
    picture.samples = 1;
    const strata::Camera camera = *l.scene.camera;
    for (auto _ : state) {
        const strata::Image image =
            strata::gl::renderGdmPicture(renderer, camera, l.scene.lighting, picture, technique);
        benchmark::DoNotOptimize(image.row(0));
    }
    const strata::PrismShell prisms = strata::buildPrismShell(l.mesh, shell);
    const strata::gl::GdmGpuMemory memory = renderer.gpuMemory();
    constexpr double kMiB = 1 << 20;
    state.counters["gpu_MiB"] = double(memory.total()) / kMiB;
    state.counters["gdm_MiB"] = double(memory.gdm) / kMiB;
    state.counters["volumes_MiB"] = double(memory.volumes) / kMiB;
    state.counters["shell_MiB"] = double(memory.shell) / kMiB;
    state.counters["prisms"] = double(prisms.prisms.size());
    state.SetLabel(l.gdm.description);
}

}  // namespace

int main(int argc, char** argv) {
    for (const char* name : kScenes)
        for (const auto technique :
             {strata::GdmTechnique::Gdm, strata::GdmTechnique::Refine, strata::GdmTechnique::March})
            benchmark::RegisterBenchmark((std::string(name) + "/" + strata::toString(technique)).c_str(),
                                         frame, std::string(name), technique)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
