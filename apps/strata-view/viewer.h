// strata-view: the interactive viewer. A GLFW window with an OpenGL 4.5 core context, the relief renderer
// of `strata render` (gl::ReliefRenderer::draw into the window's framebuffer) and Dear ImGui panels on
// top; or, with a GDM (--gdm, a scene's "gdm"), the GDM renderer of `strata render --gdm`, its pictures drawn
// offscreen on a worker thread and shown in the window (gdm_view.h). docs/viewer.md describes the panels and
// controls.
#pragma once

#include "material_bake.h"

#include <filesystem>
#include <optional>
#include <string>

namespace strata::view {

// Frames drawn before --screenshot reads the window back: the first builds the shader programs and lets
// ImGui lay its windows out; by the third everything is in place.
inline constexpr int kScreenshotFrames = 3;

struct ViewerOptions {
    std::string material;             // a material JSON, a texture set, or a built-in name; "" = the scene's
    std::filesystem::path sceneFile;  // optional scene JSON (docs/scenes.md) for mesh, camera, light, relief
    std::string mesh;                 // a built-in mesh name or a mesh file; "" = the scene's (teapot)
    int width = 1280;                 // window size in screen coordinates
    int height = 720;
    int resolution = kDefaultEditResolution;  // composition size while editing
    std::filesystem::path screenshot;         // set: draw `frames` frames, save the window as PNG, exit
    int frames = kScreenshotFrames;
    bool hideUi = false;  // start with the panels hidden (H toggles them)
    std::string meta;     // "live" | "baked": how the meta-relief reaches the shader; "" = the scene's
    // A GDM instead of a material (as `strata render --gdm`): an asset directory or a built-in
    // mesostructure name; "" = the scene's "gdm" (none: a relief material).
    std::string gdm;
    std::string gdmTechnique;              // "gdm" | "refine" | "march"; "" = the scene's
    std::string gdmRank;                   // "K" | "raw"; "" = the scene's (the stored rank)
    std::string gdmLightFrame;             // "tangent" | "jacobian"; "" = the scene's (tangent)
    std::optional<double> shellThickness;  // T, world units (> 0); unset = the scene's (H x tile length)
    std::optional<double> tiling;          // tiles per unit of mesh uv (> 0); unset = the scene's
    // The GDM's environment lighting (as `strata render --env`, EnvironmentSettings): a built-in sky or an
    // equirectangular EXR; "" = the scene's "env" (none: the ambient term). Unset numbers: the scene's.
    // The rotation (the panel turns it live) and intensity (the panel scales it live), the RTV's bounces and
    // rank and the glossy term's specular and shininess (baked at start).
    EnvironmentFlags env;
};

// Runs the viewer until its window is closed (or, with a screenshot, until it is written).
// Throws Error: Io or InvalidInput for the material, GDM, environment, mesh or scene (before any window
// opens), Usage for a GDM with a material or --meta, GDM or environment settings without a GDM, or an
// environment setting out of range (naming the flag), Unsupported
// when there is no display or no OpenGL 4.5 core context (with a hint to use xvfb-run), Io when the
// screenshot cannot be written, Runtime for a GL failure.
void runViewer(const ViewerOptions& options);

}  // namespace strata::view
