// Dual-depth relief textures (dual_depth.h): sampling against an analytic sphere, exact coverage of texel
// centres on triangle edges, the file round trip and the errors.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/dual_depth.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <string>

namespace strata {
namespace {

constexpr double kSixteenBitStep = 1.0 / 65535.0;
constexpr double kPi = std::numbers::pi;

// Expects `call` to throw Error of `kind` with every one of `words` in its message.
template <typename F>
void expectError(F&& call, ErrorKind kind, std::initializer_list<std::string> words) {
    try {
        call();
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        for (const std::string& word : words)
            EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what() << " lacks " << word;
    }
}

// The built-in sphere (radius 0.5 at the origin) at the default tessellation 16: 64 segments around and
// 32 from pole to pole, so every triangle spans at most delta = pi/32 of latitude and of longitude.
constexpr double kRadius = 0.5;
constexpr double kDelta = kPi / 32.0;
// Every triangle's corners lie on the sphere and within an angle delta of each other along each direction,
// so its plane is at least r cos(delta) from the centre: the polygonal surface lies between the spheres of
// radii r (1 - (1 - cos delta)) and r. r (1 - cos pi/32) = 0.0024; plus half a 16-bit step of slack for
// float positions.
const double kDeficit = kRadius * (1.0 - std::cos(kDelta)) + 1e-5;

TEST(DualDepth, SphereMatchesTheAnalyticSurface) {
    const Mesh sphere = makeBuiltinMesh("sphere");
    constexpr int kSize = 128;
    const DualDepthTexture texture = makeDualDepth(sphere, Axis::Z, kSize);
    ASSERT_EQ(texture.front.width(), kSize);
    ASSERT_EQ(texture.back.height(), kSize);
    ASSERT_EQ(texture.normal.channels(), 3);
    EXPECT_EQ(texture.axis, Axis::Z);
    // Poles and the equator ring are vertices: the bounds are exactly [-0.5, 0.5]^3, so S = E / L = 1.
    EXPECT_NEAR(texture.depthScale, 1.0, 1e-6);

    // The silhouette is the equator's 64-gon: inside its inradius r cos(pi/64) every line hits, outside r
    // none does.
    const double inradius = kRadius * std::cos(kPi / 64.0);
    int hits = 0, misses = 0;
    double worstRadius = 0.0, worstNormal = 0.0, worstInteriorDepth = 0.0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            // Texel centre in world units: footprint [-0.5, 0.5]^2, row 0 at the top (+y).
            const double x = -0.5 + (i + 0.5) / kSize;
            const double y = 0.5 - (j + 0.5) / kSize;
            const double rho = std::hypot(x, y);
            const double front = texture.front.at(i, j), back = texture.back.at(i, j);
            const bool hit = front <= back;
            if (rho < inradius - 1e-6) {
                EXPECT_TRUE(hit) << i << ", " << j;
            }
            if (rho > kRadius + 1e-6) {
                EXPECT_FALSE(hit) << i << ", " << j;
                EXPECT_EQ(front, 1.0);
                EXPECT_EQ(back, 0.0);
                EXPECT_EQ(texture.normal.at(i, j, 2), 1.0f);
            }
            if (!hit) {
                ++misses;
                continue;
            }
            ++hits;
            // d = (max_z - z) / E with max_z = 0.5, E = 1.
            const double frontZ = 0.5 - front, backZ = 0.5 - back;
            // Both points lie on the polygonal sphere: radius in [r - deficit, r].
            for (const double z : {frontZ, backZ}) {
                const double radius = std::sqrt(rho * rho + z * z);
                EXPECT_LE(radius, kRadius + 1e-5) << i << ", " << j;
                EXPECT_GE(radius, kRadius - kDeficit) << i << ", " << j;
                worstRadius = std::max(worstRadius, std::abs(radius - kRadius));
            }
            EXPECT_GE(frontZ, backZ);
            // Away from the silhouette the depth itself is close: the true surface is at sqrt(r^2 - rho^2),
            // and a radial gap of at most kDeficit along a line at angle theta to the normal is at most
            // kDeficit / cos(theta) along z; rho <= 0.8 r keeps cos(theta) >= 0.6.
            if (rho <= 0.8 * kRadius) {
                const double trueZ = std::sqrt(kRadius * kRadius - rho * rho);
                EXPECT_NEAR(frontZ, trueZ, kDeficit / 0.6) << i << ", " << j;
                EXPECT_NEAR(backZ, -trueZ, kDeficit / 0.6) << i << ", " << j;
                worstInteriorDepth = std::max(worstInteriorDepth, std::abs(frontZ - trueZ));
                // The vertex normals are the analytic p_i / r, so the interpolated normal sum w_i p_i / r
                // is parallel to the interpolated point P itself: equal to P / |P| up to float rounding
                // (1e-3 rad; the surface normal of the flat triangle would be off by up to delta).
                const glm::dvec3 analytic = glm::normalize(glm::dvec3(x, y, frontZ));
                const glm::dvec3 stored(texture.normal.at(i, j, 0), texture.normal.at(i, j, 1),
                                        texture.normal.at(i, j, 2));
                EXPECT_NEAR(glm::length(stored), 1.0, 1e-6);
                const double angle = std::acos(std::clamp(glm::dot(analytic, stored), -1.0, 1.0));
                EXPECT_LE(angle, 1e-3) << i << ", " << j;
                worstNormal = std::max(worstNormal, angle);
            }
            EXPECT_GE(texture.normal.at(i, j, 2), 0.0f);  // facing up
        }
    // The disc of radius 0.5 covers pi/4 of the footprint.
    EXPECT_NEAR(double(hits) / (kSize * kSize), kPi / 4.0, 0.01);
    EXPECT_GT(misses, 0);
    RecordProperty("worst_radius_error", std::to_string(worstRadius));
    RecordProperty("worst_interior_depth_error", std::to_string(worstInteriorDepth));
    RecordProperty("worst_normal_degrees", std::to_string(worstNormal * 180.0 / kPi));
}

TEST(DualDepth, AxesPermuteTheTileFrame) {
    // The sphere is symmetric: along x and y it samples the same as along z, up to the frame. Its front
    // normal at the centre texel points along the axis: (0, 0, 1) in the tile frame for every axis.
    const Mesh sphere = makeBuiltinMesh("sphere");
    for (const Axis axis : {Axis::X, Axis::Y, Axis::Z}) {
        const DualDepthTexture t = makeDualDepth(sphere, axis, 33);
        EXPECT_NEAR(t.depthScale, 1.0, 1e-6) << toString(axis);
        EXPECT_NEAR(t.front.at(16, 16), 0.0, kDeficit) << toString(axis);
        EXPECT_NEAR(t.back.at(16, 16), 1.0, kDeficit) << toString(axis);
        EXPECT_NEAR(t.normal.at(16, 16, 2), 1.0, 1e-3) << toString(axis);
    }
    // A box that is longer along x shows it: along z the footprint is 2 x 1 (L = 2, E = 1).
    Mesh box = makeBuiltinMesh("cube", {2});
    for (MeshVertex& v : box.vertices) v.position.x *= 2.0f;
    const DualDepthTexture alongZ = makeDualDepth(box, Axis::Z, 8);
    EXPECT_NEAR(alongZ.depthScale, 0.5, 1e-6);
    // T = x spans the whole width; B = y only the middle half of the rows.
    EXPECT_EQ(alongZ.front.at(0, 3), 0.0f);
    EXPECT_EQ(alongZ.front.at(0, 0), 1.0f);  // a miss
    const DualDepthTexture alongX = makeDualDepth(box, Axis::X, 8);
    EXPECT_NEAR(alongX.depthScale, 2.0, 1e-6);  // E = 2 along x, L = 1
}

TEST(DualDepth, TexelCentresOnTriangleEdgesAreNotLost) {
    // Cube faces are 8 x 8 grids of 1/8 cells split along a diagonal; at 16 texels across, every cell holds
    // 2 x 2 texel centres, two of them exactly on its diagonal. Every line must hit the top (d = 0) and
    // the bottom (d = 1), with the face normal.
    const Mesh cube = makeBuiltinMesh("cube", {8});
    const DualDepthTexture texture = makeDualDepth(cube, Axis::Z, 16);
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
            EXPECT_EQ(texture.front.at(i, j), 0.0f) << i << ", " << j;
            EXPECT_EQ(texture.back.at(i, j), 1.0f) << i << ", " << j;
            EXPECT_NEAR(texture.normal.at(i, j, 2), 1.0f, 1e-6f) << i << ", " << j;
        }
}

