// `strata render` of a GDM scene (scene.gdm, docs/gdm.md): the scene's GDM in the prism shell of its mesh,
// drawn by strata::gl's GdmRenderer.
#include "cli_common.h"
#include "render_common.h"

#include "strata/core/error.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gdm/scene_gdm.h"
#include "strata/gl/context.h"
#include "strata/gl/gdm_picture.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/mesh/mesh.h"

#include <chrono>
#include <cmath>
#include <sstream>

namespace strata::cli {

std::vector<RenderedScene> renderGdmScene(const Scene& scene, const std::vector<GdmTechnique>& techniques) {
    const auto start = std::chrono::steady_clock::now();
    const auto context = gl::HeadlessContext::create();

    progress("mesh " + scene.mesh);
    const Mesh mesh = loadSceneMesh(scene);
    const SceneGdm gdm = loadSceneGdm(scene, [](const std::string& m) { progress(m); });

    gl::GdmRenderer renderer;
    const PrismShellOptions shell = gl::prepareGdmRenderer(renderer, gdm, mesh, scene);
    const PrismShell prisms = buildPrismShell(mesh, shell);

    // Framed on the shell's bounds, which hold everything the GDM can draw.
    Bounds bounds = meshBounds(mesh);
    const auto grow = glm::vec3(float(prisms.thickness));
    bounds.min -= grow;
    bounds.max += grow;
    const Camera camera = scene.camera.value_or(
        frameCamera(bounds, double(scene.picture.width) / double(scene.picture.height)));

    std::vector<RenderedScene> results;
    const std::vector<GdmTechnique> list = techniques.empty() ? std::vector{scene.gdm.technique} : techniques;
    for (GdmTechnique technique : list) {
        progress(std::string("rendering (") + toString(technique) + ")");
        RenderedScene result;
        result.image = gl::renderGdmPicture(renderer, camera, scene.lighting, scene.picture, technique);
        std::ostringstream summary;
        summary << mesh.name << ", GDM " << gdm.description << ", " << toString(technique)
                << (scene.gdm.lightFrame == GdmLightFrame::Jacobian ? ", Jacobian light" : "") << ", tiling "
                << formatNumber(scene.relief.tiling) << ", T = " << formatNumber(prisms.thickness) << ", "
                << scene.picture.width << "x" << scene.picture.height;
        if (gdm.environment && (scene.environment.rotation != 0.0 || scene.environment.intensity != 1.0))
            summary << ", environment turned " << formatNumber(scene.environment.rotation) << " degrees, x "
                    << formatNumber(scene.environment.intensity);
        if (scene.picture.output != RenderOutput::Shaded)
            summary << ", " << toString(scene.picture.output);
        else if (scene.picture.samples > 1)
            summary << ", " << scene.picture.samples << " samples (supersampled)";
        result.summary = summary.str();
        results.push_back(std::move(result));
    }
    std::vector<std::filesystem::path> inputs = gdm.inputs;
    if (std::filesystem::exists(scene.mesh)) inputs.emplace_back(scene.mesh);
    finishRendered(results, inputs, context->rendererName(), start);
    return results;
}

}  // namespace strata::cli
