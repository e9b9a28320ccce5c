// Environment lighting of the GDM renderer (issue 19, docs/gdm.md "Global illumination"): the frame cost of
// the example scenes lit by their sky against the same frame under local illumination, what each example
// precomputes (the RTV and the macro transfer: time and memory), and the GL picture's error against the
// path tracer on the verification scene.
//
// Conditions: a headless OpenGL 4.5 context (llvmpipe on the 2-core build machine, or a GPU where there is
// one); each example scene as `strata render` reads it, its built-in mesostructure baked once per process at
// `strata gdm bake`'s defaults (64 x 64 x 16 voxels, 16 x 32 directions, rank 8, the signed distance volume)
// with the scene's RTV (env_bounces, env_rank) before any timing.
//   frame/<scene>/<lighting>  gl::renderGdmPicture of the shaded picture at 512 x 512, one sample per pixel
//                             (the draw, its read-back and the conversion to sRGB), with the scene's point
//                             light turned on (white) and: environment = the scene's sky as well (the RTV
//                             lookup and dot product in every hit's shading), local = no environment (the
//                             ambient term), glossy = the environment with a glossy term as well
//                             (env_specular 0.4: the glossy RTV's rank-4 SVD reconstructed per hit). The
//                             ratio to local is the environment's cost.
//   turn/<scene>              GdmRenderer::setEnvironment of the scene's sky turned by 1 degree more each
//                             time (turnEnvironment): per vertex the macro transfer times the SH, on the CPU,
//                             and the upload; what the viewer does when the sky turns.
//   rtv/<scene>               bakeGdmRtv with the scene's bounces and compressGdmRtv to its rank (the raw
//                             GDM and the distance volume already baked). Counters: the rank's GPU maps
//                             (weights, basis, inside flags) and the uncompressed RTV.
//   macro/<scene>             bakeMacroTransfer of the scene's mesh from the top of its shell (Embree, 2560
//                             rays per vertex). Counter: its 16 x 16 floats per vertex.
//   accuracy/<meso>/<technique>/<albedo>  one run: the GL picture of the verification scene (§8's view at
//                             45 degrees, 128 x 128) lit by the band-limited overcast sky, 1 bounce, against
//                             pathTraceGdm (256 paths per pixel) under the same sky: relative RMSE over the
//                             surface hits of both (gdmSurfaceHitMask). albedo: grey (0.7 in both) or the
//                             mesostructure's colours (the renderer's trilinear albedo volume against the
//                             path tracer's exact albedo).
//   curved/<bounces>          one run: the chain torus (gdm_torus_chain_sky.json's mesh, tiling, GDM and
//                             technique) at 128 x 96 under the band-limited overcast sky, albedo the chain's
//                             colours, the RTV with `bounces` interreflections, against pathTraceGdmMesh (the
//                             exact warped chain, macro occlusion by the torus, 64 paths per pixel) with as
//                             many: relative RMSE over the pixels both hit.
//                             STRATA_GDM_ENV_CURVED_IMAGE=PREFIX writes PREFIX_<bounces>.png: the GL picture
//                             and the path tracer's side by side.
// Run: build/ci/bench/bench_gdm_environment --benchmark_counters_tabular=true
#include "strata/environment/environment.h"
#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_mesh_path_trace.h"
#include "strata/gdm/gdm_path_trace.h"
#include "strata/gdm/gdm_rtv.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/macro_transfer.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gdm/scene_gdm.h"
#include "strata/gl/context.h"
#include "strata/gl/gdm_picture.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/image/image_io.h"
#include "strata/image/srgb.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/scene/scene.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <utility>

