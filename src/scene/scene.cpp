#include "strata/scene/scene.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/mesh/mesh_loader.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/relief/dual_depth.h"
#include "strata/relief/patterns.h"
#include "strata/relief/texture_set.h"
#include "strata/scene/material.h"

#include "core/json_reader.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata {

namespace {

using ObjectReader = detail::JsonObjectReader;

// The main job's material, examples/shaped_fabric.json, built in so that `strata render` needs no files.
constexpr const char* kShapedFabricJson = R"({
  "name": "Shaped Fabric",
  "resolution": 1024, "depth_scale": 0.08, "normals": "paper", "color_from": 1,
  "layers": [
    { "pattern": "base",   "size": 1024, "seed": 1, "tiling": 1.0, "weight_depth": 1.0, "weight_normal": 1.0 },
    { "pattern": "fabric", "size": 512,  "seed": 1, "tiling": 8.0, "weight_depth": 0.3, "weight_normal": 0.3 }
  ]
})";

std::optional<glm::dvec3> readVec3(ObjectReader& reader, const std::string& key) {
    const json* value = reader.array(key);
    if (!value) return std::nullopt;
    if (value->size() != 3) reader.fail(reader.keyPath(key), "must be an array of 3 numbers");
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i) {
        const json& element = (*value)[static_cast<std::size_t>(i)];
        if (!element.is_number() || !std::isfinite(element.get<double>()))
            reader.fail(reader.keyPath(key), "must be an array of 3 finite numbers");
        v[i] = element.get<double>();
    }
    return v;
}

template <typename Parse>
auto readName(ObjectReader& reader, const std::string& key, Parse parse)
    -> std::optional<decltype(parse(""))> {
    const auto text = reader.string(key);
    if (!text) return std::nullopt;
    try {
        return parse(*text);
    } catch (const Error& e) {
        reader.fail(reader.keyPath(key), e.what());
    }
}

fs::path resolve(const fs::path& base, const std::string& path) {
    const fs::path p(path);
    return p.is_absolute() || base.empty() ? p : base / p;
}

}  // namespace

