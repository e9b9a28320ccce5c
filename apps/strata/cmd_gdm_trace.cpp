// strata gdm trace DIR [--eye X,Y,Z] [--target X,Y,Z] [--fov DEG] [--size WxH] [--light X,Y,Z]
//                  --output uvw|shadow|mask [--reference] [--gl] [--gdm svd|raw] [--lookup nearest|bilinear]
//                  -o F.png
//
// Renders the GDM verification scene of CONVENTIONS §8 (the unit quad, the shell box [0, 1]^2 x [0, H] above
// it) on the CPU from a GDM asset: the paper's per-pixel algorithm (emulateGdm, Sec. 3.2) on the asset's SVD
// (default) or its raw GDM, or with --reference the exact reference (renderGdmReference) on the solid mesh
// the asset stores. The output is one of §8's 16-bit PNGs: uvw (RGBA), shadow or mask (gray).
#include "cli_common.h"
#include "render_common.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gl/context.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/image/image_io.h"
#include "strata/image/srgb.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/mesh/mesh.h"
#include "strata/scene/scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;

namespace strata::cli {

namespace {

// The defaults: the view of the accuracy table in docs/gdm.md (bench_gdm_trace), 45 degrees from the
// normal at distance 1.6 from the quad's centre, eye (0.5, 0.5 - 1.6 sin 45°, 1.6 cos 45°).
constexpr const char* kDefaultEye = "0.5,-0.6314,1.1314";
constexpr const char* kDefaultTarget = "0.5,0.5,0";
constexpr double kDefaultFov = 45.0;
constexpr const char* kDefaultSize = "256x256";
constexpr const char* kDefaultLight = "0.5,-0.6,1.1";
// As `strata render`'s pictures.
constexpr int kMaxPictureSize = 8192;

struct GdmTraceOptions {
    fs::path asset;
    std::string eye = kDefaultEye;
    std::string target = kDefaultTarget;
    double fov = kDefaultFov;
    std::string size = kDefaultSize;
    std::string light = kDefaultLight;
    std::string output;
    bool reference = false;
    bool gl = false;   // the paper's algorithm in OpenGL (strata::gl::renderGdmScene) instead of on the CPU
    std::string mesh;  // --gl only: a built-in or a mesh file whose prism shell is drawn
    double tiling = 1.0;              // tiles per uv unit on --mesh
    std::optional<double> thickness;  // T in world units on --mesh; default H times a tile's world length
    std::string technique;            // --gl only: gdm (default) | refine | march
    std::string lightFrame;           // --gl only: world (default) | jacobian
    std::string gdm;                  // svd (default) | raw; empty: not given
    std::string lookup;               // nearest (default) | bilinear; empty: not given
    fs::path file;
};

enum class TraceOutput { Uvw, Shadow, Mask, Shaded };

TraceOutput parseTraceOutput(const std::string& name) {
    if (name == "uvw") return TraceOutput::Uvw;
    if (name == "shadow") return TraceOutput::Shadow;
    if (name == "mask") return TraceOutput::Mask;
    if (name == "shaded") return TraceOutput::Shaded;
    throw Error(ErrorKind::Usage,
                "gdm trace: --output must be uvw, shadow, mask or shaded, got \"" + name + "\"");
}

// Every file of the asset that exists: the trace must never overwrite one.
std::vector<fs::path> assetFiles(const fs::path& dir) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (const char* name : {kGdmAssetSidecar, "weights.f32", "eigen.f32", "occupancy.u8", "albedo.rgb8",
                             "raw.f32", "solid.obj"})
        if (fs::exists(dir / name, ec)) files.push_back(dir / name);
    return files;
}

void runGdmTrace(const GdmTraceOptions& options) {
    // The flags first, then the asset's directory: nothing is read before both are known to be good. An -o
    // that is one of the asset's files is refused as such (exit 2), before the extension check (exit 1).
    if (options.asset.empty()) throw Error(ErrorKind::Usage, "gdm trace: give the GDM asset directory DIR");
    if (options.output.empty())
        throw Error(ErrorKind::Usage,
                    "gdm trace: give --output uvw, shadow or mask (CONVENTIONS §8), or shaded");
    const TraceOutput output = parseTraceOutput(options.output);
    if (output == TraceOutput::Shaded && !options.gl)
        throw Error(ErrorKind::Usage, "gdm trace: --output shaded is drawn in OpenGL: give --gl with it");
    if (options.file.empty()) throw Error(ErrorKind::Usage, "gdm trace: give the output PNG with -o F.png");
    if (options.reference && options.gl)
        throw Error(ErrorKind::Usage,
                    "gdm trace: --reference traces the solid mesh on the CPU; --gl is for the "
                    "paper's algorithm");
    if (options.reference && (!options.gdm.empty() || !options.lookup.empty()))
        throw Error(ErrorKind::Usage,
                    "gdm trace: --reference traces the solid mesh; --gdm and --lookup are for the emulation");
    if (!options.mesh.empty() && !options.gl)
        throw Error(ErrorKind::Usage,
                    "gdm trace: --mesh draws the prism shell of a mesh in OpenGL: give --gl with it (the CPU "
                    "emulation and the reference are the flat quad's)");
    if ((options.tiling != 1.0 || options.thickness) && options.mesh.empty())
        throw Error(ErrorKind::Usage, "gdm trace: --tiling and --thickness are for --mesh");
    if (!(std::isfinite(options.tiling) && options.tiling > 0.0))
        throw Error(ErrorKind::Usage, "gdm trace: --tiling must be > 0, got " + formatNumber(options.tiling));
    if (options.thickness && !(std::isfinite(*options.thickness) && *options.thickness > 0.0))
        throw Error(ErrorKind::Usage, "gdm trace: --thickness must be > 0 world units, got " +
                                          formatNumber(*options.thickness));
    if (!options.technique.empty() && !options.gl)
        throw Error(ErrorKind::Usage, "gdm trace: --technique is the OpenGL renderer's: give --gl with it");
    if (!options.lightFrame.empty() && !options.gl)
        throw Error(ErrorKind::Usage, "gdm trace: --light-frame is the OpenGL renderer's: give --gl with it");
    if (!options.lightFrame.empty() && options.lightFrame != "tangent" && options.lightFrame != "jacobian")
        throw Error(ErrorKind::Usage, "gdm trace: --light-frame must be tangent or jacobian, got \"" +
                                          options.lightFrame + "\"");
    const std::string techniqueName = options.technique.empty() ? "gdm" : options.technique;
    if (techniqueName != "gdm" && techniqueName != "refine" && techniqueName != "march")
        throw Error(ErrorKind::Usage,
                    "gdm trace: --technique must be gdm, refine or march, got \"" + techniqueName + "\"");
    const gl::GdmTechnique technique = techniqueName == "refine"  ? gl::GdmTechnique::Refine
                                       : techniqueName == "march" ? gl::GdmTechnique::March
                                                                  : gl::GdmTechnique::Gdm;
    const std::string gdmName = options.gdm.empty() ? "svd" : options.gdm;
    if (gdmName != "svd" && gdmName != "raw")
        throw Error(ErrorKind::Usage, "gdm trace: --gdm must be svd or raw, got \"" + gdmName + "\"");
    const std::string lookupName = options.lookup.empty() ? "nearest" : options.lookup;
    if (lookupName != "nearest" && lookupName != "bilinear")
        throw Error(ErrorKind::Usage,
                    "gdm trace: --lookup must be nearest or bilinear, got \"" + lookupName + "\"");
    const GdmDirectionLookup lookup =
        lookupName == "bilinear" ? GdmDirectionLookup::Bilinear : GdmDirectionLookup::Nearest;
    const std::vector<int> size = parseSizeList(options.size, 2, "--size", "WxH (e.g. 256x256)");
    Camera camera;
    camera.eye = parseVec3(options.eye, "--eye");
    camera.target = parseVec3(options.target, "--target");
    camera.fovYDegrees = options.fov;
    const glm::dvec3 light = parseVec3(options.light, "--light");
    for (int s : size)
        if (s < 1 || s > kMaxPictureSize)
            throw Error(ErrorKind::InvalidInput, "gdm trace: --size must be in [1, " +
                                                     std::to_string(kMaxPictureSize) + "] each, got " +
                                                     options.size);
    validateCamera(camera, "gdm trace (--eye, --target, --fov)");

    std::error_code ec;
    if (!fs::is_directory(options.asset, ec))
        throw Error(ErrorKind::Io, options.asset.string() +
                                       ": no such directory (a GDM asset directory, from `strata gdm bake`)");
    if (!fs::exists(options.asset / kGdmAssetSidecar, ec))
        throw Error(ErrorKind::Io, options.asset.string() + ": not a GDM asset (it has no " +
                                       std::string(kGdmAssetSidecar) + ")");
    refuseToOverwriteInputs(options.file, assetFiles(options.asset));
    checkOutputExtension(options.file, "gdm trace: -o",
                         {ImageFormat::Png, ImageFormat::Exr, ImageFormat::Jpeg});

    const auto start = std::chrono::steady_clock::now();
    progress("reading " + options.asset.string());
    const GdmAsset asset = readGdmAsset(options.asset);
    const std::string dir = options.asset.string();
    const int width = size[0], height = size[1];
    const std::string pixels = std::to_string(width) + "x" + std::to_string(height);
    GdmSceneImages images;
    std::string what;
    // The GL path needs a context for as long as it draws; made before the asset's work starts failing late.
    std::unique_ptr<gl::HeadlessContext> context;
    std::string engine =
        options.gl ? ", OpenGL" + (options.technique.empty() ? std::string() : ", " + options.technique) : "";
    if (options.gl) context = gl::HeadlessContext::create();
    // --mesh: its prism shell instead of the quad's; framed like `strata render` unless a view is given.
    std::optional<Mesh> mesh;
    PrismShellOptions shell;
    Camera view = camera;
    if (!options.mesh.empty()) {
        Scene scene;
        scene.mesh = options.mesh;
        mesh = loadSceneMesh(scene);
        shell.tiling = glm::dvec2(options.tiling);
        shell.thickness = options.thickness;
        engine += ", on " + mesh->name;
        if (options.eye == kDefaultEye && options.target == kDefaultTarget)
            view = frameCamera(meshBounds(*mesh), double(width) / double(height), options.fov);
    }
    // OpenGL: the prism shell of the quad, or of --mesh; shaded with the asset's volumes.
    Image shaded;
    const auto drawGl = [&](const auto& gdm) {
        gl::GdmRenderer renderer;
        renderer.setGdm(gdm);
        renderer.setMesh(mesh ? *mesh : makeBuiltinMesh("quad"), shell);
        if (options.lightFrame == "jacobian") renderer.setLightFrame(GdmLightFrame::Jacobian);
        if (!mesh) renderer.setBaseEntry(false);  // §8: a ray entering the box through its bottom is a miss
        if (output == TraceOutput::Shaded || technique != gl::GdmTechnique::Gdm) {
            renderer.setVolumes(asset.occupancy, asset.albedo);
            renderer.setDistance(asset.distance);  // none in older assets: refine reads the occupancy
        }
        if (output == TraceOutput::Shaded) {
            shaded = renderer.renderShaded(view, light, width, height, lookup, technique);
            images.mask = Image(width, height, 1);
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x) images.mask.at(x, y) = shaded.at(x, y, 3);
        } else {
            images = renderer.render(view, light, width, height, lookup, technique);
        }
    };
    if (options.reference) {
        if (!asset.solid)
            throw Error(
                ErrorKind::InvalidInput,
                dir +
                    ": holds no solid.obj (baked before the asset stored its solid), which --reference "
                    "traces: bake it again with `strata gdm bake`");
        what = "exact reference, " + std::to_string(asset.solid->triangles.size()) + " triangles";
        progress("tracing the exact reference at " + pixels);
        images = renderGdmReference(*asset.solid, camera, light, width, height);
    } else if (gdmName == "raw") {
        if (!asset.raw)
            throw Error(ErrorKind::InvalidInput,
                        dir +
                            ": holds no raw GDM (raw.f32), which --gdm raw reads: bake it with --keep-raw, "
                            "or trace the SVD (--gdm svd)");
        what = "the paper's algorithm on the raw GDM, " + lookupName + " directions" + engine;
        progress("running the paper's algorithm on the raw GDM at " + pixels + engine);
        if (options.gl)
            drawGl(*asset.raw);
        else
            images = emulateGdm(*asset.raw, camera, light, width, height, lookup);
    } else {
        what = "the paper's algorithm on the rank-" + std::to_string(asset.svd.rank) + " SVD, " + lookupName +
               " directions" + engine;
        progress("running the paper's algorithm on the rank-" + std::to_string(asset.svd.rank) + " SVD at " +
                 pixels + engine);
        if (options.gl)
            drawGl(asset.svd);
        else
            images = emulateGdm(asset.svd, camera, light, width, height, lookup);
    }

