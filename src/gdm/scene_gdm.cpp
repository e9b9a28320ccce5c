#include "strata/gdm/scene_gdm.h"

#include "strata/core/error.h"
#include "strata/environment/environment.h"
#include "strata/environment/sh_rotation.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_distance.h"
#include "strata/gdm/gdm_path_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"

#include <glm/gtc/constants.hpp>
#include <glm/trigonometric.hpp>

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

// The RTV and the environment of a scene with `env` (loadSceneGdm's contract).
void loadEnvironmentLighting(const Scene& scene, SceneGdm& out, const SceneProgress& progress) {
    const EnvironmentSettings& settings = scene.environment;
    if (progress) progress("environment " + settings.source);
    Environment environment = [&] {
        try {
            return openEnvironment(settings.source);
        } catch (const Error& e) {
            throw Error(e.kind(), std::string("env: ") + e.what());
        }
    }();
    if (!environment.isProcedural()) out.inputs.emplace_back(settings.source);
    out.environmentName = environment.name();
    out.environmentSh = environment.sh();
    out.environment = turnEnvironment(environment.sh(), settings.rotation, settings.intensity);

    GdmAsset& asset = out.asset;
    Gdm rebaked;
    const Gdm* raw = asset.raw ? &*asset.raw : nullptr;
    if (!raw) {
        if (!asset.solid)
            throw Error(
                ErrorKind::InvalidInput,
                scene.gdm.source +
                    ": env: the radiance transfer is baked from the raw GDM or the solid, and the asset "
                    "holds neither (raw.f32, solid.obj): bake it again with `strata gdm bake`");
        if (progress) progress("baking the GDM again from the solid, for the radiance transfer");
        rebaked = bakeGdm(*asset.solid, asset.svd.dims);
        raw = &rebaked;
    }
    std::vector<float> distance = asset.distance;
    if (distance.empty()) {
        if (!asset.solid)
            throw Error(ErrorKind::InvalidInput, scene.gdm.source +
                                                     ": env: the radiance transfer needs the signed distance "
                                                     "(distance.f32) or the solid (solid.obj)");
        distance = bakeGdmDistance(*asset.solid, asset.svd.dims);
    }
    const GdmDims& dims = asset.svd.dims;
    const GdmAlbedo albedo = asset.albedo.empty()
                                 ? GdmAlbedo([](const glm::dvec3&) { return glm::dvec3(0.7); })
                                 : gdmVolumeAlbedo(asset.albedo, dims.nx, dims.ny, dims.nz);
    if (progress)
        progress("radiance transfer, " + std::to_string(settings.bounces) + " bounce" +
                 (settings.bounces == 1 ? "" : "s"));
    GdmRtvOptions options;
    options.bounces = settings.bounces;
    const GdmRtv rtv = bakeGdmRtv(*raw, distance, albedo, options);
    out.rtv = compressGdmRtv(rtv, settings.rank);
    if (settings.specular > 0.0) {
        if (progress) progress("glossy radiance transfer, shininess " + formatNumber(settings.shininess));
        GdmGlossyOptions glossy;
        glossy.shininess = settings.shininess;
        // Baked in chunks straight into its SVD: the uncompressed form (1 GiB at the defaults) is never held.
        const int views = (raw->dims.ntheta / 2) * raw->dims.nphi;
        out.glossy = bakeCompressedGdmGlossyRtv(*raw, distance, glossy, std::min(settings.rank, views));
        out.glossySpecular = settings.specular;
    }
    out.description +=
        ", " + out.environmentName + " (RTV rank " + std::to_string(settings.rank) + ", " +
        std::to_string(settings.bounces) + " bounce" + (settings.bounces == 1 ? "" : "s") +
        (out.glossy ? ", glossy " + formatNumber(settings.specular) + " s " + formatNumber(settings.shininess)
                    : std::string()) +
        ")";
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
    if (!scene.environment.source.empty()) loadEnvironmentLighting(scene, out, progress);
    return out;
}

ShColor turnEnvironment(const ShColor& world, double degrees, double intensity) {
    const double a = glm::radians(degrees);
    // Columns of the rotation about +z by a: a light from direction d moves to R d.
    const glm::dmat3 rotation(glm::dvec3(std::cos(a), std::sin(a), 0.0),
                              glm::dvec3(-std::sin(a), std::cos(a), 0.0), glm::dvec3(0.0, 0.0, 1.0));
    ShColor turned = shRotate(world, rotation);
    for (glm::dvec3& c : turned) c *= intensity;
    return turned;
}

}  // namespace strata