Scene parseScene(const json& document, const fs::path& source) {
    const std::string file = source.empty() ? std::string("scene") : source.string();
    const fs::path baseDir = source.empty() ? fs::path() : source.parent_path();
    ObjectReader reader(document, "", file);
    Scene scene;
    scene.source = source;

    if (const auto mesh = reader.string("mesh")) {
        if (mesh->empty()) reader.fail("mesh", "must not be empty");
        const fs::path asFile = resolve(baseDir, *mesh);
        scene.mesh = fs::exists(asFile) ? asFile.string() : *mesh;
    }
    if (const auto n = reader.integer("tessellation", 1, 256)) scene.tessellation = static_cast<int>(*n);
    if (const auto material = reader.string("material")) {
        if (material->empty()) reader.fail("material", "must not be empty");
        const fs::path asFile = resolve(baseDir, *material);
        scene.material = fs::exists(asFile) ? asFile.string() : *material;
    }
    if (const auto depthMap = reader.string("depth_map")) {
        scene.depthMap = resolve(baseDir, *depthMap);
        if (!fs::exists(scene.depthMap))
            throw Error(ErrorKind::Io, file + ": depth_map: no such file: " + scene.depthMap.string());
    }

    ReliefSettings& relief = scene.relief;
    if (const auto t = readName(reader, "technique", parseTechnique)) relief.technique = *t;
    if (const auto n = reader.integer("linear_steps", 1, 1024)) relief.linearSteps = static_cast<int>(*n);
    if (const auto n = reader.integer("binary_steps", 0, 32)) relief.binarySteps = static_cast<int>(*n);
    if (const auto s = reader.number("depth_scale")) relief.depthScale = *s;
    if (const auto t = reader.number("tiling")) relief.tiling = *t;
    if (const auto b = reader.boolean("self_shadow")) relief.selfShadow = *b;
    if (const auto b = reader.boolean("depth_correction")) relief.depthCorrection = *b;
    if (const auto b = reader.boolean("ao")) relief.ao = *b;
    if (const auto r = readName(reader, "ao_rescale", parseAoRescale)) relief.aoRescale = *r;
    if (const auto m = readName(reader, "meta", parseMetaPath)) scene.meta = *m;

    GdmSettings& gdm = scene.gdm;
    if (const auto gdmSource = reader.string("gdm")) {
        if (gdmSource->empty()) reader.fail("gdm", "must not be empty");
        const fs::path asFile = resolve(baseDir, *gdmSource);
        gdm.source = fs::exists(asFile) ? asFile.string() : *gdmSource;
    }
    if (const auto t = readName(reader, "gdm_technique", parseGdmTechnique)) gdm.technique = *t;
    if (reader.has("gdm_rank")) {
        if (document["gdm_rank"].is_number()) {
            if (const auto k = reader.integer("gdm_rank", 1, 1 << 20)) gdm.rank = static_cast<int>(*k);
        } else if (const auto r = readName(reader, "gdm_rank", parseGdmRank)) {
            gdm.rank = *r;
        }
    }
    if (const auto t = reader.number("shell_thickness")) gdm.shellThickness = *t;
    if (const auto f = readName(reader, "gdm_light_frame", parseGdmLightFrame)) gdm.lightFrame = *f;

    EnvironmentSettings& environment = scene.environment;
    if (const auto env = reader.string("env")) {
        if (env->empty()) reader.fail("env", "must not be empty");
        const fs::path asFile = resolve(baseDir, *env);
        environment.source = fs::exists(asFile) ? asFile.string() : *env;
    }
    if (const auto r = reader.number("env_rotation")) environment.rotation = *r;
    if (const auto i = reader.number("env_intensity")) environment.intensity = *i;
    if (const auto n = reader.integer("env_bounces", 0, 8)) environment.bounces = static_cast<int>(*n);
    if (const auto n = reader.integer("env_rank", 1, 48)) environment.rank = static_cast<int>(*n);
    if (const auto v = reader.number("env_specular")) environment.specular = *v;
    if (const auto v = reader.number("env_shininess")) environment.shininess = *v;

    if (const json* cameraJson = reader.object("camera")) {
        ObjectReader cameraReader(*cameraJson, "camera", file);
        Camera camera;
        if (const auto v = readVec3(cameraReader, "eye")) camera.eye = *v;
        if (const auto v = readVec3(cameraReader, "target")) camera.target = *v;
        if (const auto v = readVec3(cameraReader, "up")) camera.up = *v;
        if (const auto f = cameraReader.number("fov")) camera.fovYDegrees = *f;
        cameraReader.rejectUnknown();
        try {
            validateCamera(camera);
        } catch (const Error& e) {
            throw Error(ErrorKind::InvalidInput, file + ": " + e.what());
        }
        scene.camera = camera;
    }

    Lighting& lighting = scene.lighting;
    if (const json* lightJson = reader.object("light")) {
        ObjectReader lightReader(*lightJson, "light", file);
        if (const auto v = readVec3(lightReader, "position")) lighting.lightPosition = *v;
        if (const auto v = readVec3(lightReader, "color")) lighting.lightColor = *v;
        if (const auto a = lightReader.number("ambient")) lighting.ambient = *a;
        if (const auto s = lightReader.number("specular")) lighting.specular = *s;
        if (const auto s = lightReader.number("shininess")) lighting.shininess = *s;
        lightReader.rejectUnknown();
    }

    PictureSettings& picture = scene.picture;
    if (const json* size = reader.array("size")) {
        if (size->size() != 2 || !(*size)[0].is_number_integer() || !(*size)[1].is_number_integer())
            reader.fail("size", "must be [width, height] in pixels");
        picture.width = (*size)[0].get<int>();
        picture.height = (*size)[1].get<int>();
    }
    if (const auto n = reader.integer("samples", 1, 16)) picture.samples = static_cast<int>(*n);
    if (const auto o = readName(reader, "output", parseRenderOutput)) picture.output = *o;
    if (const auto v = readVec3(reader, "background")) picture.background = *v;
    reader.rejectUnknown({"name", "description"});

    // Ranges, with the file named (the settings' own messages name the key).
    try {
        validate(relief);
        validate(lighting);
        validate(picture);
        validate(gdm, picture);
        validate(environment, gdm);
    } catch (const Error& e) {
        throw Error(ErrorKind::InvalidInput, file + ": " + e.what());
    }
    return scene;
}

Scene readScene(const fs::path& path) {
    return parseScene(detail::readJsonFile(path), path);
}

Camera frameCamera(const Bounds& bounds, double aspect, double fovYDegrees) {
    const glm::dvec3 lo(bounds.min), hi(bounds.max);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
    // From the front (-y), a little to the right (+x) and above: a three-quarter view in which +x (the
    // teapot's spout) points right.
    Camera camera;
    camera.target = centre;
    camera.up = {0.0, 0.0, 1.0};
    camera.fovYDegrees = fovYDegrees;
    const glm::dvec3 direction = glm::normalize(glm::dvec3(0.55, -1.0, 0.6));
    const double tanY = std::tan(glm::radians(fovYDegrees) * 0.5);
    const double tanX = tanY * aspect;
    // The nearest distance at which all eight corners of the box lie within 97 % of the picture's half-
    // extents (bisection: the projected extent shrinks monotonically with distance beyond the box).
    const auto fits = [&](double distance) {
        camera.eye = centre + distance * direction;
        const CameraFrame frame = cameraFrame(camera);
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 p(corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z);
            const glm::dvec3 d = p - camera.eye;
            const double z = glm::dot(d, frame.forward);
            if (z <= 0.0 || std::abs(glm::dot(d, frame.right)) > 0.97 * tanX * z ||
                std::abs(glm::dot(d, frame.up)) > 0.97 * tanY * z)
                return false;
        }
        return true;
    };
    double near = radius, far = radius / std::sin(std::atan(0.97 * std::min(tanX, tanY))) + radius;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (near + far);
        (fits(mid) ? far : near) = mid;
    }
    camera.eye = centre + far * direction;
    return camera;
}

