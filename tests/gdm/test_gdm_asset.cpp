// The GDM asset: a bit-exact round trip, every corruption refused naming the file, nothing left behind; the
// optional solid.obj (the solid as baked) and assets without it.
#include "strata/gdm/gdm_asset.h"

#include "strata/core/error.h"
#include "strata/image/quantize.h"

#include "test_solids.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

namespace strata {
namespace {

namespace fs = std::filesystem;

// A 2 x 2 x 2 GDM with 2 x 2 directions: voxel 0 inside (all 0), the others a mix of hits and misses.
Gdm tinyGdm() {
    Gdm gdm;
    gdm.dims = {2, 2, 2, 2, 2};
    gdm.height = 0.25;
    gdm.values.resize(gdm.dims.valueCount());
    for (std::size_t n = 0; n < gdm.values.size(); ++n)
        gdm.values[n] = n < 4 ? 0.0f : (n % 3 == 0 ? kGdmMiss : 0.01f * float(n));
    return gdm;
}

GdmAsset tinyAsset(bool keepRaw) {
    const Gdm gdm = tinyGdm();
    GdmAsset asset;
    asset.svd = compressGdm(gdm, 2);
    asset.occupancy = gdmOccupancy(gdm);
    if (keepRaw) {
        asset.raw = gdm;
        for (std::size_t n = 0; n < 8 * 3; ++n) asset.albedo.push_back(std::uint8_t(n * 10));
    }
    asset.source = "test";
    asset.bake = {"--size 2x2x2", 0.5, "2026-12-04T00:00:00Z"};
    return asset;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

void writeText(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// `text` with its first `from` replaced by `to` (a failure if there is none).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

// Runs `f` and returns the message of the Error(kind) it must throw.
template <class F>
std::string errorOf(F f, ErrorKind kind) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error";
    return {};
}

TEST(GdmAsset, OccupancyIsWhereEveryDirectionIsZero) {
    const std::vector<std::uint8_t> occupancy = gdmOccupancy(tinyGdm());
    ASSERT_EQ(occupancy.size(), 8u);
    EXPECT_EQ(occupancy[0], 1);
    for (std::size_t v = 1; v < 8; ++v) EXPECT_EQ(occupancy[v], 0) << v;
}

TEST(GdmAsset, AlbedoIsTheNearestPartsColourAtEachVoxelCentre) {
    const Mesostructure meso = makeMesostructure("grid");
    const GdmDims dims{4, 4, 2, 1, 1};
    const std::vector<std::uint8_t> albedo = mesostructureAlbedo(meso, dims);
    ASSERT_EQ(albedo.size(), dims.voxelCount() * 3);
    // Voxel (1, 2, 1): index 1 + 4 (2 + 4 * 1) = 25; the exact 8-bit value of its sample's colour.
    const glm::dvec3 colour = meso.sample(gdmVoxelCentre(dims, meso.height(), 1, 2, 1)).albedo;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(albedo[25 * 3 + std::size_t(c)], toUnorm8(colour[c])) << c;
}

TEST(GdmAsset, RoundTripIsBitExact) {
    test::ScratchDir dir("gdm-asset");
    const GdmAsset asset = tinyAsset(true);
    writeGdmAsset(dir / "a", asset);
    EXPECT_TRUE(isGdmAsset(dir / "a"));
    EXPECT_EQ(test::countEntries(dir.path()), 1);  // no staging directory left
    EXPECT_EQ(test::countEntries(dir / "a"), 6);   // gdm.json and five payloads
    const GdmAsset back = readGdmAsset(dir / "a");
    EXPECT_EQ(back.svd.dims, asset.svd.dims);
    EXPECT_EQ(back.svd.height, asset.svd.height);
    EXPECT_EQ(back.svd.layout, asset.svd.layout);
    EXPECT_EQ(back.svd.rank, asset.svd.rank);
    EXPECT_EQ(back.svd.rows, asset.svd.rows);
    EXPECT_EQ(back.svd.cols, asset.svd.cols);
    EXPECT_EQ(back.svd.exitTolerance, asset.svd.exitTolerance);
    EXPECT_EQ(back.svd.singularValues, asset.svd.singularValues);  // JSON doubles round-trip exactly
    EXPECT_TRUE(sameBits(back.svd.weights, asset.svd.weights));
    EXPECT_TRUE(sameBits(back.svd.eigen, asset.svd.eigen));
    ASSERT_TRUE(back.raw.has_value());
    EXPECT_TRUE(sameBits(back.raw->values, asset.raw->values));  // +inf (kGdmMiss) included
    EXPECT_EQ(back.raw->values[6], kGdmMiss);
    EXPECT_EQ(back.occupancy, asset.occupancy);
    EXPECT_EQ(back.albedo, asset.albedo);
    EXPECT_EQ(back.source, "test");
    EXPECT_EQ(back.bake.settings, "--size 2x2x2");
    EXPECT_EQ(back.bake.seconds, 0.5);
    EXPECT_EQ(back.bake.date, "2026-12-04T00:00:00Z");
}

// tinyAsset with the solid it was (notionally) baked from: a box crossing the tile side x = 1 (it wraps,
// CONVENTIONS §8) and poking out of the shell's top (clipped).
GdmAsset tinyAssetWithSolid() {
    GdmAsset asset = tinyAsset(false);
    asset.solid = boxMesh({0.6f, 0.1f, 0.0f}, {1.3f, 0.7f, 0.3f}, asset.svd.height);
    return asset;
}

TEST(GdmAsset, SolidRoundTripsExactly) {
    test::ScratchDir dir("gdm-asset-solid");
    const GdmAsset asset = tinyAssetWithSolid();
    writeGdmAsset(dir / "a", asset);
    EXPECT_EQ(test::countEntries(dir / "a"), 5);  // gdm.json, weights, eigen, occupancy, solid.obj
    const std::string sidecar = readText(dir / "a" / "gdm.json");
    EXPECT_NE(sidecar.find("\"solid\""), std::string::npos) << sidecar;
    EXPECT_NE(sidecar.find("\"type\": \"obj\""), std::string::npos) << sidecar;
    const GdmAsset back = readGdmAsset(dir / "a");
    ASSERT_TRUE(back.solid.has_value());
    EXPECT_EQ(back.solid->positions, asset.solid->positions);  // %.9g round-trips every float
    EXPECT_EQ(back.solid->triangles, asset.solid->triangles);
    EXPECT_EQ(back.solid->height, asset.svd.height);
    EXPECT_EQ(back.solid->source, "test");  // the asset's source, for messages
    // Rewritten without it, the old solid.obj goes.
    writeGdmAsset(dir / "a", tinyAsset(false));
    EXPECT_EQ(test::countEntries(dir / "a"), 4);
    EXPECT_FALSE(readGdmAsset(dir / "a").solid.has_value());
}

TEST(GdmAsset, AssetWithoutSolidStillReads) {
    // An asset written before solid.obj existed: the same version 1 sidecar, no payloads.solid.
    test::ScratchDir dir("gdm-asset-nosolid");
    writeGdmAsset(dir / "a", tinyAsset(true));
    EXPECT_EQ(readText(dir / "a" / "gdm.json").find("solid"), std::string::npos);
    const GdmAsset back = readGdmAsset(dir / "a");
    EXPECT_FALSE(back.solid.has_value());
    EXPECT_TRUE(back.raw.has_value());
}

TEST(GdmAsset, SolidThatCouldNotBeReadBackIsNotWritten) {
    test::ScratchDir dir("gdm-asset-solid-bad");
    GdmAsset asset = tinyAssetWithSolid();
    asset.solid->height = 0.5;  // not the SVD's H
    std::string message = errorOf([&] { writeGdmAsset(dir / "a", asset); }, ErrorKind::InvalidInput);
    EXPECT_NE(message.find("H 0.5"), std::string::npos) << message;
    asset = tinyAssetWithSolid();
    asset.solid->triangles.pop_back();  // open
    message = errorOf([&] { writeGdmAsset(dir / "a", asset); }, ErrorKind::InvalidInput);
    EXPECT_NE(message.find("the solid: open"), std::string::npos) << message;
    EXPECT_EQ(test::countEntries(dir.path()), 0);
}

TEST(GdmAsset, MissingOrCorruptSolidIsRefusedNamingIt) {
    test::ScratchDir dir("gdm-asset-solid-corrupt");
    const fs::path a = dir / "a";
    writeGdmAsset(a, tinyAssetWithSolid());
    const std::string sidecar = readText(a / "gdm.json");
    const std::string obj = readText(a / "solid.obj");
    auto refused = [&](const std::string& expect, ErrorKind kind = ErrorKind::InvalidInput) {
        const std::string message = errorOf([&] { readGdmAsset(a); }, kind);
        EXPECT_NE(message.find(expect), std::string::npos) << message;
    };
    const std::string file = (a / "solid.obj").string();

    // Missing: unreadable is I/O, naming the file.
    fs::rename(a / "solid.obj", dir / "solid.obj");
    refused(file, ErrorKind::Io);
    fs::rename(dir / "solid.obj", a / "solid.obj");
    // Truncated, or longer than the sidecar says: the size is checked first.
    writeText(a / "solid.obj", obj.substr(0, obj.size() - 1));
    refused(file + ": " + std::to_string(obj.size() - 1) + " bytes");
    writeText(a / "solid.obj", obj + "\n");
    refused(file + ": " + std::to_string(obj.size() + 1) + " bytes");
    // The same size, but a face turned round: validateSolidMesh's refusal, naming the file.
    std::string flipped = obj;
    const auto face = flipped.find("f 1 3 4");
    ASSERT_NE(face, std::string::npos) << obj;
    flipped.replace(face, 7, "f 1 4 3");
    writeText(a / "solid.obj", flipped);
    refused(file + ": inconsistently oriented");
    // A malformed line: the file and line number.
    std::string malformed = obj;
    const auto vertex = malformed.find("\nv ");  // line 2, after the comment
    ASSERT_NE(vertex, std::string::npos) << obj;
    malformed[vertex + 3] = 'x';
    writeText(a / "solid.obj", malformed);
    refused(file + ":2: not a number");
    writeText(a / "solid.obj", obj);
    EXPECT_NO_THROW(readGdmAsset(a));

    // The sidecar's entry: type, file name, bytes, unknown keys.
    auto edit = [&](const std::string& from, const std::string& to) {
        writeText(a / "gdm.json", replaced(sidecar, from, to));
    };
    edit("\"type\": \"obj\"", "\"type\": \"ply\"");
    refused("gdm.json: payloads.solid.type");
    edit("\"file\": \"solid.obj\"", "\"file\": \"other.obj\"");
    refused("gdm.json: payloads.solid.file");
    edit("\"type\": \"obj\"", "\"type\": \"obj\", \"shape\": [1]");
    refused("gdm.json: payloads.solid.shape: unknown key");
    writeText(a / "gdm.json", sidecar);
    EXPECT_NO_THROW(readGdmAsset(a));
}

TEST(GdmAsset, RewritingWithoutRawDropsIt) {
    test::ScratchDir dir("gdm-asset-rewrite");
    writeGdmAsset(dir / "a", tinyAsset(true));
    writeGdmAsset(dir / "a", tinyAsset(false));
    EXPECT_EQ(test::countEntries(dir / "a"), 4);
    EXPECT_FALSE(readGdmAsset(dir / "a").raw.has_value());
    EXPECT_TRUE(readGdmAsset(dir / "a").albedo.empty());
}

TEST(GdmAsset, RefusesToOverwriteWhatIsNotAnAsset) {
    test::ScratchDir dir("gdm-asset-refuse");
    fs::create_directories(dir / "other");
    writeText(dir / "other" / "notes.txt", "mine");
    const std::string message =
        errorOf([&] { writeGdmAsset(dir / "other", tinyAsset(false)); }, ErrorKind::Io);
    EXPECT_NE(message.find("not a GDM asset"), std::string::npos) << message;
    writeText(dir / "file", "mine");
    errorOf([&] { writeGdmAsset(dir / "file", tinyAsset(false)); }, ErrorKind::Io);
    EXPECT_EQ(test::countEntries(dir / "other"), 1);
    EXPECT_EQ(readText(dir / "other" / "notes.txt"), "mine");
    EXPECT_EQ(test::countEntries(dir.path()), 2);  // no staging directory left
}

TEST(GdmAsset, AFailedWriteLeavesNothing) {
    test::ScratchDir dir("gdm-asset-fail");
    GdmAsset asset = tinyAsset(false);
    asset.occupancy.pop_back();  // disagrees with the dims
    errorOf([&] { writeGdmAsset(dir / "a", asset); }, ErrorKind::InvalidInput);
    EXPECT_EQ(test::countEntries(dir.path()), 0);
}

TEST(GdmAsset, CorruptionsAreRefusedNamingTheFile) {
    test::ScratchDir dir("gdm-asset-corrupt");
    const fs::path a = dir / "a";
    writeGdmAsset(a, tinyAsset(true));
    const std::string sidecar = readText(a / "gdm.json");
    auto refused = [&](const std::string& expect, ErrorKind kind = ErrorKind::InvalidInput) {
        const std::string message = errorOf([&] { readGdmAsset(a); }, kind);
        EXPECT_NE(message.find(expect), std::string::npos) << message;
    };

    // A truncated payload.
    const std::string weights = readText(a / "weights.f32");
    writeText(a / "weights.f32", weights.substr(0, weights.size() - 1));
    refused("weights.f32");
    writeText(a / "weights.f32", weights);
    // A missing payload: unreadable is I/O.
    fs::rename(a / "raw.f32", dir / "raw.f32");
    refused("raw.f32", ErrorKind::Io);
    fs::rename(dir / "raw.f32", a / "raw.f32");
    // An unknown version.
    auto edit = [&](const std::string& from, const std::string& to) {
        writeText(a / "gdm.json", replaced(sidecar, from, to));
    };
    edit("\"version\": 1", "\"version\": 2");
    refused("version");
    // A missing key, an unknown one, a wrong type, a wrong layout.
    edit("\"height\": ", "\"heigth\": ");
    refused("gdm.json: height");
    edit("\"rank\": 2", "\"rank\": \"2\"");
    refused("gdm.json: rank");
    edit("\"layout\": \"", "\"layout\": \"x");
    refused("layout");
    edit("\"format\": \"strata.gdm\"", "\"format\": \"strata.texture-set\"");
    refused("format");
    writeText(a / "gdm.json", "{ not json");
    refused("gdm.json");
    writeText(a / "gdm.json", sidecar);
    EXPECT_NO_THROW(readGdmAsset(a));
}

}  // namespace
}  // namespace strata