namespace {

constexpr const char* kScenes[] = {"gdm_torus_chain_sky", "gdm_trunk_bark_sky"};
constexpr double kMiB = 1 << 20;

strata::gl::HeadlessContext& context() {
    static const auto made = strata::gl::HeadlessContext::create();
    return *made;
}

struct Loaded {
    strata::Scene scene;
    strata::Mesh mesh;
    strata::SceneGdm gdm;
};

// The scene `name`; with `specular` > 0 its environment gets the glossy term too (env_specular).
const Loaded& loaded(const std::string& name, double specular = 0.0) {
    static std::map<std::pair<std::string, double>, std::unique_ptr<Loaded>> cache;
    auto& slot = cache[{name, specular}];
    if (!slot) {
        slot = std::make_unique<Loaded>();
        slot->scene =
            strata::readScene(std::string(STRATA_SOURCE_DIR) + "/examples/scenes/" + name + ".json");
        slot->scene.environment.specular = specular;
        slot->mesh = strata::loadSceneMesh(slot->scene);
        slot->gdm = strata::loadSceneGdm(slot->scene);
    }
    return *slot;
}

void frame(benchmark::State& state, const std::string& name, bool environment, double specular) {
    context();
    const Loaded& l = loaded(name, specular);
    strata::gl::GdmRenderer renderer;
    strata::gl::prepareGdmRenderer(renderer, l.gdm, l.mesh, l.scene);
    if (!environment) renderer.clearEnvironment();
    strata::Lighting lighting = l.scene.lighting;
    lighting.lightColor = glm::dvec3(1.0);
    renderer.setLighting(lighting);
    strata::PictureSettings picture = l.scene.picture;
    picture.width = picture.height = 512;
    picture.samples = 1;
    for (auto _ : state) {
        const strata::Image image =
            strata::gl::renderGdmPicture(renderer, *l.scene.camera, lighting, picture, l.scene.gdm.technique);
        benchmark::DoNotOptimize(image.row(0));
    }
    state.counters["environment_MiB"] = double(renderer.gpuMemory().environment) / kMiB;
    state.counters["gpu_MiB"] = double(renderer.gpuMemory().total()) / kMiB;
    state.SetLabel(l.gdm.description);
}

void turn(benchmark::State& state, const std::string& name) {
    context();
    const Loaded& l = loaded(name);
    strata::gl::GdmRenderer renderer;
    strata::gl::prepareGdmRenderer(renderer, l.gdm, l.mesh, l.scene);
    double degrees = 0.0;
    for (auto _ : state) {
        degrees += 1.0;
        renderer.setEnvironment(strata::turnEnvironment(l.gdm.environmentSh, degrees, 1.0));
    }
    state.counters["vertices"] = double(l.mesh.vertices.size());
}

void rtv(benchmark::State& state, const std::string& name) {
    const Loaded& l = loaded(name);
    const strata::GdmAsset& asset = l.gdm.asset;
    const strata::GdmDims& d = asset.svd.dims;
    const strata::GdmAlbedo albedo = strata::gdmVolumeAlbedo(asset.albedo, d.nx, d.ny, d.nz);
    strata::GdmRtvOptions options;
    options.bounces = l.scene.environment.bounces;
    std::size_t rawBytes = 0, gpuBytes = 0;
    for (auto _ : state) {
        const strata::GdmRtv baked = strata::bakeGdmRtv(*asset.raw, asset.distance, albedo, options);
        const strata::GdmRtvSvd svd = strata::compressGdmRtv(baked, l.scene.environment.rank);
        rawBytes = baked.transfer.size() * sizeof(float);
        gpuBytes = (svd.weights.size() + svd.basis.size() + svd.distance.size()) * sizeof(float);
        benchmark::DoNotOptimize(svd.weights.data());
    }
    state.counters["rtv_gpu_MiB"] = double(gpuBytes) / kMiB;
    state.counters["rtv_raw_MiB"] = double(rawBytes) / kMiB;
    state.SetLabel(l.gdm.description);
}

void macro(benchmark::State& state, const std::string& name) {
    const Loaded& l = loaded(name);
    strata::PrismShellOptions shell;
    shell.height = l.gdm.asset.svd.height;
    shell.tiling = glm::dvec2(l.scene.relief.tiling);
    shell.thickness = l.scene.gdm.shellThickness;
    strata::MacroTransferOptions options;
    options.shellThickness = strata::buildPrismShell(l.mesh, shell).thickness;
    std::size_t bytes = 0;
    for (auto _ : state) {
        const strata::MacroTransfer transfer = strata::bakeMacroTransfer(l.mesh, options);
        bytes = transfer.matrices.size() * sizeof(float);
        benchmark::DoNotOptimize(transfer.matrices.data());
    }
    state.counters["macro_MiB"] = double(bytes) / kMiB;
    state.counters["vertices"] = double(l.mesh.vertices.size());
}

void accuracy(benchmark::State& state, const std::string& meso, strata::GdmTechnique technique, bool colour) {
    context();
    strata::Scene scene;
    scene.gdm.source = meso;
    const strata::SceneGdm gdm = strata::loadSceneGdm(scene);
    const strata::GdmAsset& asset = gdm.asset;
    const strata::GdmDims& d = asset.svd.dims;
    const strata::Mesostructure structure = strata::makeMesostructure(meso);
    const strata::GdmAlbedo albedo =
        colour ? strata::mesostructureLinearAlbedo(structure)
               : strata::GdmAlbedo([](const glm::dvec3&) { return glm::dvec3(0.7); });
    const strata::ShColor sky = strata::makeEnvironment("sky-overcast", 64, 32).sh();
    constexpr int kSize = 128;
    const strata::Camera camera = strata::gdmSceneView(45.0);
    const glm::dvec3 light(0.5, -0.6, 1.1);
    double error = 0.0;
    for (auto _ : state) {
        const strata::Mesh quad = strata::makeBuiltinMesh("quad");
        strata::gl::GdmRenderer renderer;
        renderer.setGdm(*asset.raw);
        renderer.setMesh(quad, {});
        renderer.setBaseEntry(false);
        renderer.setVolumes(asset.occupancy, colour ? asset.albedo : std::vector<std::uint8_t>{});
        renderer.setDistance(asset.distance);
        strata::Lighting lighting;
        lighting.lightColor = glm::dvec3(0.0);
        renderer.setLighting(lighting);
        renderer.setRtv(
            strata::bakeGdmRtv(*asset.raw, asset.distance,
                               colour ? strata::gdmVolumeAlbedo(asset.albedo, d.nx, d.ny, d.nz) : albedo));
        renderer.setMacroTransfer(strata::bakeMacroTransfer(quad));
        renderer.setEnvironment(sky);
        const strata::GdmSceneImages hits =
            renderer.render(camera, light, kSize, kSize, strata::GdmDirectionLookup::Nearest, technique);
        const strata::Image shaded = renderer.renderShaded(camera, light, kSize, kSize,
                                                           strata::GdmDirectionLookup::Nearest, technique);
        strata::Image radiance(kSize, kSize, 3);
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x)
                for (int c = 0; c < 3; ++c) radiance.at(x, y, c) = shaded.at(x, y, c);
        strata::GdmPathTraceOptions options;
        options.samplesPerPixel = 256;
        options.bounces = 1;
        const strata::EnvironmentRadiance environment = [&sky](const glm::dvec3& direction) {
            return glm::max(strata::shReconstruct(sky, direction), glm::dvec3(0.0));
        };
        const strata::GdmPathTraceImages reference =
            strata::pathTraceGdm(*asset.solid, albedo, environment, camera, kSize, kSize, options);
        const strata::Image exact =
            strata::gdmSurfaceHitMask(strata::renderGdmReference(*asset.solid, camera, light, kSize, kSize));
        error = strata::gdmRelativeRmse(radiance, strata::gdmSurfaceHitMask(hits), reference.radiance, exact);
    }
    state.counters["relative_rmse_percent"] = 100.0 * error;
}

