#include "strata/gl/gdm_picture.h"

#include "strata/core/error.h"
#include "strata/gdm/macro_transfer.h"
#include "strata/image/srgb.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

namespace strata::gl {

namespace {

// k of the k x k grid, limited so that the supersampled picture fits the driver's renderbuffers (as the
// relief renderer's).
int supersamplingFactor(const PictureSettings& picture) {
    int factor = std::max(1, int(std::lround(std::sqrt(double(picture.samples)))));
    GLint maxSize = 4096;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    while (factor > 1 && std::max(picture.width, picture.height) * factor > maxSize) --factor;
    return factor;
}

}  // namespace

PrismShellOptions prepareGdmRenderer(GdmRenderer& renderer, const SceneGdm& gdm, const Mesh& mesh,
                                     const Scene& scene) {
    if (gdm.raw)
        renderer.setGdm(*gdm.asset.raw);
    else
        renderer.setGdm(gdm.svd);
    PrismShellOptions shell;
    shell.height = gdm.asset.svd.height;
    shell.tiling = glm::dvec2(scene.relief.tiling);
    shell.thickness = scene.gdm.shellThickness;
    renderer.setMesh(mesh, shell);
    renderer.setVolumes(gdm.asset.occupancy, gdm.asset.albedo);
    if (!gdm.asset.distance.empty()) renderer.setDistance(gdm.asset.distance);
    renderer.setLightFrame(scene.gdm.lightFrame);
    renderer.setLighting(scene.lighting);
    if (gdm.rtv && gdm.environment) {
        renderer.setRtv(*gdm.rtv);
        if (gdm.glossy) renderer.setGlossyRtv(*gdm.glossy, gdm.glossySpecular);
        MacroTransferOptions macro;
        macro.shellThickness = buildPrismShell(mesh, shell).thickness;
        renderer.setMacroTransfer(bakeMacroTransfer(mesh, macro));
        renderer.setEnvironment(*gdm.environment);
    }
    return shell;
}

Image renderGdmPicture(GdmRenderer& renderer, const Camera& camera, const Lighting& lighting,
                       const PictureSettings& picture, GdmTechnique technique) {
    validate(picture);
    if (std::find(std::begin(kGdmOutputs), std::end(kGdmOutputs), picture.output) == std::end(kGdmOutputs))
        throw Error(ErrorKind::InvalidInput,
                    std::string("GDM picture: output ") + toString(picture.output) +
                        " is a relief output (a GDM render draws shaded, uvw, shadow "
                        "or mask)");
    if (picture.output != RenderOutput::Shaded) {
        GdmSceneImages images = renderer.render(camera, lighting.lightPosition, picture.width, picture.height,
                                                GdmDirectionLookup::Nearest, technique);
        return picture.output == RenderOutput::Uvw      ? std::move(images.uvw)
               : picture.output == RenderOutput::Shadow ? std::move(images.shadow)
                                                        : std::move(images.mask);
    }
    const int factor = supersamplingFactor(picture);
    const Image shaded =
        renderer.renderShaded(camera, lighting.lightPosition, picture.width * factor, picture.height * factor,
                              GdmDirectionLookup::Nearest, technique);
    // Linear colour with coverage in alpha: composited over the background in linear, then box-filtered.
    glm::dvec3 background;
    for (int c = 0; c < 3; ++c) background[c] = srgbToLinear(picture.background[c]);
    const double weight = 1.0 / double(factor * factor);
    Image out = Image::uninitialized(picture.width, picture.height, 3);
    for (int y = 0; y < picture.height; ++y)
        for (int x = 0; x < picture.width; ++x)
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0;
                for (int j = 0; j < factor; ++j)
                    for (int i = 0; i < factor; ++i) {
                        const int sx = x * factor + i, sy = y * factor + j;
                        const double alpha = shaded.at(sx, sy, 3);
                        sum += double(shaded.at(sx, sy, c)) + (1.0 - alpha) * background[c];
                    }
                out.at(x, y, c) = float(linearToSrgb(std::clamp(sum * weight, 0.0, 1.0)));
            }
    return out;
}

}  // namespace strata::gl
