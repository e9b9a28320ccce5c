// `strata gdm bake` and `strata info` on a GDM asset end to end; the documented errors write nothing.
#include "test_support.h"

#include "strata/gdm/gdm_asset.h"

#include <gtest/gtest.h>

#include <fstream>

namespace strata {
namespace {

using test::runCli;

std::string quoted(const std::filesystem::path& path) {
    return "\"" + path.string() + "\"";
}

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