    // CONVENTIONS §8: 16-bit, round(value * 65535), no dither. uvw's fourth channel is 1 on a hit and its
    // others 0 on a miss, as §8's A = 65535 / all zero. Shaded (not a §8 output): 8-bit sRGB with alpha,
    // dithered, as `strata render` writes its pictures.
    if (output == TraceOutput::Shaded)
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                for (int c = 0; c < 3; ++c)
                    shaded.at(x, y, c) =
                        float(linearToSrgb(std::clamp(double(shaded.at(x, y, c)), 0.0, 1.0)));
    const Image& picture = output == TraceOutput::Uvw      ? images.uvw
                           : output == TraceOutput::Shadow ? images.shadow
                           : output == TraceOutput::Shaded ? shaded
                                                           : images.mask;
    std::size_t hits = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) hits += images.mask.at(x, y) > 0.5f ? 1 : 0;
    PngWriteOptions png;
    png.bitDepth = output == TraceOutput::Shaded ? PngBitDepth::Eight : PngBitDepth::Sixteen;
    png.dither = output == TraceOutput::Shaded;
    if (!options.file.parent_path().empty()) fs::create_directories(options.file.parent_path());
    writeImage(options.file, picture, png);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::ostringstream summary;
    summary << asset.source << ", " << what << ", " << options.output << ", " << pixels << ", "
            << formatNumber(std::round(1000.0 * double(hits) / (double(width) * height)) / 10.0)
            << "% of the pixels hit, " << formatNumber(std::round(seconds * 10) / 10) << " s";
    std::cout << "wrote " << options.file.string() << " (" << summary.str() << ")\n";
}

}  // namespace

