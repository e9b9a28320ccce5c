#include "render_common.h"

#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/gl/context.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/gl/scene_material.h"
#include "strata/mesh/mesh.h"

#include <chrono>
#include <cmath>
#include <sstream>

namespace fs = std::filesystem;

namespace strata::cli {

glm::dvec3 parseVec3(const std::string& text, const char* flag) {
    glm::dvec3 v;
    std::istringstream in(text);
    char comma1 = 0, comma2 = 0;
    if (!(in >> v.x >> comma1 >> v.y >> comma2 >> v.z) || comma1 != ',' || comma2 != ',' || !in.eof() ||
        !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw Error(ErrorKind::Usage,
                    std::string(flag) + ": expected X,Y,Z (three numbers), got '" + text + "'");
    return v;
}

namespace {

bool parseOnOff(const std::string& text, const char* flag) {
    if (text == "on") return true;
    if (text == "off") return false;
    throw Error(ErrorKind::Usage, std::string(flag) + ": expected on or off, got '" + text + "'");
}

std::string describe(const Scene& scene, double depthScale) {
    std::ostringstream out;
    const ReliefSettings& r = scene.relief;
    out << fs::path(scene.mesh).filename().string() << ", " << toString(r.technique);
    if (r.technique == Technique::Relief) out << " " << r.linearSteps << "+" << r.binarySteps;
    if (scene.meta == MetaPath::Live) out << ", live meta-relief";
    out << ", S = " << depthScale << ", tiling " << r.tiling << ", " << scene.picture.width << "x"
        << scene.picture.height;
    if (scene.picture.output != RenderOutput::Shaded)
        out << ", " << toString(scene.picture.output);
    else if (scene.picture.samples > 1)
        out << ", " << scene.picture.samples << " samples (supersampled)";
    return out.str();
}

}  // namespace

void addSceneFlags(CLI::App& command, SceneFlags& f) {
    command.add_option("scene", f.sceneFile, "Scene file (JSON, docs/scenes.md); flags override its keys")
        ->check(CLI::ExistingFile);
    command.add_option(
        "--mesh", f.mesh,
        "Built-in mesh (teapot, cube, sphere, torus, cylinder, vase, patch, trunk, plane, quad) or "
        "a mesh file (.obj, .gltf, .glb)");
    command.add_option("--tessellation", f.tessellation, "Tessellation of a built-in mesh")
        ->check(CLI::Range(1, 256));
    command.add_option("--material", f.material,
                       "Material JSON, texture set directory, 'shaped-fabric' or a built-in pattern name");
    command
        .add_option("--depth-map", f.depthMap,
                    "Render this depth map (d in [0, 1], 0 = top) instead of a material: the verification "
                    "scene's input (CONVENTIONS §7)")
        ->check(CLI::ExistingFile);
    command
        .add_option("--technique", f.technique,
                    "texture, normal, parallax, relief, maxmip (exact), cone (exact) or dual-depth (a "
                    "dual-depth texture)")
        ->check(CLI::IsMember({"texture", "normal", "parallax", "relief", "maxmip", "cone", "dual-depth"}));
    command
        .add_option("--linear-steps", f.linearSteps,
                    "Relief: linear search steps at normal incidence (paper: 10)")
        ->check(CLI::Range(1, 1024));
    command.add_option("--binary-steps", f.binarySteps, "Relief: binary search steps (paper: 5)")
        ->check(CLI::Range(0, 32));
    command.add_option("--depth-scale", f.depthScale,
                       "Depth of d = 1 in tile widths (default: the material's)");
    command.add_option("--tiling", f.tiling, "Tiles per unit of mesh uv");
    command.add_option("--shadows", f.shadows, "Self-shadowing: on or off")
        ->check(CLI::IsMember({"on", "off"}));
    command.add_option("--depth-correction", f.depthCorrection, "Write the relief's depth: on or off")
        ->check(CLI::IsMember({"on", "off"}));
    command.add_option("--ao", f.ao, "Texture-space AO on the ambient term: on or off")
        ->check(CLI::IsMember({"on", "off"}));
    command.add_option("--ao-rescale", f.aoRescale, "AO at another depth scale: exact, paper (Eq. 6) or off")
        ->check(CLI::IsMember({"off", "paper", "exact"}));
    command
        .add_option("--meta", f.meta,
                    "A material JSON's layers: baked (composed on load) or live (combined per fragment)")
        ->check(CLI::IsMember({"baked", "live"}));
    command.add_option("--eye", f.eye, "Camera position X,Y,Z (default: framed from the mesh's bounds)");
    command.add_option("--target", f.target, "Camera target X,Y,Z");
    command.add_option("--up", f.up, "Camera up X,Y,Z (default 0,0,1)");
    command.add_option("--fov", f.fov, "Vertical field of view in degrees");
    command.add_option("--size", f.size, "Picture size WxH in pixels (default 1280x720)");
    command
        .add_option(
            "--samples", f.samples,
            "Samples per pixel of shaded pictures: a k x k supersampling grid, k = round(sqrt(N)) (1 = none)")
        ->check(CLI::Range(1, 16));
    command.add_option("--light", f.light, "Point light position X,Y,Z");
    command
        .add_option(
            "--output", f.output,
            "What a pixel holds: shaded, uv, shadow or depth (CONVENTIONS §7); with --gdm shaded, uvw, "
            "shadow or mask (§8)")
        ->check(CLI::IsMember({"shaded", "uv", "shadow", "depth", "uvw", "mask"}));
    command.add_option(
        "--gdm", f.gdm,
        "Draw a generalized displacement map in the mesh's prism shell instead of a relief "
        "material: a GDM asset directory (strata gdm bake) or a built-in mesostructure (weave, "
        "chain, grid, scales, bark; baked on the fly)");
    command
        .add_option(
            "--gdm-technique", f.gdmTechnique,
            "With --gdm: gdm (the paper's lookup, default), refine (exact steps near its hit) or march "
            "(the occupancy every voxel)")
        ->check(CLI::IsMember({"gdm", "refine", "march"}));
    command.add_option("--gdm-rank", f.gdmRank,
                       "With --gdm: the SVD terms the lookups read (default: all the asset stores, 8 for a "
                       "built-in), or raw (the raw GDM)");
    command
        .add_option("--gdm-light-frame", f.gdmLightFrame,
                    "With --gdm: the shadow lookup's light direction in texture space: tangent (in the "
                    "surface's frame, "
                    "the paper's) or "
                    "jacobian (mapped by each prism's own Jacobian)")
        ->check(CLI::IsMember({"tangent", "jacobian"}));
    command.add_option("--shell-thickness", f.shellThickness,
                       "With --gdm: the prism shell's thickness T in world units (default: H times the world "
                       "length of one tile)");
    command.add_option("--env", f.env.source,
                       "With --gdm: light it with an environment, a built-in sky (sky-clear, sky-overcast, "
                       "sky-sunset, studio) or an equirectangular EXR (CONVENTIONS §9), by bi-scale radiance "
                       "transfer (docs/gdm.md); it replaces the ambient term");
    command.add_option("--env-rotation", f.env.rotation,
                       "With --env: degrees the environment turns about +z (towards +y), default 0");
    command.add_option("--env-intensity", f.env.intensity,
                       "With --env: its radiance's scale, >= 0, default 1");
    command.add_option("--env-bounces", f.env.bounces,
                       "With --env: interreflections in the radiance transfer volume, 0..8, default 1");
    command.add_option(
        "--env-rank", f.env.rank,
        "With --env: the radiance transfer volume's SVD terms, 1..48, default 4 (the paper's)");
    command.add_option("--env-specular", f.env.specular,
                       "With --env: a glossy term's specular coefficient, >= 0, default 0 (none); bakes the "
                       "view-dependent radiance transfer volume");
    command.add_option("--env-shininess", f.env.shininess,
                       "With --env-specular: the glossy lobe's Phong exponent, 0..64, default 8");
}

namespace {

// "tiling: must be in (0, 4096], got 1e+12" -> "--tiling: must be ...": the validators name the scene key;
// a flag's error names the flag (width and height come from --size).
std::string flagMessage(const std::string& message) {
    const std::size_t colon = message.find(':');
    if (colon == std::string::npos) return message;
    std::string key = message.substr(0, colon);
    if (key.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") != std::string::npos) return message;
    if (key == "width" || key == "height") key = "size";
    for (char& c : key)
        if (c == '_') c = '-';
    return "--" + key + message.substr(colon);
}

}  // namespace

Scene buildScene(const SceneFlags& f) {
    Scene scene = f.sceneFile.empty() ? Scene{} : readScene(f.sceneFile);
    if (!f.mesh.empty()) scene.mesh = f.mesh;
    if (f.tessellation) scene.tessellation = *f.tessellation;
    if (!f.material.empty()) scene.material = f.material;
    if (!f.depthMap.empty()) scene.depthMap = f.depthMap;
    ReliefSettings& r = scene.relief;
    if (!f.technique.empty()) r.technique = parseTechnique(f.technique);
    if (f.linearSteps) r.linearSteps = *f.linearSteps;
    if (f.binarySteps) r.binarySteps = *f.binarySteps;
    if (f.depthScale) r.depthScale = *f.depthScale;
    if (f.tiling) r.tiling = *f.tiling;
    if (!f.shadows.empty()) r.selfShadow = parseOnOff(f.shadows, "--shadows");
    if (!f.depthCorrection.empty()) r.depthCorrection = parseOnOff(f.depthCorrection, "--depth-correction");
    if (!f.ao.empty()) r.ao = parseOnOff(f.ao, "--ao");
    if (!f.aoRescale.empty()) r.aoRescale = parseAoRescale(f.aoRescale);
    if (!f.meta.empty()) scene.meta = parseMetaPath(f.meta);

    const bool cameraFlags = !f.eye.empty() || !f.target.empty() || !f.up.empty() || f.fov;
    if (cameraFlags) {
        Camera camera = scene.camera.value_or(Camera{});
        if (!scene.camera && (f.eye.empty() || f.target.empty()))
            throw Error(ErrorKind::Usage, "--eye and --target go together (or come from the scene file)");
        if (!f.eye.empty()) camera.eye = parseVec3(f.eye, "--eye");
        if (!f.target.empty()) camera.target = parseVec3(f.target, "--target");
        if (!f.up.empty()) camera.up = parseVec3(f.up, "--up");
        if (f.fov) camera.fovYDegrees = *f.fov;
        scene.camera = camera;
    }
    if (scene.camera) validateCamera(*scene.camera, "camera");

    PictureSettings& p = scene.picture;
    if (!f.size.empty()) {
        const std::vector<int> size = parseSizeList(f.size, 2, "--size", "WxH (e.g. 1280x720)");
        p.width = size[0];
        p.height = size[1];
    }
    if (!f.depthMap.empty() && !f.samples) p.samples = 1;
    if (f.samples) p.samples = *f.samples;
    if (!f.light.empty()) scene.lighting.lightPosition = parseVec3(f.light, "--light");
    if (!f.output.empty()) p.output = parseRenderOutput(f.output);
    GdmSettings& gdm = scene.gdm;
    if (!f.gdm.empty()) gdm.source = f.gdm;
    if (!f.gdmTechnique.empty()) gdm.technique = parseGdmTechnique(f.gdmTechnique);
    if (!f.gdmRank.empty()) {
        try {
            gdm.rank = parseGdmRank(f.gdmRank);
        } catch (const Error& e) {
            throw Error(ErrorKind::Usage, std::string("--gdm-rank: ") + e.what());
        }
    }
    if (f.shellThickness) gdm.shellThickness = *f.shellThickness;
    if (!f.gdmLightFrame.empty()) gdm.lightFrame = parseGdmLightFrame(f.gdmLightFrame);
    if (gdm.source.empty() &&
        (!f.gdmTechnique.empty() || !f.gdmRank.empty() || f.shellThickness || !f.gdmLightFrame.empty()))
        throw Error(
            ErrorKind::Usage,
            "--gdm-technique, --gdm-rank, --shell-thickness and --gdm-light-frame are for a GDM render: "
            "give --gdm");
    EnvironmentSettings& env = scene.environment;
    applyEnvironmentFlags(f.env, env, !gdm.source.empty());
    if (!gdm.source.empty() && (!f.material.empty() || !scene.depthMap.empty()))
        throw Error(
            ErrorKind::Usage,
            "--gdm draws a mesostructure instead of a material: give no --material or --depth-map with "
            "it");
    // readScene validated the file's values, so a value out of range now came from a flag: a usage error
    // that names the flag, not the scene key.
    try {
        validate(r);
        validate(scene.lighting);
        validate(p);
        validate(gdm, p);
        validate(env, gdm);
    } catch (const Error& e) {
        if (e.kind() != ErrorKind::InvalidInput) throw;
        throw Error(ErrorKind::Usage, flagMessage(e.what()));
    }
    return scene;
}

std::vector<RenderedScene> renderScene(const Scene& scene, const std::vector<Technique>& techniques) {
    if (!scene.gdm.source.empty()) {
        if (!techniques.empty())
            throw Error(ErrorKind::Usage, "a GDM scene has no relief techniques to compare (give no --gdm)");
        return renderGdmScene(scene);
    }
    const auto start = std::chrono::steady_clock::now();
    // The context first: without one nothing else is worth doing.
    const auto context = gl::HeadlessContext::create();

    progress("mesh " + scene.mesh);
    const Mesh mesh = loadSceneMesh(scene);
    std::vector<std::string> notes;
    gl::ReliefRenderer renderer;
    const gl::GpuMesh gpuMesh = gl::uploadMesh(mesh);
    const SceneMaterial material =
        prepareSceneMaterial(scene, &notes, [](const std::string& m) { progress(m); });
    for (const auto& text : notes) note(text);
    const double depthScale = material.depthScale;
    const gl::GpuMaterial gpuMaterial = gl::uploadSceneMaterial(material);

    gl::RenderRequest request;
    request.objects.push_back({&gpuMesh, glm::dmat4(1.0), &gpuMaterial, glm::dvec3(0.8)});
    request.relief = scene.relief;
    request.relief.depthScale = depthScale;
    request.lighting = scene.lighting;
    request.picture = scene.picture;
    request.camera = scene.camera.value_or(
        frameCamera(meshBounds(mesh), static_cast<double>(scene.picture.width) / scene.picture.height));

    std::vector<RenderedScene> results;
    const std::vector<Technique> list = techniques.empty() ? std::vector{scene.relief.technique} : techniques;
    for (Technique technique : list) {
        request.relief.technique = technique;
        Scene described = scene;
        described.relief.technique = technique;
        progress(std::string("rendering (") + toString(technique) + ")");
        RenderedScene result;
        result.image = renderer.render(request);
        result.summary = describe(described, depthScale);
        results.push_back(std::move(result));
    }

    finishRendered(results, sceneInputs(scene), context->rendererName(), start);
    return results;
}

void finishRendered(std::vector<RenderedScene>& results, const std::vector<fs::path>& inputs,
                    const std::string& rendererName, std::chrono::steady_clock::time_point start) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (RenderedScene& result : results) {
        result.inputs = inputs;
        result.summary += ", " + rendererName + ", " + formatNumber(std::round(seconds * 10) / 10) + " s";
    }
}

}  // namespace strata::cli
