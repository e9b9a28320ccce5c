// A scene's material, made ready for the renderer: which of the three kinds it is (a baked relief texture,
// a live meta-relief's layers, or a dual-depth texture) and every CPU step each kind needs (loading,
// composition, the AO bakes), so that a front end only uploads it (gl::uploadSceneMaterial). `strata render`,
// `strata compare`, the viewer and the tests all make their materials through this file.
//
// The kind (sceneMaterialKind):
//   Live       scene.meta is MetaPath::Live: the layers of a material JSON (or the built-in "shaped-fabric"),
//              combined per fragment (Limberger et al. 2015, Sec. III-A);
//   DualDepth  the technique is dual-depth and the material is a dual-depth texture (Policarpo et al. 2005,
//              Sec. 4);
//   Baked      everything else: a material composed on load, a texture set, a pattern, or the verification
//              scene's depth map (loadSceneMaterial).
#pragma once

#include "strata/compose/compose.h"
#include "strata/image/image.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/occlusion/meta_relief_ao.h"
#include "strata/relief/dual_depth.h"
#include "strata/relief/relief_texture.h"
#include "strata/scene/scene.h"

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace strata {

enum class MaterialKind { Baked, Live, DualDepth };
const char* toString(MaterialKind kind);

// Which kind `scene` draws (see the top of this file). Reads nothing but the file system's view of
// scene.material (whether it is a dual-depth texture's directory).
MaterialKind sceneMaterialKind(const Scene& scene);

struct SceneMaterial {
    MaterialKind kind = MaterialKind::Baked;
    double depthScale = 0.0;  // S the render uses: scene.relief.depthScale, else the material's own

    // Baked: the texture (depth, normals, colour, AO), with its AO made fit for the render's S
    // (aoForRender), valid at aoDepthScale.
    ReliefTexture texture;
    double aoDepthScale = 0.0;

    // Live: the loaded layers with their tilings and weights, the material's composition settings, its AO
    // (nullopt: none, also when the scene's AO is off) and AO settings.
    std::vector<CompositionLayer> layers;
    ComposeParams compose;
    std::optional<MetaAoMode> liveAo;
    AoParams aoParams;
    // Live, AO Multiply / Min: each layer's own AO map (liveLayerAo), an empty image for a layer without one.
    std::vector<Image> layerAo;
    // Live, AO Exact: the AO of the composed depth (composedAoForRender), valid at composedAoDepthScale.
    Image composedAo;
    double composedAoDepthScale = 0.0;

    // DualDepth: the texture as read.
    DualDepthTexture dual;
};

// Loads, composes and bakes what `scene` draws (see the top of this file). Loader notes and composition
// warnings are appended to `notes`; `progress` (may be empty) hears a line before each long step. Throws
// like loadSceneMaterial, loadSceneLayeredMaterial, loadLayers, readDualDepth and bakeAo (Error naming the
// file or key).
SceneMaterial prepareSceneMaterial(const Scene& scene, std::vector<std::string>* notes = nullptr,
                                   const SceneProgress& progress = {});

// A live material's per-layer AO maps for MetaAoMode::Multiply and Min: layer i's depth baked at its share of
// the depth, S_i = S (w_d,i / W) t_i (metaReliefLayerAoParams), an empty image where that share is 0. Empty
// for every other mode (and nullopt). What gl::uploadLiveMaterial takes as its pre-baked layer AO.
std::vector<Image> liveLayerAo(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                               std::optional<MetaAoMode> ao, const AoParams& aoParams);

// A live material's AO for MetaAoMode::Exact: the layers composed (compose) and the composed depth's AO baked
// with aoParams, at the render's S when rescale is AoRescale::Exact, else at compose.depthScale. Returns the
// map; *aoDepthScale gets the S it is valid at.
Image composedAoForRender(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                          const AoParams& aoParams, double renderDepthScale, AoRescale rescale,
                          double* aoDepthScale, const SceneProgress& progress = {});

// Every file a render of `scene` reads: the mesh file, the depth map, the material file and what it reads (a
// texture set's maps, a material JSON's layer files), the scene file. An output must be none of these.
std::vector<std::filesystem::path> sceneInputs(const Scene& scene);

}  // namespace strata