Mesh loadSceneMesh(const Scene& scene) {
    const fs::path asFile(scene.mesh);
    if (fs::exists(asFile)) return loadMesh(asFile);
    BuiltinMeshParams params;
    if (scene.tessellation > 0) params.tessellation = scene.tessellation;
    return makeBuiltinMesh(scene.mesh, params);
}

ReliefTexture loadSceneMaterial(const Scene& scene, std::vector<std::string>* notes,
                                const SceneProgress& progress) {
    if (!scene.depthMap.empty()) {
        std::string note;
        ReliefTexture texture;
        texture.depth = readDepthMap(scene.depthMap, DepthEncoding::Depth, &note);
        if (!note.empty() && notes) notes->push_back(note);
        texture.depthScale = scene.relief.depthScale.value_or(kDefaultDepthScale);
        texture.normal = normalsFromDepth(texture.depth, texture.depthScale);
        return texture;
    }
    const fs::path asFile(scene.material);
    if (fs::exists(asFile)) {
        if (isDualDepth(asFile)) {
            // A dual-depth texture read as a single depth layer, its front surface (the impostor drawn by
            // every technique but dual-depth, with the paper's "skins"; docs/dual-depth.md).
            const DualDepthTexture dual = readDualDepth(asFile);
            ReliefTexture texture;
            texture.depth = dual.front;
            texture.normal = dual.normal;
            texture.depthScale = dual.depthScale;
            return texture;
        }
        const bool isTextureSet = fs::is_directory(asFile) || asFile.filename() == kSidecarName;
        if (isTextureSet) return readTextureSet(asFile);
        return composeMaterial(readMaterial(asFile), notes, progress);
    }
    if (scene.material == kMainJobMaterial) {
        return composeMaterial(
            parseMaterial(json::parse(kShapedFabricJson), "built-in material shaped-fabric"), notes,
            progress);
    }
    if (isPattern(scene.material)) {
        if (progress) progress("pattern " + scene.material);
        ReliefTexture texture = makePattern(scene.material);
        AoParams params;
        params.depthScale = texture.depthScale;
        if (progress) progress("ambient occlusion (sweep)");
        texture.ao = bakeAo(texture.depth, params);
        return texture;
    }
    std::string names;
    for (const PatternInfo& info : patternList()) names += ", " + info.name;
    throw Error(ErrorKind::Io, "material '" + scene.material +
                                   "' is neither a file nor a built-in material (" + kMainJobMaterial +
                                   names + ")");
}

const char* toString(MetaPath path) {
    return path == MetaPath::Live ? "live" : "baked";
}

MetaPath parseMetaPath(const std::string& text) {
    if (text == "baked") return MetaPath::Baked;
    if (text == "live") return MetaPath::Live;
    throw Error(ErrorKind::InvalidInput, "meta path must be baked or live, got '" + text + "'");
}

Material loadSceneLayeredMaterial(const Scene& scene) {
    const std::string why =
        " has no layers: the live meta-relief path needs a material JSON (docs/material.md)";
    if (!scene.depthMap.empty()) throw Error(ErrorKind::InvalidInput, "a depth map" + why);
    const fs::path asFile(scene.material);
    if (fs::exists(asFile)) {
        if (fs::is_directory(asFile) || asFile.filename() == kSidecarName)
            throw Error(ErrorKind::InvalidInput, "texture set " + asFile.string() + why);
        return readMaterial(asFile);
    }
    if (scene.material == kMainJobMaterial)
        return parseMaterial(json::parse(kShapedFabricJson), "built-in material shaped-fabric");
    throw Error(ErrorKind::InvalidInput, "material '" + scene.material + "'" + why);
}

double renderDepthScale(const Scene& scene, const ReliefTexture& texture) {
    return scene.relief.depthScale.value_or(texture.depthScale);
}

Image aoForRender(const ReliefTexture& texture, double renderScale, AoRescale rescale, double* aoDepthScale) {
    *aoDepthScale = texture.depthScale;
    if (texture.ao.empty()) return {};
    if (rescale != AoRescale::Exact || renderScale == texture.depthScale) return texture.ao;
    AoParams params;  // the sweep, R = 1, M = 50: the same as every Strata AO map by default
    params.depthScale = renderScale;
    *aoDepthScale = renderScale;
    return bakeAo(texture.depth, params);
}

}  // namespace strata