void addGdmTraceCommand(CLI::App& gdm) {
    auto options = std::make_shared<GdmTraceOptions>();
    CLI::App* command = gdm.add_subcommand("trace",
                                           "Render the GDM verification scene (CONVENTIONS §8) on the CPU "
                                           "from a GDM asset: the paper's algorithm, "
                                           "or the exact reference");
    command->add_option("dir", options->asset, "GDM asset directory (strata gdm bake)")->required();
    command->add_option("--eye", options->eye, "Camera position X,Y,Z")->capture_default_str();
    command->add_option("--target", options->target, "Camera target X,Y,Z")->capture_default_str();
    command->add_option("--fov", options->fov, "Vertical field of view in degrees")->capture_default_str();
    command->add_option("--size", options->size, "Picture size WxH in pixels")->capture_default_str();
    command->add_option("--light", options->light, "Point light position X,Y,Z")->capture_default_str();
    command->add_option(
        "--output", options->output,
        "What a pixel holds: uvw (RGBA), shadow or mask (gray), 16-bit (CONVENTIONS §8); shaded (--gl: 8-bit "
        "sRGB with alpha)");
    command->add_flag("--reference", options->reference,
                      "Trace the exact reference on the asset's solid mesh (solid.obj) instead of the GDM");
    command->add_option(
        "--gdm", options->gdm,
        "The GDM the paper's algorithm reads: svd (the stored rank; default) or raw (raw.f32, "
        "from a bake with --keep-raw)");
    command->add_flag("--gl", options->gl,
                      "Run the paper's algorithm in OpenGL 4.5 (a fragment shader on the quad's prism shell) "
                      "instead of on the CPU; the same pictures to float rounding");
    command->add_option(
        "--mesh", options->mesh,
        "With --gl: draw the prism shell of this mesh (a built-in name or an OBJ / glTF / OFF "
        "file) instead of the quad's; framed automatically unless --eye / --target are given");
    command->add_option("--tiling", options->tiling, "With --mesh: tiles per uv unit")->capture_default_str();
    command->add_option("--thickness", options->thickness,
                        "With --mesh: the shell's thickness T in world units (default: H times the world "
                        "length of one tile)");
    command->add_option(
        "--technique", options->technique,
        "With --gl: gdm (the paper's lookup, default), refine (sphere tracing on the asset's distance "
        "volume; without one, the occupancy near the hit) or "
        "march (the occupancy every voxel, no GDM)");
    command->add_option(
        "--light-frame", options->lightFrame,
        "With --gl: the shadow lookup's light direction in texture space, tangent (the paper's, "
        "default) or jacobian (mapped by each prism's own Jacobian)");
    command->add_option("--lookup", options->lookup,
                        "Direction lookup of the emulation: nearest (default) or bilinear");
    command->add_option("-o,--out", options->file, "Output PNG");
    command->callback([options] { runGdmTrace(*options); });
}

}  // namespace strata::cli
