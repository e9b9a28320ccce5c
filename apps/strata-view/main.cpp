// strata-view: the interactive viewer. Thin: it parses the command line and runs the viewer (viewer.h).
//
// Exit codes, as the `strata` CLI's (docs/cli.md, docs/viewer.md):
//   0 success, 1 command line (usage), 2 I/O (a file cannot be read or written),
//   3 invalid input (a bad material, scene or mesh), 4 runtime failure,
//   5 unsupported (no display, no OpenGL 4.5 context: run under xvfb-run).
#include "viewer.h"

#include "strata/core/error.h"
#include "strata/core/interrupt.h"
#include "strata/core/memory_budget.h"
#include "strata/core/version.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <new>
#include <sstream>

namespace {

// "WxH" -> width, height; malformed or out of [1, 8192] is a command-line error.
void parseSize(const std::string& text, int& width, int& height) {
    int w = 0, h = 0;
    char x = 0;
    std::istringstream in(text);
    if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || !in.eof() || w < 1 || h < 1 || w > 8192 || h > 8192)
        throw strata::Error(
            strata::ErrorKind::Usage,
            "--size: expected WxH with both in [1, 8192] (e.g. 1280x720), got '" + text + "'");
    width = w;
    height = h;
}

}  // namespace

int main(int argc, char** argv) {
    strata::installInterruptCleanup();  // before any thread: a signal removes half-written screenshots
    CLI::App app{
        "strata-view: interactive relief mapping, meta-relief editing and generalized displacement maps "
        "(docs/viewer.md)"};
    app.set_version_flag("--version", std::string("strata-view ") + strata::kVersion);
    app.footer(
        "Without a display, run it under a virtual one: xvfb-run -a strata-view --screenshot out.png\n"
        "Exit codes: 0 ok, 1 usage, 2 I/O, 3 invalid input, 4 runtime, 5 unsupported (e.g. no display).");

    strata::view::ViewerOptions options;
    std::string size;
    app.add_option(
        "material", options.material,
        "Material JSON, texture set directory (or its strata.json), 'shaped-fabric' (default) or a "
        "built-in pattern name");
    app.add_option("--scene", options.sceneFile,
                   "Scene JSON (docs/scenes.md): mesh, camera, light and relief settings to start from")
        ->check(CLI::ExistingFile);
    app.add_option("--mesh", options.mesh,
                   "Built-in mesh (teapot, cube, sphere, torus, cylinder, vase, patch, trunk, plane, quad) "
                   "or a mesh file");
    app.add_option("--size", size, "Window size WxH (default 1280x720)");
    app.add_option("--resolution", options.resolution,
                   "Composition size while editing, in texels (default 512; saved materials keep theirs)")
        ->check(CLI::Range(64, 4096));
    app.add_option("--screenshot", options.screenshot,
                   "Draw a few frames, save the window as this PNG and exit (works under xvfb-run)");
    app.add_option("--frames", options.frames,
                   "Frames to draw before --screenshot reads the window (default 3)")
        ->check(CLI::Range(1, 100000));
    app.add_option("--meta", options.meta,
                   "How the meta-relief reaches the shader: baked (composed on the CPU, default) or live "
                   "(its layers combined per fragment; weights change without a re-bake)")
        ->check(CLI::IsMember({"baked", "live"}));
    app.add_flag("--no-ui", options.hideUi, "Start with the panels hidden (H toggles them)");
    app.add_option("--tiling", options.tiling, "Tiles per unit of mesh uv (default: the scene's, 1)")
        ->check(CLI::PositiveNumber);
    app.add_option("--gdm", options.gdm,
                   "Show a generalized displacement map in the mesh's prism shell instead of a material: a "
                   "GDM asset directory (strata gdm bake) or a built-in mesostructure (weave, chain, grid, "
                   "scales, bark; baked on the fly), as strata render --gdm");
    app.add_option("--gdm-technique", options.gdmTechnique,
                   "With --gdm: gdm (the paper's lookup, default), refine or march")
        ->check(CLI::IsMember({"gdm", "refine", "march"}));
    app.add_option("--gdm-rank", options.gdmRank,
                   "With --gdm: the SVD terms the lookups read (default: all the asset stores), or raw");
    app.add_option("--gdm-light-frame", options.gdmLightFrame,
                   "With --gdm: the shadow lookup's light direction in texture space: tangent (the paper's, "
                   "default) or jacobian")
        ->check(CLI::IsMember({"tangent", "jacobian"}));
    app.add_option("--shell-thickness", options.shellThickness,
                   "With --gdm: the prism shell's thickness T in world units (default: H times the world "
                   "length of one tile)")
        ->check(CLI::PositiveNumber);
    app.add_option("--env", options.env.source,
                   "With --gdm: light it with an environment, a built-in sky (sky-clear, sky-overcast, "
                   "sky-sunset, studio) or an equirectangular EXR, as strata render --env");
    app.add_option("--env-rotation", options.env.rotation,
                   "With --env: degrees the environment turns about +z (towards +y), default 0; the GDM "
                   "panel turns it live");
    app.add_option("--env-intensity", options.env.intensity,
                   "With --env: its radiance's scale, >= 0, default 1; the GDM panel scales it live");
    app.add_option("--env-bounces", options.env.bounces,
                   "With --env: interreflections in the radiance transfer volume, 0..8, default 1");
    app.add_option("--env-rank", options.env.rank,
                   "With --env: the radiance transfer volume's SVD terms, 1..48, default 4 (the paper's)");
    app.add_option("--env-specular", options.env.specular,
                   "With --env: a glossy term's specular coefficient, >= 0, default 0 (none)");
    app.add_option("--env-shininess", options.env.shininess,
                   "With --env-specular: the glossy lobe's Phong exponent, 0..64, default 8");
    // The memory budget, as `strata --max-memory` (docs/cli.md): every image the viewer holds counts.
    app.add_option_function<std::string>(
           "--max-memory",
           [](const std::string& text) { strata::setMemoryBudget(strata::parseMemorySize(text)); },
           "Refuse materials and screenshots that need more memory than SIZE (e.g. 512M, 4G); default half "
           "of physical memory")
        ->type_name("SIZE");

    try {
        app.parse(argc, argv);
        if (!size.empty()) parseSize(size, options.width, options.height);
        strata::view::runViewer(options);
    } catch (const CLI::ParseError& e) {
        // --help and --version are "errors" with exit code 0 to CLI11; everything else is usage.
        const int code = app.exit(e);
        return code == 0 ? 0 : strata::exitCode(strata::ErrorKind::Usage);
    } catch (...) {
        return strata::reportCurrentException("strata-view");
    }
    return 0;
}
