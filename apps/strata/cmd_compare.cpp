// strata compare [SCENE.json] [-o OUT.png] [scene flags]
// The same view rendered with normal, parallax and relief mapping, side by side (the relief-mapping paper's
// Fig. 19). Default: the `plane` mesh with the stone-bricks relief, seen at a grazing angle.
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

struct CompareOptions {
    SceneFlags scene;
    fs::path output = "out/compare.png";
};

// The gap between panels, in pixels, in the background colour.
constexpr int kGap = 6;

void runCompare(CompareOptions options) {
    checkOutputExtension(options.output, "compare: -o",
                         {ImageFormat::Png, ImageFormat::Exr, ImageFormat::Jpeg});
    SceneFlags& f = options.scene;
    if (f.sceneFile.empty()) {
        // The paper's Fig. 19 setting: one polygon, a relief with sharp and smooth features, a low view.
        if (f.mesh.empty()) f.mesh = "plane";
        if (f.material.empty()) f.material = "stone-bricks";
        if (f.eye.empty() && f.target.empty()) {
            f.eye = "0.15,-1.55,0.55";
            f.target = "0,-0.1,0";
        }
        if (!f.fov) f.fov = 40.0;
        if (f.size.empty()) f.size = "480x400";
        if (!f.tiling) f.tiling = 2.0;
        if (!f.depthScale) f.depthScale = 0.06;
        if (f.light.empty()) f.light = "1.2,1.6,1.2";
    }
    if (!f.technique.empty()) throw Error(ErrorKind::Usage, "compare: --technique makes no sense here");
    const Scene scene = buildScene(f);
    const std::vector<Technique> techniques{Technique::Normal, Technique::Parallax, Technique::Relief};
    std::vector<RenderedScene> panels = renderScene(scene, techniques);
    refuseToOverwriteInputs(options.output, panels.front().inputs);

    const int w = scene.picture.width, h = scene.picture.height;
    const int channels = panels.front().image.channels();
    Image sheet(3 * w + 2 * kGap, h, channels, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < sheet.width(); ++x)
            for (int c = 0; c < channels; ++c)
                sheet.at(x, y, c) = static_cast<float>(scene.picture.background[c]);
    for (int i = 0; i < 3; ++i)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < channels; ++c)
                    sheet.at(i * (w + kGap) + x, y, c) = panels[i].image.at(x, y, c);
    if (!options.output.parent_path().empty()) fs::create_directories(options.output.parent_path());
    PngWriteOptions png;
    png.bitDepth = PngBitDepth::Eight;
    writeImage(options.output, sheet, png);
    std::cout << "wrote " << options.output.string() << " (normal | parallax | relief; "
              << panels.back().summary << ")\n";
}

}  // namespace

void addCompareCommand(CLI::App& app) {
    auto options = std::make_shared<CompareOptions>();
    CLI::App* command = app.add_subcommand(
        "compare", "Normal, parallax and relief mapping of the same view, side by side (paper Fig. 19)");
    addSceneFlags(*command, options->scene);
    command->add_option("-o,--out", options->output, "Output PNG")->capture_default_str();
    command->callback([options] { runCompare(*options); });
}

}  // namespace strata::cli
