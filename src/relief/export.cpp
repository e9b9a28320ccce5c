#include "strata/relief/export.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/core/version.h"
#include "strata/image/image_io.h"
#include "strata/image/image_ops.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/texture_set.h"

#include "core/staging_dir.h"

#include <nlohmann/json.hpp>

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata {

namespace {

const char* kGltfSource = "glTF 2.0 Specification (Khronos): Materials, Meshes";
const char* kHdrpSources[] = {"Unity HDRP manual: Lit Shader", "Unity HDRP manual: Mask and Detail maps"};
const char* kUnrealSources[] = {"Unreal Engine documentation: Physically Based Materials",
                                "Unreal Engine documentation: Texture Format Support and Settings"};
const char* kGodotSources[] = {"Godot Engine 4 documentation: Standard Material 3D and ORM Material 3D",
                               "Godot Engine 4 class reference: BaseMaterial3D"};

std::vector<ExportPresetSpec> makePresets() {
    std::vector<ExportPresetSpec> presets;
    presets.push_back({ExportPreset::Gltf,
                       "gltf",
                       "glTF 2.0",
                       NormalY::Up,
                       {kGltfSource},
                       {{"basecolor.png", "RGB", "base colour, sRGB (baseColorTexture)"},
                        {"normal.png", "RGB", "tangent-space normal n * 0.5 + 0.5, +Y up (normalTexture)"},
                        {"orm.png", "R", "ambient occlusion, 1 = open (occlusionTexture)"},
                        {"orm.png", "G", "roughness (metallicRoughnessTexture), constant --roughness"},
                        {"orm.png", "B", "metallic (metallicRoughnessTexture), constant --metallic"},
                        {"height.png", "gray", "height h = 1 - d, white = high (extras.strata_height)"}}});
    presets.push_back({ExportPreset::UnityHdrp,
                       "unity-hdrp",
                       "Unity HDRP (Lit shader)",
                       NormalY::Up,
                       {kHdrpSources[0], kHdrpSources[1]},
                       {{"basecolor.png", "RGB", "base colour, sRGB (Base Map)"},
                        {"normal.png", "RGB", "tangent-space normal n * 0.5 + 0.5, +Y up (Normal Map)"},
                        {"mask.png", "R", "metallic, constant --metallic"},
                        {"mask.png", "G", "ambient occlusion, 1 = open"},
                        {"mask.png", "B", "detail mask, 1 (detail everywhere)"},
                        {"mask.png", "A", "smoothness = 1 - roughness, constant"},
                        {"height.png", "gray", "height h = 1 - d, white = high (Height Map)"}}});
    presets.push_back(
        {ExportPreset::Unreal,
         "unreal",
         "Unreal Engine 5",
         NormalY::Down,
         {kUnrealSources[0], kUnrealSources[1]},
         {{"basecolor.png", "RGB", "base colour, sRGB (Base Color)"},
          {"normal.png", "RGB", "tangent-space normal n * 0.5 + 0.5, DirectX: +Y down (Normal)"},
          {"arm.png", "R", "ambient occlusion, 1 = open (Ambient Occlusion)"},
          {"arm.png", "G", "roughness, constant --roughness (Roughness)"},
          {"arm.png", "B", "metallic, constant --metallic (Metallic)"},
          {"height.png", "gray", "height h = 1 - d, white = high (parallax / displacement)"}}});
    presets.push_back({ExportPreset::Godot,
                       "godot",
                       "Godot 4 (StandardMaterial3D / ORMMaterial3D)",
                       NormalY::Up,
                       {kGodotSources[0], kGodotSources[1]},
                       {{"albedo.png", "RGB", "albedo, sRGB (albedo_texture)"},
                        {"normal.png", "RGB", "tangent-space normal n * 0.5 + 0.5, +Y up (normal_texture)"},
                        {"orm.png", "R", "ambient occlusion, 1 = open (orm_texture / ao_texture, Red)"},
                        {"orm.png", "G", "roughness, constant --roughness (roughness_texture, Green)"},
                        {"orm.png", "B", "metallic, constant --metallic (metallic_texture, Blue)"},
                        {"height.png", "gray", "height h = 1 - d, white = high (heightmap_texture)"}}});
    presets.push_back({ExportPreset::Strata,
                       "strata",
                       "Strata texture set (docs/texture-sets.md)",
                       NormalY::Up,
                       {"CONVENTIONS §2-§6", "docs/texture-sets.md"},
                       {{"depth.png", "gray", "depth d, 0 = top, 1 = deepest"},
                        {"height.png", "gray", "height h = 1 - d, white = high"},
                        {"normal.png", "RGB", "tangent-space normal n * 0.5 + 0.5 (--normal-y)"},
                        {"color.png", "RGB", "colour, sRGB, 8-bit PNG (only if the set has colour)"},
                        {"ao.png", "gray", "AO, 1 = open (only if the set has AO)"},
                        {"packed.png", "RGBA", "R = nx*0.5+0.5, G = ny*0.5+0.5, B = AO, A = d"}}});
    return presets;
}

Image constantImage(int width, int height, int channels, float value) {
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c) image.at(x, y, c) = value;
    return image;
}

Image heightOf(const Image& depth) {
    return heightToDepth(depth);  // the same function both ways: h = 1 - d
}

Image encodedNormals(const Image& normals, NormalY normalY) {
    Image encoded = encodeNormals(normals);
    if (normalY == NormalY::Down)
        for (int y = 0; y < encoded.height(); ++y)
            for (int x = 0; x < encoded.width(); ++x) encoded.at(x, y, 1) = 1.0f - encoded.at(x, y, 1);
    return encoded;
}

// AO at the depth map's resolution (1.0, fully open, when the set has none).
Image aoAtDepthResolution(const ReliefTexture& texture) {
    const int width = texture.depth.width();
    const int height = texture.depth.height();
    if (texture.ao.empty()) return constantImage(width, height, 1, 1.0f);
    if (texture.ao.width() == width && texture.ao.height() == height) return texture.ao;
    return resample(texture.ao, width, height);
}

// Three or four channels at the depth map's resolution from per-channel constants and AO at `aoChannel`.
Image packChannels(const ReliefTexture& texture, const std::vector<float>& constants, int aoChannel) {
    const Image ao = aoAtDepthResolution(texture);
    const int channels = static_cast<int>(constants.size());
    Image out(ao.width(), ao.height(), channels);
    for (int y = 0; y < ao.height(); ++y)
        for (int x = 0; x < ao.width(); ++x)
            for (int c = 0; c < channels; ++c)
                out.at(x, y, c) = c == aoChannel ? ao.at(x, y) : constants[static_cast<std::size_t>(c)];
    return out;
}

Image baseColour(const ReliefTexture& texture) {
    // No colour in the set: a mid-light grey, 0.8 as stored (sRGB-encoded).
    if (texture.color.empty()) return constantImage(texture.depth.width(), texture.depth.height(), 3, 0.8f);
    return toRgb(texture.color);
}

json channelTable(const ExportPresetSpec& spec) {
    json table = json::array();
    for (const ExportChannel& c : spec.channels)
        table.push_back({{"file", c.file}, {"channel", c.channel}, {"content", c.content}});
    return table;
}

// ---------------------------------------------------------------------------------------------------------
// glTF through tinygltf.

template <typename T>
int addBufferView(tinygltf::Model& model, const std::vector<T>& data, int target) {
    tinygltf::Buffer& buffer = model.buffers[0];
    const std::size_t offset = buffer.data.size();
    const std::size_t bytes = data.size() * sizeof(T);
    buffer.data.resize(offset + bytes);
    std::memcpy(buffer.data.data() + offset, data.data(), bytes);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = bytes;
    view.target = target;
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size()) - 1;
}