void curved(benchmark::State& state, int bounces) {
    context();
    const Loaded& l = loaded("gdm_torus_chain_sky");
    strata::Scene scene = l.scene;
    scene.environment.source = "sky-overcast";
    scene.environment.rotation = 0.0;
    scene.environment.intensity = 1.0;
    scene.environment.bounces = bounces;
    scene.environment.rank = 48;
    const strata::SceneGdm gdm = strata::loadSceneGdm(scene);
    const strata::ShColor sky = *gdm.environment;
    constexpr int kWidth = 128, kHeight = 96;
    double error = 0.0, coverage = 0.0;
    for (auto _ : state) {
        strata::gl::GdmRenderer renderer;
        const strata::PrismShellOptions shell = strata::gl::prepareGdmRenderer(renderer, gdm, l.mesh, scene);
        const strata::Camera camera = *scene.camera;
        const glm::dvec3 light = scene.lighting.lightPosition;
        const strata::GdmSceneImages hits = renderer.render(
            camera, light, kWidth, kHeight, strata::GdmDirectionLookup::Nearest, scene.gdm.technique);
        const strata::Image shaded = renderer.renderShaded(
            camera, light, kWidth, kHeight, strata::GdmDirectionLookup::Nearest, scene.gdm.technique);
        strata::Image radiance(kWidth, kHeight, 3);
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                for (int c = 0; c < 3; ++c) radiance.at(x, y, c) = shaded.at(x, y, c);
        const strata::Mesostructure meso = strata::makeMesostructure("chain");
        strata::GdmMeshPathTraceOptions options;
        options.samplesPerPixel = 64;
        options.bounces = bounces;
        const strata::EnvironmentRadiance environment = [&sky](const glm::dvec3& direction) {
            return glm::max(strata::shReconstruct(sky, direction), glm::dvec3(0.0));
        };
        const strata::GdmPathTraceImages reference =
            strata::pathTraceGdmMesh(*gdm.asset.solid, l.mesh, shell, strata::mesostructureLinearAlbedo(meso),
                                     environment, camera, kWidth, kHeight, options);
        error = strata::gdmRelativeRmse(radiance, hits.mask, reference.radiance, reference.mask);
        if (const char* path = std::getenv("STRATA_GDM_ENV_CURVED_IMAGE")) {
            // GL | path tracer, sRGB, side by side.
            strata::Image both(2 * kWidth, kHeight, 3);
            for (int y = 0; y < kHeight; ++y)
                for (int x = 0; x < kWidth; ++x)
                    for (int c = 0; c < 3; ++c) {
                        both.at(x, y, c) =
                            float(strata::linearToSrgb(std::clamp(double(radiance.at(x, y, c)), 0.0, 1.0)));
                        both.at(x + kWidth, y, c) = float(strata::linearToSrgb(
                            std::clamp(double(reference.radiance.at(x, y, c)), 0.0, 1.0)));
                    }
            strata::writePng(std::string(path) + "_" + std::to_string(bounces) + ".png", both);
        }
        double both = 0.0, any = 0.0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                const bool a = hits.mask.at(x, y) > 0.5f, b = reference.mask.at(x, y) > 0.5f;
                both += a && b ? 1.0 : 0.0;
                any += a || b ? 1.0 : 0.0;
            }
        coverage = any > 0.0 ? both / any : 0.0;
    }
    state.counters["relative_rmse_percent"] = 100.0 * error;
    state.counters["mask_iou"] = coverage;
}

}  // namespace

