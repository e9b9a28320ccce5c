// Export presets (docs/export.md): each file's channels hold what the preset's channel table says, the glTF
// asset round-trips through tinygltf, the EXR set through readTextureSet, and refused combinations write
// nothing.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/relief/export.h"
#include "strata/relief/texture_set.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>

namespace strata {
namespace {

// A 16 x 8 set (not square) with a depth ramp, its normals, colour and an AO map that differs per texel.
ReliefTexture testSet() {
    ReliefTexture texture;
    texture.depthScale = 0.1;
    texture.depth = Image(16, 8, 1);
    texture.ao = Image(16, 8, 1);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            texture.depth.at(x, y) =
                static_cast<float>(x) / 15.0f * 0.5f + static_cast<float>(y) / 7.0f * 0.25f;
            texture.ao.at(x, y) = 0.3f + 0.04f * static_cast<float>(x);
        }
    texture.normal = normalsFromDepth(texture.depth, texture.depthScale);
    texture.color = Image(16, 8, 3, 0.4f);
    return texture;
}

// 8-bit outputs are dithered by at most +-0.5 LSB before rounding (CONVENTIONS §5): one LSB at most.
constexpr double kEightBitTolerance = 1.0 / 255.0 + 1e-6;
// The 16-bit height: rounding to the nearest step, half a step at most.
constexpr double kSixteenBitTolerance = 0.5 / 65535.0 + 1e-7;

double maxChannelError(const Image& image, int channel, const std::function<double(int, int)>& expected) {
    double error = 0.0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            error = std::max(error, std::abs(static_cast<double>(image.at(x, y, channel)) - expected(x, y)));
    return error;
}

TEST(Export, GltfRoundTripsThroughTinygltfWithItsChannels) {
    test::ScratchDir dir("export-gltf");
    const ReliefTexture texture = testSet();
    ExportOptions options;
    options.preset = ExportPreset::Gltf;
    options.roughness = 0.6;
    options.metallic = 0.25;
    const auto written = exportTextureSet(dir / "out", texture, options);
    EXPECT_EQ(written.size(), 7u);  // basecolor, normal, orm, height, .bin, .gltf, export.json

    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string error;
    std::string warning;
    ASSERT_TRUE(loader.LoadASCIIFromFile(&model, &error, &warning, (dir / "out" / "relief.gltf").string()))
        << error;
    EXPECT_TRUE(error.empty()) << error;
    EXPECT_EQ(model.asset.version, "2.0");
    ASSERT_EQ(model.materials.size(), 1u);
    const tinygltf::Material& material = model.materials[0];
    auto uriOf = [&](int textureIndex) {
        return model
            .images[static_cast<std::size_t>(model.textures[static_cast<std::size_t>(textureIndex)].source)]
            .uri;
    };
    EXPECT_EQ(uriOf(material.pbrMetallicRoughness.baseColorTexture.index), "basecolor.png");
    EXPECT_EQ(uriOf(material.normalTexture.index), "normal.png");
    EXPECT_EQ(uriOf(material.occlusionTexture.index), "orm.png");
    EXPECT_EQ(uriOf(material.pbrMetallicRoughness.metallicRoughnessTexture.index), "orm.png");
    EXPECT_EQ(material.pbrMetallicRoughness.metallicFactor, 1.0);
    EXPECT_EQ(material.pbrMetallicRoughness.roughnessFactor, 1.0);
    const tinygltf::Value& height = material.extras.Get("strata_height");
    ASSERT_TRUE(height.IsObject());
    EXPECT_EQ(height.Get("uri").Get<std::string>(), "height.png");
    EXPECT_EQ(height.Get("scale").GetNumberAsDouble(), 0.1);  // S as written, exactly

    // The unit quad of CONVENTIONS §7, with t = 1 - v (glTF's t = 0 is the image's first row, Strata's v =
    // 1).
    ASSERT_EQ(model.meshes.size(), 1u);
    const tinygltf::Primitive& primitive = model.meshes[0].primitives[0];
    auto floats = [&](const char* attribute) {
        const tinygltf::Accessor& accessor =
            model.accessors[static_cast<std::size_t>(primitive.attributes.at(attribute))];
        const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
        const unsigned char* data = model.buffers[static_cast<std::size_t>(view.buffer)].data.data() +
                                    view.byteOffset + accessor.byteOffset;
        std::vector<float> values(view.byteLength / sizeof(float));
        std::memcpy(values.data(), data, view.byteLength);
        return values;
    };
    EXPECT_EQ(floats("POSITION"), (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
    EXPECT_EQ(floats("TEXCOORD_0"), (std::vector<float>{0, 1, 1, 1, 1, 0, 0, 0}));
    EXPECT_EQ(floats("TANGENT"), (std::vector<float>{1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}));

    // ORM: R = AO, G = roughness, B = metallic.
    const Image orm = readImage(dir / "out" / "orm.png");
    ASSERT_EQ(orm.channels(), 3);
    EXPECT_LE(maxChannelError(orm, 0, [&](int x, int y) { return static_cast<double>(texture.ao.at(x, y)); }),
              kEightBitTolerance);
    EXPECT_LE(maxChannelError(orm, 1, [](int, int) { return 0.6; }), kEightBitTolerance);
    EXPECT_LE(maxChannelError(orm, 2, [](int, int) { return 0.25; }), kEightBitTolerance);
    // tinygltf decoded the same bytes: its R channel is the file's.
    const tinygltf::Image& ormImage = model.images[static_cast<std::size_t>(
        model.textures[static_cast<std::size_t>(material.occlusionTexture.index)].source)];
    ASSERT_EQ(ormImage.width, 16);
    ASSERT_EQ(ormImage.height, 8);
    EXPECT_EQ(ormImage.image[0], static_cast<unsigned char>(std::lround(orm.at(0, 0, 0) * 255.0f)));

    // Normal: OpenGL, green = ny * 0.5 + 0.5.
    const Image normal = readImage(dir / "out" / "normal.png");
    EXPECT_LE(maxChannelError(
                  normal, 1,
                  [&](int x, int y) { return static_cast<double>(texture.normal.at(x, y, 1)) * 0.5 + 0.5; }),
              kEightBitTolerance);
    // Height: white = high, h = 1 - d.
    const Image heightMap = readImage(dir / "out" / "height.png");
    EXPECT_EQ(readImageInfo(dir / "out" / "height.png").bitDepth, 16);
    EXPECT_LE(
        maxChannelError(heightMap, 0,
                        [&](int x, int y) { return 1.0 - static_cast<double>(texture.depth.at(x, y)); }),
        kSixteenBitTolerance);
}

TEST(Export, UnityMaskMapIsMetallicAoDetailSmoothness) {
    test::ScratchDir dir("export-unity");
    const ReliefTexture texture = testSet();
    ExportOptions options;
    options.preset = ExportPreset::UnityHdrp;
    options.roughness = 0.7;
    options.metallic = 0.9;
    exportTextureSet(dir / "out", texture, options);
    const Image mask = readImage(dir / "out" / "mask.png");
    ASSERT_EQ(mask.channels(), 4);
    EXPECT_LE(maxChannelError(mask, 0, [](int, int) { return 0.9; }), kEightBitTolerance);
    EXPECT_LE(
        maxChannelError(mask, 1, [&](int x, int y) { return static_cast<double>(texture.ao.at(x, y)); }),
        kEightBitTolerance);
    EXPECT_LE(maxChannelError(mask, 2, [](int, int) { return 1.0; }), kEightBitTolerance);
    EXPECT_LE(maxChannelError(mask, 3, [](int, int) { return 0.3; }), kEightBitTolerance);  // 1 - roughness
    std::ifstream stream(dir / "out" / "export.json");
    const nlohmann::json manifest = nlohmann::json::parse(stream);
    EXPECT_EQ(manifest["preset"], "unity-hdrp");
    EXPECT_EQ(manifest["height"]["amplitude_tile_widths"].get<double>(), 0.1);
}

TEST(Export, UnrealNormalsAreDirectXAndArmPacked) {
    test::ScratchDir dir("export-unreal");
    const ReliefTexture texture = testSet();
    ExportOptions options;
    options.preset = ExportPreset::Unreal;
    exportTextureSet(dir / "out", texture, options);
    const Image normal = readImage(dir / "out" / "normal.png");
    // DirectX: green = -ny * 0.5 + 0.5; red unchanged.
    EXPECT_LE(maxChannelError(
                  normal, 1,
                  [&](int x, int y) { return -static_cast<double>(texture.normal.at(x, y, 1)) * 0.5 + 0.5; }),
              kEightBitTolerance);
    EXPECT_LE(maxChannelError(
                  normal, 0,
                  [&](int x, int y) { return static_cast<double>(texture.normal.at(x, y, 0)) * 0.5 + 0.5; }),
              kEightBitTolerance);
    const Image arm = readImage(dir / "out" / "arm.png");
    EXPECT_LE(maxChannelError(arm, 0, [&](int x, int y) { return static_cast<double>(texture.ao.at(x, y)); }),
              kEightBitTolerance);
    EXPECT_LE(maxChannelError(arm, 1, [](int, int) { return 0.8; }),
              kEightBitTolerance);  // default roughness
    EXPECT_LE(maxChannelError(arm, 2, [](int, int) { return 0.0; }), kEightBitTolerance);  // default metallic

    // --normal-y up overrides the engine's default.
    options.normalY = NormalY::Up;
    exportTextureSet(dir / "up", texture, options);
    EXPECT_LE(maxChannelError(
                  readImage(dir / "up" / "normal.png"), 1,
                  [&](int x, int y) { return static_cast<double>(texture.normal.at(x, y, 1)) * 0.5 + 0.5; }),
              kEightBitTolerance);
}

TEST(Export, GodotWritesAlbedoNormalOrmHeight) {
    test::ScratchDir dir("export-godot");
    ExportOptions options;
    options.preset = ExportPreset::Godot;
    const auto written = exportTextureSet(dir / "out", testSet(), options);
    std::vector<std::string> names;
    for (const auto& path : written) names.push_back(path.filename().string());
    EXPECT_EQ(names,
              (std::vector<std::string>{"albedo.png", "normal.png", "orm.png", "height.png", "export.json"}));
}

TEST(Export, StrataExrSetReadsBackExactlyWithHeightBesideDepth) {
    test::ScratchDir dir("export-exr");
    const ReliefTexture texture = testSet();
    ExportOptions options;
    options.preset = ExportPreset::Strata;
    options.format = ExportFormat::Exr;
    exportTextureSet(dir / "out", texture, options);
    EXPECT_EQ(readImageInfo(dir / "out" / "depth.exr").bitDepth, 32);
    const ReliefTexture back = readTextureSet(dir / "out");
    // float32 EXR stores the floats themselves: no quantisation at all.
    EXPECT_EQ(test::maxAbsDiff(back.depth, texture.depth), 0.0);
    EXPECT_EQ(test::maxAbsDiff(back.ao, texture.ao), 0.0);
    // Normals go through n * 0.5 + 0.5 and back, and are renormalised: float rounding only.
    EXPECT_LE(test::maxAbsDiff(back.normal, texture.normal), 1e-6);
    // h = 1 - d computed in float, as the export does, and stored as that float.
    const Image height = readImage(dir / "out" / "height.exr");
    EXPECT_EQ(
        maxChannelError(height, 0,
                        [&](int x, int y) { return static_cast<double>(1.0f - texture.depth.at(x, y)); }),
        0.0);
    EXPECT_EQ(readSidecar(dir / "out")["height"]["file"], "height.exr");
}

TEST(Export, RefusedCombinationsWriteNothing) {
    test::ScratchDir dir("export-refused");
    const ReliefTexture texture = testSet();
    auto kindOf = [&](const ExportOptions& options) {
        try {
            exportTextureSet(dir / "out", texture, options);
        } catch (const Error& e) {
            return e.kind();
        }
        return ErrorKind::Runtime;  // not thrown: fails the expectation below
    };
    ExportOptions gltfDown;
    gltfDown.normalY = NormalY::Down;
    EXPECT_EQ(kindOf(gltfDown), ErrorKind::Usage);
    ExportOptions unityExr;
    unityExr.preset = ExportPreset::UnityHdrp;
    unityExr.format = ExportFormat::Exr;
    EXPECT_EQ(kindOf(unityExr), ErrorKind::Usage);
    ExportOptions rough;
    rough.roughness = 1.5;
    EXPECT_EQ(kindOf(rough), ErrorKind::InvalidInput);
    EXPECT_EQ(test::countEntries(dir.path()), 0);  // no output directory, no staging left behind
    EXPECT_THROW(parseExportPreset("unity"), Error);
}

}  // namespace
}  // namespace strata