TEST(DualDepth, IsDeterministic) {
    const Mesh teapot = makeBuiltinMesh("teapot", {8});
    const DualDepthTexture a = makeDualDepth(teapot, Axis::Y, 96);
    const DualDepthTexture b = makeDualDepth(teapot, Axis::Y, 96);
    EXPECT_EQ(a.front, b.front);
    EXPECT_EQ(a.back, b.back);
    EXPECT_EQ(a.normal, b.normal);
}

TEST(DualDepth, RoundTripsAt16Bits) {
    test::ScratchDir dir("dual-depth");
    const DualDepthTexture texture = makeDualDepth(makeBuiltinMesh("torus"), Axis::Z, 64);
    const auto written = writeDualDepth(dir / "torus", texture, "torus");
    ASSERT_EQ(written.size(), 2u);
    EXPECT_EQ(written[0].filename(), "packed.png");
    EXPECT_EQ(written[1].filename(), "strata.json");
    EXPECT_EQ(test::countEntries(dir.path()), 1);  // no staging directory or temporary file left
    EXPECT_TRUE(isDualDepth(dir / "torus"));
    EXPECT_TRUE(isDualDepth(dir / "torus" / "strata.json"));
    const ImageInfo info = readImageInfo(dir / "torus" / "packed.png");
    EXPECT_EQ(info.channels, 4);
    EXPECT_EQ(info.bitDepth, 16);

    for (const auto& path : {dir / "torus", dir / "torus" / "strata.json"}) {
        const DualDepthTexture back = readDualDepth(path);
        EXPECT_EQ(back.axis, Axis::Z);
        EXPECT_DOUBLE_EQ(back.depthScale, texture.depthScale);
        // Depths are stored as they are: half a 16-bit step at most.
        EXPECT_LE(test::maxAbsDiff(back.front, texture.front), 0.5 * kSixteenBitStep + 1e-7);
        EXPECT_LE(test::maxAbsDiff(back.back, texture.back), 0.5 * kSixteenBitStep + 1e-7);
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                // n * 0.5 + 0.5 at half a step: one step after decoding.
                for (int c = 0; c < 2; ++c)
                    EXPECT_NEAR(back.normal.at(x, y, c), texture.normal.at(x, y, c), kSixteenBitStep + 1e-7);
                // nz = sqrt(1 - nx^2 - ny^2) moves by (|nx| + |ny|) / nz per unit of error in nx, ny: at
                // nz >= 0.1 at most sqrt(2) / 0.1 steps.
                if (texture.normal.at(x, y, 2) >= 0.1f) {
                    EXPECT_NEAR(back.normal.at(x, y, 2), texture.normal.at(x, y, 2),
                                std::sqrt(2.0) / 0.1 * kSixteenBitStep + 1e-6);
                }
            }
    }
}