int addAccessor(tinygltf::Model& model, int view, int componentType, std::size_t count, int type) {
    tinygltf::Accessor accessor;
    accessor.bufferView = view;
    accessor.byteOffset = 0;
    accessor.componentType = componentType;
    accessor.count = count;
    accessor.type = type;
    model.accessors.push_back(accessor);
    return static_cast<int>(model.accessors.size()) - 1;
}

int addTexture(tinygltf::Model& model, const std::string& uri) {
    tinygltf::Image image;
    image.uri = uri;
    image.mimeType = "image/png";
    model.images.push_back(image);
    tinygltf::Texture texture;
    texture.source = static_cast<int>(model.images.size()) - 1;
    texture.sampler = 0;
    model.textures.push_back(texture);
    return static_cast<int>(model.textures.size()) - 1;
}

void writeGltf(const fs::path& file, const Mesh& mesh, const ReliefTexture& texture,
               const ExportOptions& options) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = std::string("strata ") + kVersion;
    model.buffers.resize(1);
    model.buffers[0].uri = options.assetName + ".bin";

    std::vector<float> positions;
    std::vector<float> normals;
    std::vector<float> tangents;
    std::vector<float> uvs;
    std::vector<double> lo(3, 0.0);
    std::vector<double> hi(3, 0.0);
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const MeshVertex& v = mesh.vertices[i];
        for (int c = 0; c < 3; ++c) {
            const auto cc = static_cast<std::size_t>(c);
            const double p = static_cast<double>(v.position[c]);
            lo[cc] = i == 0 ? p : std::min(lo[cc], p);
            hi[cc] = i == 0 ? p : std::max(hi[cc], p);
            positions.push_back(v.position[c]);
            normals.push_back(v.normal[c]);
        }
        for (int c = 0; c < 4; ++c) tangents.push_back(v.tangent[c]);
        // glTF's texture coordinates have t = 0 at the image's first row; Strata's v = 1 is that row.
        uvs.push_back(v.uv.x);
        uvs.push_back(1.0f - v.uv.y);
    }
    const std::size_t count = mesh.vertices.size();
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    const int position = addAccessor(model, addBufferView(model, positions, TINYGLTF_TARGET_ARRAY_BUFFER),
                                     TINYGLTF_COMPONENT_TYPE_FLOAT, count, TINYGLTF_TYPE_VEC3);
    model.accessors[static_cast<std::size_t>(position)].minValues = lo;
    model.accessors[static_cast<std::size_t>(position)].maxValues = hi;
    primitive.attributes["POSITION"] = position;
    primitive.attributes["NORMAL"] =
        addAccessor(model, addBufferView(model, normals, TINYGLTF_TARGET_ARRAY_BUFFER),
                    TINYGLTF_COMPONENT_TYPE_FLOAT, count, TINYGLTF_TYPE_VEC3);
    primitive.attributes["TANGENT"] =
        addAccessor(model, addBufferView(model, tangents, TINYGLTF_TARGET_ARRAY_BUFFER),
                    TINYGLTF_COMPONENT_TYPE_FLOAT, count, TINYGLTF_TYPE_VEC4);
    primitive.attributes["TEXCOORD_0"] =
        addAccessor(model, addBufferView(model, uvs, TINYGLTF_TARGET_ARRAY_BUFFER),
                    TINYGLTF_COMPONENT_TYPE_FLOAT, count, TINYGLTF_TYPE_VEC2);
    primitive.indices =
        addAccessor(model, addBufferView(model, mesh.indices, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, mesh.indices.size(), TINYGLTF_TYPE_SCALAR);
    primitive.material = 0;

    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    sampler.wrapS = TINYGLTF_TEXTURE_WRAP_REPEAT;
    sampler.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
    model.samplers.push_back(sampler);

    tinygltf::Material material;
    material.name = options.assetName;
    material.pbrMetallicRoughness.baseColorTexture.index = addTexture(model, "basecolor.png");
    material.normalTexture.index = addTexture(model, "normal.png");
    const int orm = addTexture(model, "orm.png");
    material.occlusionTexture.index = orm;
    material.pbrMetallicRoughness.metallicRoughnessTexture.index = orm;
    // The texture holds the values; the factors (default 1) leave them as they are.
    material.pbrMetallicRoughness.metallicFactor = 1.0;
    material.pbrMetallicRoughness.roughnessFactor = 1.0;
    tinygltf::Value::Object height;
    height["uri"] = tinygltf::Value(std::string("height.png"));
    height["encoding"] = tinygltf::Value(std::string("height, white = high: h = 1 - d (16-bit gray PNG)"));
    height["scale"] = tinygltf::Value(texture.depthScale);
    height["scale_meaning"] = tinygltf::Value(
        std::string("the height of h = 1 above h = 0, in tile widths; one tile is one unit of TEXCOORD_0"));
    tinygltf::Value::Object extras;
    extras["strata_height"] = tinygltf::Value(height);
    material.extras = tinygltf::Value(extras);
    model.materials.push_back(material);

    tinygltf::Mesh gltfMesh;
    gltfMesh.name = mesh.name;
    gltfMesh.primitives.push_back(primitive);
    model.meshes.push_back(gltfMesh);
    tinygltf::Node node;
    node.mesh = 0;
    node.name = options.assetName;
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes.push_back(0);
    model.scenes.push_back(scene);
    model.defaultScene = 0;

    tinygltf::TinyGLTF writer;
    // The PNGs are written by Strata (writePng): tinygltf only records their URIs.
    writer.SetImageWriter(nullptr, nullptr);
    if (!writer.WriteGltfSceneToFile(&model, file.string(), false, false, true, false))
        throw Error(ErrorKind::Io, file.string() + ": cannot write the glTF asset");
}

}  // namespace

