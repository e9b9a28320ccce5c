// A render scene: what `strata render SCENE.json` reads and what its flags override. docs/scenes.md documents
// every key; examples/scenes/*.json are working scenes.
//
//   { "mesh": "teapot", "material": "shaped-fabric", "technique": "relief",
//     "linear_steps": 10, "binary_steps": 5, "depth_scale": 0.08, "tiling": 2,
//     "self_shadow": true, "depth_correction": true, "ao": true, "ao_rescale": "exact",
//     "camera": { "eye": [2.2, -2.4, 1.6], "target": [0, 0, 0.4], "up": [0, 0, 1], "fov": 35 },
//     "light": { "position": [3, -2, 4], "color": [1, 1, 1], "ambient": 0.25, "specular": 0.35,
//                "shininess": 48 },
//     "size": [1280, 720], "samples": 4, "output": "shaded", "background": [0.16, 0.17, 0.19] }
//
// Every key is optional; the defaults render the main job (the teapot with the Shaped Fabric meta-relief of
// the meta-relief paper's Fig. 1(b)). Parsing is strict, like materials: an unknown key, a wrong type or a
// value out of range throws Error(InvalidInput) "<file>: <key>: <what is wrong>"; a missing file throws
// Error(Io).
//
// Meshes ("mesh"): a built-in name (builtinMeshList(): teapot, cube, sphere, torus, cylinder, vase, patch,
// trunk, plane, quad) or a mesh file (.obj, .gltf, .glb). A name is a built-in unless a file of that name
// exists.
//
// Materials ("material"): in this order,
//   - an existing path: a material JSON (composed on load, docs/material.md), a texture set directory or its
//     strata.json (docs/texture-sets.md), or a dual-depth texture's directory (strata/relief/dual_depth.h:
//     its front layer as the depth, unless the technique is dual-depth, docs/dual-depth.md);
//   - "shaped-fabric": the built-in material of the main job (examples/shaped_fabric.json: base + fabric,
//     weights 1.0 / 0.3, exact AO);
//   - a built-in pattern name (patternList()), at 512^2, seed 1, with exact AO.
// "depth_map" (a depth image, d in [0, 1], 0 = top; CONVENTIONS §2) replaces the material: normals derived at
// the render's depth scale, no colour (white), no AO. This is the verification scene's input (CONVENTIONS
// §7). Relative paths are relative to the scene file.
// "gdm" (an asset directory, or a built-in mesostructure name) makes the scene a GDM render (GdmSettings):
// the mesostructure in the mesh's prism shell instead of the material; "gdm_technique", "gdm_rank" (an
// integer or "raw") and "shell_thickness" go with it, and "output" is then shaded, uvw, shadow or mask.
// "env" (a built-in sky or an equirectangular EXR, relative to the scene file) lights a GDM render with the
// environment (EnvironmentSettings), with "env_rotation", "env_intensity", "env_bounces" and "env_rank".
#pragma once

#include "strata/mesh/mesh.h"
#include "strata/relief/relief_texture.h"
#include "strata/scene/camera.h"
#include "strata/scene/material.h"
#include "strata/scene/render_settings.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace strata {

inline constexpr const char* kMainJobMaterial = "shaped-fabric";

// How a meta-relief material reaches the shader ("meta", --meta).
enum class MetaPath {
    Baked,  // composed into one relief texture on load (compose()), the paper's baked MRT
    Live,   // its layers combined per fragment (gl::uploadLiveMaterial): weights change without a re-bake
};
const char* toString(MetaPath path);
// "baked" | "live"; throws Error(InvalidInput) listing them for anything else.
MetaPath parseMetaPath(const std::string& text);

struct Scene {
    std::filesystem::path source;  // the scene file, for messages ("" for flags only)
    std::string mesh = "teapot";   // built-in name or file path (resolved against the scene file)
    int tessellation = 0;          // built-in tessellation, 0 = the built-in's default
    std::string material = kMainJobMaterial;
    std::filesystem::path depthMap;   // replaces the material when set
    MetaPath meta = MetaPath::Baked;  // a layered material's path (a texture set or pattern has no layers)
    std::optional<Camera> camera;     // nullopt: framed automatically from the mesh bounds (frameCamera)
    ReliefSettings relief;
    GdmSettings gdm;                  // a GDM render instead of a relief one when gdm.source is set
    EnvironmentSettings environment;  // a GDM render's environment lighting when environment.source is set
    Lighting lighting;
    PictureSettings picture;
};

// Parses a scene document; `source` names it in messages and resolves relative paths.
Scene parseScene(const nlohmann::json& document, const std::filesystem::path& source);
// Reads a scene file. Throws Error(Io) if unreadable, Error(InvalidInput) with line and column for bad JSON.
Scene readScene(const std::filesystem::path& path);

// A three-quarter view of `bounds` from the front-left and above, the whole box in view at this aspect.
Camera frameCamera(const Bounds& bounds, double aspect, double fovYDegrees = 30.0);

// The scene's mesh, built or loaded (strata/mesh). Throws like makeBuiltinMesh / loadMesh.
Mesh loadSceneMesh(const Scene& scene);

using SceneProgress = std::function<void(const std::string& message)>;

// The relief texture the scene renders: the material composed or read, or the depth map with derived normals
// (see the top of this file). Notes (e.g. "read RGB depth through its luminance") go to `notes`.
ReliefTexture loadSceneMaterial(const Scene& scene, std::vector<std::string>* notes = nullptr,
                                const SceneProgress& progress = {});

// The layered material behind scene.material, for MetaPath::Live: a material JSON, or the built-in
// "shaped-fabric". Throws Error(InvalidInput) naming the material for a depth map, a texture set or a
// pattern (they have no layers), and like readMaterial for a bad file.
Material loadSceneLayeredMaterial(const Scene& scene);

// The depth scale a render uses: relief.depthScale, or the texture's own.
double renderDepthScale(const Scene& scene, const ReliefTexture& texture);

// AO for a render at depth scale `renderScale` (ReliefSettings::aoRescale). Exact: the AO of the depth map
// re-baked at renderScale by the sweep baker (R = 1, M = 50) when renderScale differs from the texture's S,
// else the map as it is. Off and Paper: the map as baked (Paper is applied per fragment by the shader).
// Returns the map and, in aoDepthScale, the S it is valid at. An empty image when the texture has no AO.
Image aoForRender(const ReliefTexture& texture, double renderScale, AoRescale rescale, double* aoDepthScale);

}  // namespace strata