int main(int argc, char** argv) {
    for (const char* name : kScenes) {
        for (const bool environment : {true, false})
            benchmark::RegisterBenchmark(
                (std::string("frame/") + name + "/" + (environment ? "environment" : "local")).c_str(), frame,
                std::string(name), environment, 0.0)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
        benchmark::RegisterBenchmark((std::string("frame/") + name + "/glossy").c_str(), frame,
                                     std::string(name), true, 0.4)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
        benchmark::RegisterBenchmark((std::string("turn/") + name).c_str(), turn, std::string(name))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
        benchmark::RegisterBenchmark((std::string("rtv/") + name).c_str(), rtv, std::string(name))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
        benchmark::RegisterBenchmark((std::string("macro/") + name).c_str(), macro, std::string(name))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
    for (const char* meso : {"weave", "chain"})
        for (const auto technique : {strata::GdmTechnique::Gdm, strata::GdmTechnique::Refine})
            for (const bool colour : {false, true})
                benchmark::RegisterBenchmark(
                    (std::string("accuracy/") + meso + "/" + strata::toString(technique) + "/" +
                     (colour ? "colour" : "grey"))
                        .c_str(),
                    accuracy, std::string(meso), technique, colour)
                    ->Unit(benchmark::kMillisecond)
                    ->Iterations(1)
                    ->UseRealTime();
    for (const int bounces : {0, 1, 2})
        benchmark::RegisterBenchmark((std::string("curved/") + std::to_string(bounces)).c_str(), curved,
                                     bounces)
            ->Unit(benchmark::kMillisecond)
            ->Iterations(1)
            ->UseRealTime();
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