const std::vector<ExportPresetSpec>& exportPresets() {
    static const std::vector<ExportPresetSpec> presets = makePresets();
    return presets;
}

const ExportPresetSpec& exportPresetSpec(ExportPreset preset) {
    for (const ExportPresetSpec& spec : exportPresets())
        if (spec.preset == preset) return spec;
    throw Error(ErrorKind::Usage, "unknown export preset");
}

ExportPreset parseExportPreset(const std::string& name) {
    std::string known;
    for (const ExportPresetSpec& spec : exportPresets()) {
        if (spec.name == name) return spec.preset;
        known += (known.empty() ? "" : ", ") + spec.name;
    }
    throw Error(ErrorKind::Usage, "--preset: unknown preset '" + name + "' (known: " + known + ")");
}

NormalY parseNormalY(const std::string& text) {
    if (text == "up") return NormalY::Up;
    if (text == "down") return NormalY::Down;
    throw Error(ErrorKind::Usage, "--normal-y: expected up or down, got '" + text + "'");
}

ExportFormat parseExportFormat(const std::string& text) {
    if (text == "png") return ExportFormat::Png;
    if (text == "exr") return ExportFormat::Exr;
    throw Error(ErrorKind::Usage, "--format: expected png or exr, got '" + text + "'");
}