TEST(DualDepth, RefusesBadParameters) {
    const Mesh sphere = makeBuiltinMesh("sphere");
    expectError([&] { makeDualDepth(sphere, Axis::Z, 0); }, ErrorKind::InvalidInput, {"size", "0"});
    expectError([&] { makeDualDepth(sphere, Axis::Z, Image::kMaxDimension + 1); }, ErrorKind::InvalidInput,
                {"size", "16385"});
    // The plane is flat along z (E = 0) ...
    expectError([&] { makeDualDepth(makeBuiltinMesh("plane"), Axis::Z, 16); }, ErrorKind::InvalidInput,
                {"plane", "flat along z"});
    // ... and a (degenerate) vertical segment is flat across z: its footprint is a point (L = 0).
    Mesh strip;
    strip.name = "strip";
    for (const glm::vec3 p : {glm::vec3(0, 0, 0), glm::vec3(0, 0, 0.5f), glm::vec3(0, 0, 1)}) {
        MeshVertex v;
        v.position = p;
        strip.vertices.push_back(v);
    }
    strip.indices = {0, 1, 2};
    expectError([&] { makeDualDepth(strip, Axis::Z, 16); }, ErrorKind::InvalidInput,
                {"strip", "flat across z"});
    Mesh empty;
    empty.name = "empty";
    expectError([&] { makeDualDepth(empty, Axis::Z, 16); }, ErrorKind::InvalidInput,
                {"empty", "no triangles"});
    EXPECT_EQ(parseAxis("y"), Axis::Y);
    expectError([] { parseAxis("w"); }, ErrorKind::InvalidInput, {"axis", "w"});
}

