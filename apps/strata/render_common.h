// What `strata render` and `strata compare` share: the scene flags, and rendering a scene headless; the
// vector flags' parser is `strata gdm trace`'s too.
#pragma once

#include "strata/image/image.h"
#include "strata/scene/scene.h"

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata::cli {

// Every scene key as a flag (docs/scenes.md); a flag given overrides the scene file.
struct SceneFlags {
    std::filesystem::path sceneFile;
    std::string mesh;
    std::optional<int> tessellation;
    std::string material;
    std::filesystem::path depthMap;
    std::string technique;
    std::optional<int> linearSteps;
    std::optional<int> binarySteps;
    std::optional<double> depthScale;
    std::optional<double> tiling;
    std::string shadows;          // on | off
    std::string depthCorrection;  // on | off
    std::string ao;               // on | off
    std::string aoRescale;
    std::string meta;             // baked | live
    std::string eye, target, up;  // "X,Y,Z"
    std::optional<double> fov;
    std::string size;  // "WxH"
    std::optional<int> samples;
    std::string light;  // "X,Y,Z"
    std::string output;
    // A GDM render (GdmSettings): the asset or built-in, and its technique, rank and shell thickness.
    std::string gdm;
    std::string gdmTechnique;
    std::string gdmRank;  // K or raw
    std::optional<double> shellThickness;
    std::string gdmLightFrame;  // world | jacobian
    // Environment lighting of a GDM render (EnvironmentSettings).
    EnvironmentFlags env;
};

// A vector flag such as --eye 0.5,-1,1: three finite numbers separated by commas. Throws Error(Usage)
// "<flag>: expected X,Y,Z (three numbers), got '<text>'" otherwise.
glm::dvec3 parseVec3(const std::string& text, const char* flag);

// Adds the flags to `command` (and the optional positional SCENE.json).
void addSceneFlags(CLI::App& command, SceneFlags& flags);

// The scene: the file's (or the defaults), then the flags. A depth-map render is a verification render
// (CONVENTIONS §7): unless --samples is given it uses 1 sample. Throws Error(Usage) for a malformed
// vector or size flag, Error(InvalidInput) for a value out of range.
Scene buildScene(const SceneFlags& flags);

struct RenderedScene {
    Image image;                                // RenderOutput's layout (render_settings.h)
    std::vector<std::filesystem::path> inputs;  // files the render read (never to be overwritten)
    std::string summary;                        // e.g. "teapot, relief 10+5, S = 0.08, 1280x720, 4x MSAA"
};

// Loads the mesh and material (or the GDM, for a GDM render: renderGdmScene), makes a headless GL context and
// renders `scene`. `techniques`: when not
// empty, renders once per technique (same everything else) and returns the pictures in that order.
std::vector<RenderedScene> renderScene(const Scene& scene, const std::vector<Technique>& techniques = {});

// Gives every picture its inputs and ends its summary with the renderer and the seconds since `start`.
void finishRendered(std::vector<RenderedScene>& results, const std::vector<std::filesystem::path>& inputs,
                    const std::string& rendererName, std::chrono::steady_clock::time_point start);

// A GDM render (scene.gdm.source set, render_gdm.cpp): the scene's GDM (loadSceneGdm) in the prism shell of
// its mesh, one picture per technique in `techniques` (the scene's own when empty).
std::vector<RenderedScene> renderGdmScene(const Scene& scene,
                                          const std::vector<GdmTechnique>& techniques = {});

}  // namespace strata::cli