void checkExportOptions(const ExportOptions& options) {
    const ExportPresetSpec& spec = exportPresetSpec(options.preset);
    const NormalY normalY = options.normalY.value_or(spec.normalY);
    if (options.preset == ExportPreset::Gltf && normalY == NormalY::Down)
        throw Error(ErrorKind::Usage,
                    "--normal-y down: glTF 2.0 normal textures are +Y up (OpenGL); the gltf preset needs up");
    if (options.format == ExportFormat::Exr && options.preset != ExportPreset::Strata)
        throw Error(ErrorKind::Usage, "--format exr: only the strata preset writes EXR; the " + spec.name +
                                          " preset writes the PNGs its engine imports");
    auto checkUnit = [](const char* flag, double value) {
        if (!(value >= 0.0 && value <= 1.0))
            throw Error(ErrorKind::InvalidInput,
                        std::string(flag) + ": must be in [0, 1], got " + formatNumber(value));
    };
    checkUnit("--roughness", options.roughness);
    checkUnit("--metallic", options.metallic);
}

std::vector<fs::path> exportTextureSet(const fs::path& dir, const ReliefTexture& texture,
                                       const ExportOptions& options) {
    checkExportOptions(options);
    const ExportPresetSpec& spec = exportPresetSpec(options.preset);
    const NormalY normalY = options.normalY.value_or(spec.normalY);
    if (texture.depth.empty() || texture.normal.empty())
        throw Error(ErrorKind::InvalidInput, dir.string() + ": a texture set needs depth and normal maps");
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw Error(ErrorKind::Io, dir.string() + ": exists and is not a directory");

    const float roughness = static_cast<float>(options.roughness);
    const float metallic = static_cast<float>(options.metallic);
    const PngWriteOptions eight{PngBitDepth::Eight, true};
    const PngWriteOptions sixteen{PngBitDepth::Sixteen, true};

    std::vector<std::string> names;
    detail::StagingDir staging(dir);
    auto stage = [&](const std::string& name, const Image& image, const PngWriteOptions& png) {
        refuseToOverwriteInputs(dir / name, options.inputs);
        writeImage(staging.path() / name, image, png);
        names.push_back(name);
    };

    json manifest;
    manifest["format"] = "strata.export";
    manifest["format_version"] = 1;
    manifest["tool"] = std::string("strata ") + kVersion;
    manifest["preset"] = spec.name;
    manifest["engine"] = spec.engine;
    manifest["sources"] = spec.sources;
    manifest["depth_scale"] = texture.depthScale;
    manifest["normal_y"] = normalY == NormalY::Up ? "up (OpenGL)" : "down (DirectX)";
    manifest["roughness"] = options.roughness;
    manifest["metallic"] = options.metallic;
    manifest["channels"] = channelTable(spec);
    manifest["height"] = {{"file", "height.png"},
                          {"encoding", "white = high, h = 1 - d"},
                          {"amplitude_tile_widths", texture.depthScale},
                          {"amplitude_cm_for_a_1m_tile", texture.depthScale * 100.0}};

    const Image normal = encodedNormals(texture.normal, normalY);
    switch (options.preset) {
        case ExportPreset::Gltf: {
            stage("basecolor.png", baseColour(texture), eight);
            stage("normal.png", normal, eight);
            stage("orm.png", packChannels(texture, {1.0f, roughness, metallic}, 0), eight);
            stage("height.png", heightOf(texture.depth), sixteen);
            const std::string gltfName = options.assetName + ".gltf";
            refuseToOverwriteInputs(dir / gltfName, options.inputs);
            refuseToOverwriteInputs(dir / (options.assetName + ".bin"), options.inputs);
            writeGltf(staging.path() / gltfName, options.mesh ? *options.mesh : makeBuiltinMesh("quad"),
                      texture, options);
            names.push_back(options.assetName + ".bin");
            names.push_back(gltfName);
            manifest["asset"] = gltfName;
            manifest["height"]["gltf"] = "materials[0].extras.strata_height {uri, encoding, scale}";
            break;
        }
        case ExportPreset::UnityHdrp:
            stage("basecolor.png", baseColour(texture), eight);
            stage("normal.png", normal, eight);
            stage("mask.png", packChannels(texture, {metallic, 1.0f, 1.0f, 1.0f - roughness}, 1), eight);
            stage("height.png", heightOf(texture.depth), sixteen);
            manifest["engine_settings"] = {
                {"shader", "HDRP/Lit"},
                {"Normal Map", "normal.png, Texture Type: Normal map (OpenGL, +Y up)"},
                {"Mask Map", "mask.png, sRGB off"},
                {"Height Map", "height.png, sRGB off"},
                {"Displacement Mode", "Pixel displacement"},
                {"Height Map Parametrization", "Amplitude"},
                {"Amplitude (cm), for a tile 1 m wide", texture.depthScale * 100.0}};
            break;
        case ExportPreset::Unreal:
            stage("basecolor.png", baseColour(texture), eight);
            stage("normal.png", normal, eight);
            stage("arm.png", packChannels(texture, {1.0f, roughness, metallic}, 0), eight);
            stage("height.png", heightOf(texture.depth), sixteen);
            manifest["engine_settings"] = {
                {"normal.png", "Compression Settings: Normalmap (DirectX, green down)"},
                {"arm.png",
                 "Compression Settings: Masks (no sRGB); R -> Ambient Occlusion, G -> Roughness, "
                 "B -> Metallic"},
                {"height.png", "sRGB off; parallax occlusion mapping height, amplitude = depth_scale tiles"}};
            break;
        case ExportPreset::Godot:
            stage("albedo.png", baseColour(texture), eight);
            stage("normal.png", normal, eight);
            stage("orm.png", packChannels(texture, {1.0f, roughness, metallic}, 0), eight);
            stage("height.png", heightOf(texture.depth), sixteen);
            manifest["engine_settings"] = {
                {"material",
                 "ORMMaterial3D (orm_texture = orm.png), or StandardMaterial3D with "
                 "ao_texture_channel Red, roughness_texture_channel Green, "
                 "metallic_texture_channel Blue on orm.png (metallic = 1, roughness = 1)"},
                {"albedo_texture", "albedo.png"},
                {"normal_enabled", true},
                {"normal_texture", "normal.png (OpenGL, +Y up)"},
                {"ao_enabled", true},
                {"heightmap_enabled", true},
                {"heightmap_texture", "height.png"},
                {"heightmap_flip_texture", false},
                {"heightmap_deep_parallax", true},
                {"heightmap_scale, for a tile 1 m wide (cm)", texture.depthScale * 100.0}};
            break;
        case ExportPreset::Strata: {
            const bool exr = options.format == ExportFormat::Exr;
            const std::string ext = exr ? ".exr" : ".png";
            stage("depth" + ext, texture.depth, sixteen);
            stage("height" + ext, heightOf(texture.depth), sixteen);
            stage("normal" + ext, normal, sixteen);
            if (!texture.color.empty()) stage("color.png", toRgb(texture.color), eight);
            if (!texture.ao.empty()) stage("ao" + ext, texture.ao, sixteen);
            stage("packed" + ext, packRelief(texture), sixteen);
            json sidecar = json::object();
            if (!options.sourceSidecar.empty()) {
                try {
                    sidecar = json::parse(options.sourceSidecar);
                } catch (const json::exception&) {
                    sidecar = json::object();
                }
            }
            sidecar["format"] = kSidecarFormat;
            sidecar["format_version"] = 1;
            sidecar["tool"] = std::string("strata ") + kVersion;
            sidecar["depth_scale"] = texture.depthScale;
            sidecar["bit_depth"] = exr ? 32 : 16;
            sidecar["float_format"] =
                exr ? json("float32 EXR (ZIP), values as computed, not quantised") : json(nullptr);
            auto entry = [&](const char* key) -> json& {
                if (!sidecar.contains(key) || !sidecar[key].is_object()) sidecar[key] = json::object();
                return sidecar[key];
            };
            entry("depth")["file"] = "depth" + ext;
            entry("depth")["encoding"] = "depth";
            entry("depth")["meaning"] = "0 = polygon surface (top), 1 = deepest; relief point (u, v, -S * d)";
            sidecar["height"] = {{"file", "height" + ext},
                                 {"encoding", "height"},
                                 {"meaning", "white = high: h = 1 - d (CONVENTIONS §2)"}};
            entry("normal")["file"] = "normal" + ext;
            entry("normal")["convention"] = normalY == NormalY::Up ? "opengl" : "directx";
            entry("normal")["green"] =
                normalY == NormalY::Up ? "up (+y towards v = 1)" : "down (+y towards v = 0)";
            entry("normal")["encoding"] = "n * 0.5 + 0.5";
            if (texture.color.empty())
                sidecar["color"] = nullptr;
            else
                entry("color")["file"] = "color.png";
            if (texture.ao.empty())
                sidecar["ao"] = nullptr;
            else
                entry("ao")["file"] = "ao" + ext;
            entry("packed")["file"] = "packed" + ext;
            refuseToOverwriteInputs(dir / kSidecarName, options.inputs);
            writeTextFileAtomic(staging.path() / kSidecarName, sidecar.dump(2) + "\n");
            names.emplace_back(kSidecarName);
            break;
        }
    }
    if (options.preset != ExportPreset::Strata) {
        refuseToOverwriteInputs(dir / "export.json", options.inputs);
        writeTextFileAtomic(staging.path() / "export.json", manifest.dump(2) + "\n");
        names.emplace_back("export.json");
    }

    fs::create_directories(dir, ec);
    if (ec)
        throw Error(ErrorKind::Io, dir.string() + ": cannot create the output directory: " + ec.message());
    std::vector<fs::path> written;
    for (const std::string& name : names) {
        fs::rename(staging.path() / name, dir / name, ec);
        if (ec)
            throw Error(ErrorKind::Io, (dir / name).string() + ": cannot move into place: " + ec.message());
        written.push_back(dir / name);
    }
    return written;
}

}  // namespace strata
