// The GDM a scene draws (Scene::gdm, GdmSettings): what `strata render --gdm` and strata-view load. A
// GDM asset directory is read; a built-in mesostructure name is baked on the fly, as `strata gdm bake --meso
// NAME` bakes it with its defaults (64 x 64 x 16 voxels, 16 x 32 directions, the structure's own H, rank 8 in
// the paper's layout), keeping the raw GDM. Then the scene's rank picks what the lookups read.
#pragma once

#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/scene/scene.h"

#include <filesystem>
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
    std::string description;                    // e.g. "meso weave (baked on the fly), rank 8"
    std::vector<std::filesystem::path> inputs;  // the asset's files that were read (never to be overwritten)
};

// Loads scene.gdm.source (which must be set). A path that exists must be a GDM asset directory; anything
// else must be a built-in mesostructure name. Throws Error(Io) for a directory that is not an asset and as
// readGdmAsset; Error(InvalidInput) for a name that is neither (the message lists the built-ins), a rank
// above the stored one, or "raw" on an asset without its raw GDM. `progress` hears the steps of a bake.
SceneGdm loadSceneGdm(const Scene& scene, const SceneProgress& progress = {});

}  // namespace strata
