// strata render [SCENE.json] [-o OUT.png] [scene flags: --mesh --material --depth-map --technique ...]
// With no arguments: the main job, the teapot with the Shaped Fabric meta-relief (the meta-relief paper's
// Fig. 1(b)) at 1280x720, 2 x 2 supersampled, written to out/teapot.png.
// Shaded pictures are 8-bit sRGB PNGs (16-bit with --bit-depth 16, and always for a --depth-map render);
// uv, shadow and depth are 16-bit PNGs as CONVENTIONS §7 says.
#include "cli_common.h"
#include "render_common.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/image/image_io.h"

#include <iostream>
#include <memory>

namespace fs = std::filesystem;

namespace strata::cli {

namespace {

struct RenderOptions {
    SceneFlags scene;
    fs::path output;
    int bitDepth = 0;  // 0: 8 for shaded, 16 for the rest and for verification renders
};

void runRender(const RenderOptions& options) {
    const Scene scene = buildScene(options.scene);
    fs::path output = options.output;
    if (output.empty()) {
        const std::string stem = !options.scene.sceneFile.empty() ? options.scene.sceneFile.stem().string()
                                                                  : fs::path(scene.mesh).stem().string();
        output = fs::path("out") / (stem + ".png");
    }
    checkOutputExtension(output, "render: -o", {ImageFormat::Png, ImageFormat::Exr, ImageFormat::Jpeg});
    RenderedScene rendered = std::move(renderScene(scene).front());
    refuseToOverwriteInputs(output, rendered.inputs);
    const bool verification = !scene.depthMap.empty() || scene.picture.output != RenderOutput::Shaded;
    const int bits = options.bitDepth != 0 ? options.bitDepth : (verification ? 16 : 8);
    PngWriteOptions png;
    png.bitDepth = bits == 8 ? PngBitDepth::Eight : PngBitDepth::Sixteen;
    // Debug outputs are values, not colours: never dithered (CONVENTIONS §7).
    png.dither = scene.picture.output == RenderOutput::Shaded;
    if (!output.parent_path().empty()) fs::create_directories(output.parent_path());
    writeImage(output, rendered.image, png);
    std::cout << "wrote " << output.string() << " (" << rendered.summary << ")\n";
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto options = std::make_shared<RenderOptions>();
    CLI::App* command = app.add_subcommand(
        "render",
        "Render a relief-mapped mesh headless (OpenGL 4.5 through EGL); no arguments: the main job");
    addSceneFlags(*command, options->scene);
    command->add_option("-o,--out", options->output, "Output PNG (default out/<scene or mesh name>.png)");
    command
        ->add_option("--bit-depth", options->bitDepth, "PNG bit depth (default 8 for shaded, 16 otherwise)")
        ->check(CLI::IsMember({8, 16}));
    command->callback([options] { runRender(*options); });
}

}  // namespace strata::cli
