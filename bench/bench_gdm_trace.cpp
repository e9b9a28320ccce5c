// The GDM verification scene (strata/gdm/gdm_trace.h): the exact reference against the paper's per-pixel
// algorithm emulated on the CPU, for the raw GDM and its rank-8 SVD. Produces the table of docs/gdm.md
// ("The exact reference and the paper's algorithm on the CPU").
//
// Conditions: the built-in `weave` and `chain` (makeMesostructure defaults), meshMesostructure at 64,
// bakeGdm at the default 64 x 64 x 16 voxels x 16 x 32 directions, compressGdm at rank 8 (the paper's
// layout); baked once per structure, outside the timing. Camera: looking at the quad's centre (0.5, 0.5, 0)
// from distance 1.6, at 5, 45 or 75 degrees from the normal (the eye on the -y side: (0.5,
// 0.5 - 1.6 sin a, 1.6 cos a)), vertical field of view 45 degrees, 256 x 256. Point light (0.5, -0.6, 1.1).
// Time per iteration: one reference and two emulations. Counters: compareGdmScenes (hit/miss
// disagreement %, uvw error in voxels of H / Nz = 1 / 64 tile widths: mean, p95, p99; shadow agreement %
// over the pixels where both hit), for raw ("raw_") and rank 8 ("r8_") with the default (nearest)
// direction lookup, and for raw with the bilinear one ("rawBilinear_", computed outside the timing).
// With STRATA_GDM_TRACE_IMAGES=<dir>, each case also writes <dir>/gdm_<name>_<angle>_uvw.png: the uvw
// pictures of reference | raw emulation | rank-8 emulation side by side (R, G, B = u, v, w; 8 bits), and
// below them w alone as gray.
// Run: build/ci/bench/bench_gdm_trace --benchmark_min_time=0.01
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/image/image_io.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <numbers>
#include <string>

namespace {

constexpr int kSize = 256;
constexpr glm::dvec3 kLight{0.5, -0.6, 1.1};

struct Structure {
    strata::SolidMesh solid;
    strata::Gdm raw;
    strata::GdmSvd svd;
};

const Structure& structure(const std::string& name) {
    static std::map<std::string, std::unique_ptr<Structure>> cache;
    auto& entry = cache[name];
    if (!entry) {
        entry = std::make_unique<Structure>();
        entry->solid = strata::meshMesostructure(strata::makeMesostructure(name), 64);
        entry->raw = strata::bakeGdm(entry->solid, strata::GdmDims{});
        entry->svd = strata::compressGdm(entry->raw, 8);
    }
    return *entry;
}

void setCounters(benchmark::State& state, const std::string& prefix, const strata::GdmSceneAccuracy& a) {
    state.counters[prefix + "hitmiss%"] = a.hitMissDisagreePercent;
    state.counters[prefix + "mean"] = a.uvwMeanVoxels;
    state.counters[prefix + "p95"] = a.uvwP95Voxels;
    state.counters[prefix + "p99"] = a.uvwP99Voxels;
    state.counters[prefix + "shadow%"] = a.shadowAgreePercent;
}

void writeSideBySide(const std::string& path, const strata::GdmSceneImages* images[3]) {
    strata::Image out(3 * kSize, 2 * kSize, 3);
    for (int n = 0; n < 3; ++n)
        for (int j = 0; j < kSize; ++j)
            for (int i = 0; i < kSize; ++i)
                for (int c = 0; c < 3; ++c) {
                    out.at(n * kSize + i, j, c) = images[n]->uvw.at(i, j, c);
                    out.at(n * kSize + i, kSize + j, c) = images[n]->uvw.at(i, j, 2);
                }
    strata::writePng(path, out, {strata::PngBitDepth::Eight, false});
}

void BM_GdmScene(benchmark::State& state, const std::string& name, int angleDegrees) {
    const Structure& s = structure(name);
    const strata::Camera camera = strata::gdmSceneView(angleDegrees);
    strata::GdmSceneImages reference, raw, rank8;
    for (auto _ : state) {
        reference = strata::renderGdmReference(s.solid, camera, kLight, kSize, kSize);
        raw = strata::emulateGdm(s.raw, camera, kLight, kSize, kSize);
        rank8 = strata::emulateGdm(s.svd, camera, kLight, kSize, kSize);
    }
    const strata::GdmSceneImages bilinear =
        strata::emulateGdm(s.raw, camera, kLight, kSize, kSize, strata::GdmDirectionLookup::Bilinear);
    const double voxel = s.raw.height / s.raw.dims.nz;
    setCounters(state, "raw_", strata::compareGdmScenes(reference, raw, s.raw.height, voxel));
    setCounters(state, "rawBilinear_", strata::compareGdmScenes(reference, bilinear, s.raw.height, voxel));
    setCounters(state, "r8_", strata::compareGdmScenes(reference, rank8, s.raw.height, voxel));
    if (const char* dir = std::getenv("STRATA_GDM_TRACE_IMAGES")) {
        const strata::GdmSceneImages* images[3] = {&reference, &raw, &rank8};
        writeSideBySide(std::string(dir) + "/gdm_" + name + "_" + std::to_string(angleDegrees) + "_uvw.png",
                        images);
    }
}

int registerAll() {
    for (const char* name : {"weave", "chain"})
        for (int angle : {5, 45, 75})
            benchmark::RegisterBenchmark(
                ("BM_GdmScene/" + std::string(name) + "/" + std::to_string(angle)).c_str(), BM_GdmScene,
                std::string(name), angle)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
    return 0;
}
const int kRegistered = registerAll();

}  // namespace

BENCHMARK_MAIN();
