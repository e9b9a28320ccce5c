// The GDM a scene draws (Scene::gdm, GdmSettings): what `strata render --gdm` and strata-view load. A
// GDM asset directory is read; a built-in mesostructure name is baked on the fly, as `strata gdm bake --meso
// NAME` bakes it with its defaults (64 x 64 x 16 voxels, 16 x 32 directions, the structure's own H, rank 8 in
// the paper's layout), keeping the raw GDM. Then the scene's rank picks what the lookups read.
#pragma once

#include "strata/environment/spherical_harmonics.h"
#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_rtv.h"
#include "strata/gdm/gdm_rtv_glossy.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/scene/scene.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata {

// The rank a built-in is compressed to on the fly: `strata gdm bake`'s default.
inline constexpr int kSceneGdmDefaultRank = 8;

struct SceneGdm {
    GdmAsset asset;  // as read or baked; a built-in's keeps its raw GDM
    // What the lookups read: the raw GDM (asset.raw) when true, else `svd` (the asset's, truncated to the
    // scene's rank).
    bool raw = false;
    GdmSvd svd;
    std::string description;  // e.g. "meso weave (baked on the fly), rank 8"
    std::vector<std::filesystem::path>
        inputs;  // the asset's files (and the EXR) read: never to be overwritten

    // With scene.environment.source set: the RTV (bakeGdmRtv with the scene's bounces, compressed to its
    // rank) and the environment's SH in world space, turned and scaled (turnEnvironment).
    std::optional<GdmRtvSvd> rtv;
    // With scene.environment.specular > 0: the glossy RTV (bakeGdmGlossyRtv at the scene's shininess,
    // compressed to the scene's rank) and its specular coefficient.
    std::optional<GdmGlossyRtvSvd> glossy;
    double glossySpecular = 0.0;
    std::optional<ShColor> environment;
    std::string environmentName;  // "sky-overcast", the EXR's path
    ShColor environmentSh{};      // the environment's own SH (unturned, unscaled), for turning it again
};

// The SH of `world` turned by `degrees` about +z (towards +y: radiance that came from azimuth a comes from
// a + degrees) and scaled by `intensity`.
ShColor turnEnvironment(const ShColor& world, double degrees, double intensity);

// Loads scene.gdm.source (which must be set). A path that exists must be a GDM asset directory; anything
// else must be a built-in mesostructure name. Throws Error(Io) for a directory that is not an asset and as
// readGdmAsset; Error(InvalidInput) for a name that is neither (the message lists the built-ins), a rank
// above the stored one, or "raw" on an asset without its raw GDM. `progress` hears the steps of a bake.
// With an environment (scene.environment.source) it also opens the environment (openEnvironment: a
// built-in sky or an EXR; Error(Io) / Error(InvalidInput) as there, the message naming `env`) and bakes the
// RTV: its visibility from the raw GDM, or, for an asset without one, from a GDM baked again from the
// asset's solid (solid.obj) at the asset's dims (Error(InvalidInput) when it has neither); the signed
// distance from the asset's (or bakeGdmDistance of the solid); the albedo from its albedo volume
// (gdmVolumeAlbedo), or 0.7 grey (the renderer's) without one; with env_specular > 0 the glossy RTV too
// (bakeCompressedGdmGlossyRtv: baked in chunks into its SVD, never held uncompressed).
SceneGdm loadSceneGdm(const Scene& scene, const SceneProgress& progress = {});

}  // namespace strata