TEST(DualDepth, RefusesBadFiles) {
    test::ScratchDir dir("dual-depth-bad");
    const DualDepthTexture texture = makeDualDepth(makeBuiltinMesh("sphere", {2}), Axis::Z, 8);
    writeDualDepth(dir / "ok", texture, "sphere");

    expectError([&] { readDualDepth(dir / "missing"); }, ErrorKind::Io, {"missing"});
    EXPECT_FALSE(isDualDepth(dir / "missing"));

    // Another format: named, with its key.
    std::filesystem::create_directories(dir / "set");
    test::writeBytes(dir / "set" / "strata.json", R"({"format": "strata.texture-set", "format_version": 1})");
    expectError([&] { readDualDepth(dir / "set"); }, ErrorKind::InvalidInput,
                {"set/strata.json", "format", "strata.texture-set"});
    EXPECT_FALSE(isDualDepth(dir / "set"));

    // Not JSON at all.
    std::filesystem::create_directories(dir / "junk");
    test::writeBytes(dir / "junk" / "strata.json", "{not json");
    expectError([&] { readDualDepth(dir / "junk"); }, ErrorKind::InvalidInput, {"junk/strata.json", "JSON"});
    EXPECT_FALSE(isDualDepth(dir / "junk"));

    // A sidecar whose size does not match packed.png: the image is named.
    std::filesystem::create_directories(dir / "size");
    std::filesystem::copy_file(dir / "ok" / "packed.png", dir / "size" / "packed.png");
    test::writeBytes(dir / "size" / "strata.json",
                     R"({"format": "strata.dual-depth", "version": 1, "width": 16, "height": 8,
                         "depth_scale": 1, "axis": "z", "source": "sphere"})");
    expectError([&] { readDualDepth(dir / "size"); }, ErrorKind::InvalidInput, {"packed.png", "16x8", "8x8"});

    // A bad key: named.
    test::writeBytes(dir / "size" / "strata.json",
                     R"({"format": "strata.dual-depth", "version": 1, "width": 8, "height": 8,
                         "depth_scale": -1, "axis": "z", "source": "sphere"})");
    expectError([&] { readDualDepth(dir / "size"); }, ErrorKind::InvalidInput,
                {"strata.json", "depth_scale"});
    test::writeBytes(dir / "size" / "strata.json",
                     R"({"format": "strata.dual-depth", "version": 1, "width": 8, "height": 8,
                         "depth_scale": 1, "axis": "up", "source": "sphere"})");
    expectError([&] { readDualDepth(dir / "size"); }, ErrorKind::InvalidInput, {"strata.json", "axis", "up"});

    // A 3-channel packed.png.
    writePng(dir / "size" / "packed.png", Image(8, 8, 3, 0.5f));
    test::writeBytes(dir / "size" / "strata.json",
                     R"({"format": "strata.dual-depth", "version": 1, "width": 8, "height": 8,
                         "depth_scale": 1, "axis": "z", "source": "sphere"})");
    expectError([&] { readDualDepth(dir / "size"); }, ErrorKind::InvalidInput, {"packed.png", "4 channels"});

    // Writing over a file that is not a directory: Io, nothing changed.
    test::writeBytes(dir / "taken", "x");
    expectError([&] { writeDualDepth(dir / "taken", texture, "sphere"); }, ErrorKind::Io, {"taken"});
    EXPECT_EQ(test::countEntries(dir.path()), 5);  // ok, set, junk, size, taken: no staging left
}

}  // namespace
}  // namespace strata
