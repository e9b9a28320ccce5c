// `strata gdm bake` and `strata info` on a GDM asset end to end; the documented errors write nothing.
#include "test_support.h"

#include "strata/gdm/gdm.h"
#include "strata/gdm/gdm_asset.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <fstream>

namespace strata {
namespace {

using test::runCli;

using test::quoted;

TEST(CliGdm, BakesAReadableAssetThatInfoDescribes) {
    test::ScratchDir dir("cli-gdm");
    const auto bake = runCli("gdm bake --meso grid --size 16x16x4 --dirs 4x8 --rank 4 --keep-raw -o " +
                             quoted(dir / "out"));
    ASSERT_EQ(bake.exitCode, 0) << bake.output;
    EXPECT_EQ(test::countEntries(dir.path()), 1);  // no staging directory left
    const GdmAsset asset = readGdmAsset(dir / "out");
    EXPECT_EQ(asset.svd.dims, (GdmDims{16, 16, 4, 4, 8}));
    EXPECT_EQ(asset.svd.rank, 4);
    EXPECT_EQ(asset.source, "meso grid");
    ASSERT_TRUE(asset.raw.has_value());
    std::size_t inside = 0;
    for (std::uint8_t o : asset.occupancy) inside += o;
    EXPECT_GT(inside, 0u);  // the grid's rods fill some voxel centres, not all
    EXPECT_LT(inside, asset.occupancy.size());
    EXPECT_EQ(asset.albedo.size(), asset.occupancy.size() * 3);  // a built-in has colours
    ASSERT_TRUE(asset.solid.has_value());                        // always stored, for `gdm trace --reference`
    EXPECT_EQ(asset.solid->height, asset.svd.height);
    EXPECT_GT(asset.solid->triangles.size(), 0u);

    const auto info = runCli("info " + quoted(dir / "out"));
    ASSERT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("GDM asset"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("16x16x4 voxels, 4x8 directions"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("meso grid"), std::string::npos) << info.output;
    EXPECT_NE(
        info.output.find("solid.obj     : " + std::to_string(asset.solid->triangles.size()) + " triangles"),
        std::string::npos)
        << info.output;
    // The signed distance volume: a float per voxel.
    ASSERT_EQ(asset.distance.size(), asset.occupancy.size());
    EXPECT_NE(info.output.find("distance.f32  : " + std::to_string(asset.distance.size() * 4) + " bytes"),
              std::string::npos)
        << info.output;
}

// Distance from `origin` along unit `direction` to the sphere (centre, radius), or -1 if it misses.
double sphereDistance(const glm::dvec3& origin, const glm::dvec3& direction, const glm::dvec3& centre,
                      double radius) {
    const glm::dvec3 offset = origin - centre;
    const double b = glm::dot(offset, direction);
    const double c = glm::dot(offset, offset) - radius * radius;
    const double discriminant = b * b - c;
    if (discriminant < 0.0) return -1.0;
    const double t = -b - std::sqrt(discriminant);
    return t >= 0.0 ? t : -1.0;
}

TEST(CliGdm, BakesAnOpenVdbLevelSet) {
    // A ball written as OpenVDB writes level sets (as Blender and Houdini do): a FloatGrid of class level
    // set, in tile units, negative inside.
    test::ScratchDir dir("cli-gdm-vdb");
    openvdb::initialize();
    const glm::dvec3 centre(0.5, 0.5, 0.125);
    constexpr double kRadius = 0.1;
    constexpr double kVoxel = 1.0 / 128;
    openvdb::FloatGrid::Ptr ball = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        float(kRadius), openvdb::Vec3f(0.5f, 0.5f, 0.125f), float(kVoxel));
    ball->setName("ball");
    openvdb::io::File((dir / "ball.vdb").string()).write({ball});
    const auto bake = runCli("gdm bake --vdb " + quoted(dir / "ball.vdb") +
                             " --height 0.25 --size 16x16x4 --dirs 4x8 --keep-raw -o " + quoted(dir / "out"));
    ASSERT_EQ(bake.exitCode, 0) << bake.output;
    const GdmAsset asset = readGdmAsset(dir / "out");
    EXPECT_EQ(asset.source, (dir / "ball.vdb").string());
    ASSERT_TRUE(asset.raw.has_value());
    const Gdm& gdm = *asset.raw;
    int compared = 0;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) {
                const glm::dvec3 p = gdmVoxelCentre(gdm.dims, gdm.height, i, j, k);
                const double inside = glm::length(p - centre) - kRadius;
                // The mesh of the level set lies within about a tenth of its voxel of the sphere; centres
                // closer than one voxel to the surface are not asserted.
                if (std::abs(inside) < kVoxel) continue;
                EXPECT_EQ(asset.occupancy[std::size_t((k * 16 + j) * 16 + i)], inside < 0.0 ? 1 : 0)
                    << i << " " << j << " " << k;
                if (inside < 0.0) continue;
                for (int t = 0; t < 4; ++t)
                    for (int s = 0; s < 8; ++s) {
                        const glm::dvec3 direction = gdmDirection(gdm.dims, t, s);
                        const double d = sphereDistance(p, direction, centre, kRadius);
                        const float baked = gdm.at(i, j, k, t, s);
                        // Rays that meet this ball (no copy one tile away lies between a voxel centre and
                        // it), and not near its rim, where the faceted sphere and the true one part ways.
                        if (d < 0.0) continue;
                        const double miss = glm::length(glm::cross(centre - p, direction));
                        if (kRadius - miss < 4 * kVoxel) continue;
                        // A chord through the faceted sphere: within a voxel of the true one.
                        EXPECT_NEAR(double(baked), d, kVoxel)
                            << i << " " << j << " " << k << " " << t << " " << s;
                        ++compared;
                    }
            }
    EXPECT_GT(compared, 50);

