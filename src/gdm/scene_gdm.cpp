#include "strata/gdm/scene_gdm.h"

#include "strata/core/error.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"

#include <algorithm>

namespace fs = std::filesystem;

namespace strata {

namespace {

std::string builtinNames() {
    std::string names;
    for (const MesostructureInfo& info : mesostructureList())
        names += (names.empty() ? "" : ", ") + info.name;
    return names;
}

// `strata gdm bake --meso NAME` with its defaults, raw GDM kept.
GdmAsset bakeBuiltin(const std::string& name, const SceneProgress& progress) {
    const Mesostructure meso = makeMesostructure(name);
    const GdmDims dims;
    validateGdmDims(dims, meso.height(), "gdm " + name);
    const int resolution = std::clamp(std::max(dims.nx, dims.ny), kMinMeshResolution, kMaxMeshResolution);
    if (progress) progress("meshing " + name + " at " + std::to_string(resolution) + " voxels per tile");
    SolidMesh solid = meshMesostructure(meso, resolution);
    int lastTenth = -1;
    Gdm raw = bakeGdm(solid, dims, [&](double done) {
        const int tenth = int(done * 10.0);
        if (!progress || tenth == lastTenth) return;
        lastTenth = tenth;
        progress("baking " + name + " " + std::to_string(tenth * 10) + "%");
    });
    if (progress) progress("compressing to rank " + std::to_string(kSceneGdmDefaultRank));
    GdmAsset asset;
    asset.svd = compressGdm(raw, kSceneGdmDefaultRank);
    asset.occupancy = gdmOccupancy(raw);
    asset.albedo = mesostructureAlbedo(meso, dims);
    if (progress) progress("signed distance");
    asset.distance = bakeGdmDistance(solid, dims);
    asset.raw = std::move(raw);
    asset.solid = std::move(solid);
    asset.source = "meso " + name;
    return asset;
}

}  // namespace

SceneGdm loadSceneGdm(const Scene& scene, const SceneProgress& progress) {
    const GdmSettings& settings = scene.gdm;
    if (settings.source.empty())
        throw Error(ErrorKind::InvalidInput, "scene: no gdm to load (the scene is a relief render)");
    const fs::path path(settings.source);
    SceneGdm out;
    std::error_code ec;
    if (fs::exists(path, ec)) {
        if (!fs::is_directory(path, ec) || !isGdmAsset(path))
            throw Error(ErrorKind::Io,
                        settings.source +
                            ": not a GDM asset directory (one from `strata gdm bake`, holding " +
                            kGdmAssetSidecar + ")");
        if (progress) progress("reading " + settings.source);
        out.asset = readGdmAsset(path);
        for (const auto& entry : fs::directory_iterator(path, ec))
            if (entry.is_regular_file(ec)) out.inputs.push_back(entry.path());
        out.description = settings.source;
    } else {
        const auto& list = mesostructureList();
        if (std::none_of(list.begin(), list.end(),
                         [&](const MesostructureInfo& info) { return info.name == settings.source; }))
            throw Error(ErrorKind::InvalidInput,
                        "gdm: '" + settings.source +
                            "' is neither a GDM asset directory nor a built-in mesostructure (" +
                            builtinNames() + ")");
        out.asset = bakeBuiltin(settings.source, progress);
        out.description = "meso " + settings.source + " (baked on the fly)";
    }

    if (settings.rank == kGdmRankRaw) {
        if (!out.asset.raw)
            throw Error(
                ErrorKind::InvalidInput,
                settings.source +
                    ": gdm_rank raw: the asset holds no raw GDM (raw.f32); bake it with --keep-raw, or "
                    "draw its SVD");
        out.raw = true;
        out.description += ", raw GDM";
    } else {
        const int stored = out.asset.svd.rank;
        if (settings.rank > stored)
            throw Error(ErrorKind::InvalidInput, settings.source + ": gdm_rank " +
                                                     std::to_string(settings.rank) + " is more than the " +
                                                     std::to_string(stored) + " terms the asset stores");
        out.svd = settings.rank == 0 || settings.rank == stored
                      ? out.asset.svd
                      : truncateGdmSvd(out.asset.svd, settings.rank);
        out.description += ", rank " + std::to_string(out.svd.rank);
    }
    return out;
}

}  // namespace strata
