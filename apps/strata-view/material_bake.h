// The CPU half of "the material changed -> the texture the renderer draws": the material's layers loaded,
// composed (paper Eq. 1, 2) and their AO baked, then the AO made to fit the render's depth scale. The
// same library calls as `strata render` (composeMaterial's steps, aoForRender), with each stage cached so
// that an edit redoes only what it changes:
//   layers       a layer is loaded (pattern generated, files read) once, while it stays in the material;
//   composition  weights, tiling, order, normal mode, AO settings: compose (into the previous buffers) and
//                the material's AO bake;
//   render AO    the render's depth scale, with AoRescale::Exact: the AO re-baked at that scale.
// Not thread-safe: one bake at a time (MaterialPipeline runs them on its worker thread).
#pragma once

#include "strata/relief/relief_texture.h"
#include "strata/scene/material.h"
#include "strata/scene/render_settings.h"
#include "strata/scene/scene.h"

#include <string>
#include <vector>

namespace strata::view {

// The viewer composes at this size while editing (`--resolution` changes it), small enough that an edit
// shows almost at once (docs/viewer.md measures it). Saved materials keep their own "resolution".
inline constexpr int kDefaultEditResolution = 512;

struct BakeRequest {
    Material material;                             // layers, weights, tiling, seeds, compose and AO settings
    int resolution = kDefaultEditResolution;       // composition size (replaces material.compose.resolution)
    double renderDepthScale = kDefaultDepthScale;  // S the render uses
    AoRescale aoRescale = AoRescale::Exact;        // Exact re-bakes the AO at renderDepthScale
    // How the material reaches the GPU (MaterialPipeline): Baked composes it here; Live uploads the loaded
    // layers (layers()) and bakes only the AO of the composed depth, for material AO "exact".
    MetaPath meta = MetaPath::Baked;
};

// Everything a bake's result depends on, as a string: equal keys give equal results.
std::string bakeKey(const BakeRequest& request);

struct BakeResult {
    ReliefTexture texture;           // depth, normal, colour (if any), AO (if the material makes one)
    double aoDepthScale = 0.0;       // S the AO map is valid at (uploadMaterial's argument)
    std::vector<std::string> notes;  // composition warnings (fractional tiling) and loader notes
    int layersLoaded = 0;            // layers loaded by this bake (0 when all came from the cache)
    bool composed = false;           // whether this bake composed (false: only the render AO changed)
    double loadSeconds = 0.0;
    double composeSeconds = 0.0;
    double aoSeconds = 0.0;  // material AO and render AO
};

class MaterialBaker {
public:
    // Throws like loadLayers, compose, metaReliefAo and bakeAo (Error naming the layer and value).
    // After a failure the caches stay valid for the next request.
    BakeResult bake(const BakeRequest& request);

    // The live path's stage: the request's layers, loaded (or taken from the cache that bake() shares),
    // with their tilings and weights and labels as bake() composes them. `report` gets layersLoaded,
    // loadSeconds and the loaders' notes. Throws like loadLayers; the cache stays valid.
    std::vector<CompositionLayer> layers(const BakeRequest& request, BakeResult& report);

private:
    // Moves the cached layers that `material` keeps into `layers` (keys beside them) and loads the rest.
    // The caller holds a KeepLayers over both vectors, which puts them back into the cache whatever happens.
    void takeLayers(const Material& material, BakeResult& result, std::vector<CompositionLayer>& layers,
                    std::vector<std::string>& keys);
    struct KeepLayers {
        MaterialBaker& baker;
        std::vector<CompositionLayer>& layers;
        std::vector<std::string>& keys;
        ~KeepLayers();
    };

    std::vector<CompositionLayer> mLayers;  // the last request's layers, loaded
    std::vector<std::string> mLayerKeys;
    std::string mCompositionKey;
    Composition mComposition;
    Image mMaterialAo;
    std::string mRenderAoKey;
    Image mRenderAo;
    double mRenderAoDepthScale = 0.0;
};

}  // namespace strata::view