    // A .vdb without a level set: exit 3, naming the file; nothing written.
    openvdb::FloatGrid::Ptr fog = openvdb::FloatGrid::create(0.0f);
    fog->setGridClass(openvdb::GRID_FOG_VOLUME);
    fog->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    openvdb::io::File((dir / "fog.vdb").string()).write({fog});
    const auto refused =
        runCli("gdm bake --vdb " + quoted(dir / "fog.vdb") + " --height 0.25 -o " + quoted(dir / "fog"));
    EXPECT_EQ(refused.exitCode, 3) << refused.output;
    EXPECT_NE(refused.output.find("fog.vdb: holds no level-set FloatGrid"), std::string::npos)
        << refused.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "fog"));
}

TEST(CliGdm, ErrorsAreDocumentedCodesAndWriteNothing) {
    test::ScratchDir dir("cli-gdm-errors");
    const std::string out = " -o " + quoted(dir / "out");
    const std::string small = "gdm bake --meso grid --size 16x16x4 --dirs 4x8";
    struct Case {
        std::string args;
        int code;
        const char* mentions;
    };
    const Case cases[] = {
        {"gdm bake --meso grid --height 0" + out, 3, "--height"},
        {"gdm bake --meso grid --height -1" + out, 3, "--height"},
        {"gdm bake --meso grid --size 0x16x4" + out, 3, "Nx"},
        {"gdm bake --meso grid --dirs 4x0" + out, 3, "Nphi"},
        {"gdm bake --meso grid --size 64x64" + out, 1, "--size"},
        {"gdm bake --meso grid --size 64by64by16" + out, 1, "--size"},
        {"gdm bake --meso grid --size 4096x4096x256" + out, 3, "MiB"},  // refused before allocating
        {small + " --rank 99" + out, 3, "--rank"},
        {small + " --layout diagonal" + out, 1, "--layout"},
        {"gdm bake --meso tweed" + out, 3, "tweed"},
        {"gdm bake --mesh " + quoted(dir / "missing.obj") + " --height 0.25" + out, 2, "missing.obj"},
        {"gdm bake --mesh " + quoted(dir / "missing.obj") + out, 1, "--height"},
        {"gdm bake --meso grid --mesh a.obj --height 0.25" + out, 1, "exactly one"},
        {small, 1, "-o"},
        {"gdm", 1, ""},
    };
    for (const Case& c : cases) {
        const auto result = runCli(c.args);
        EXPECT_EQ(result.exitCode, c.code) << c.args << "\n" << result.output;
        EXPECT_NE(result.output.find(c.mentions), std::string::npos) << c.args << "\n" << result.output;
    }
    EXPECT_EQ(test::countEntries(dir.path()), 0);

    // A directory that is not an asset is never overwritten.
    std::filesystem::create_directories(dir / "mine");
    std::ofstream(dir / "mine" / "notes.txt") << "mine";
    EXPECT_EQ(runCli(small + " -o " + quoted(dir / "mine")).exitCode, 2);
    EXPECT_EQ(test::countEntries(dir / "mine"), 1);
    EXPECT_EQ(test::countEntries(dir.path()), 1);
}

}  // namespace
}  // namespace strata
