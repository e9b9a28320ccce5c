// `strata cone-map` end to end: the file holds exactly what the `cone` technique reads (packConeMap), in
// the layout its sidecar describes, and the documented errors write nothing.
#include "test_support.h"

#include "strata/image/image_io.h"
#include "strata/relief/cone_map.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace strata {
namespace {

using test::runCli;

using test::quoted;

// A 40 x 24 map (no power of two, not square): flat at d = 0.25 with one deep texel at file column 10,
// row 5, and a ramp in its right half.
Image testDepth() {
    Image depth(40, 24, 1, 0.25f);
    for (int y = 0; y < 24; ++y)
        for (int x = 24; x < 40; ++x) depth.at(x, y) = 0.25f + 0.05f * static_cast<float>(x - 24);
    depth.at(10, 5) = 0.75f;
    return depth;
}

TEST(CliConeMap, WritesWhatTheConeTechniqueReadsInTheDocumentedLayout) {
    test::ScratchDir dir("cli-cone-map");
    writePng(dir / "d.png", testDepth());
    const auto result = runCli("cone-map " + quoted(dir / "d.png") + " -o " + quoted(dir / "cone.png"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_EQ(readImageInfo(dir / "cone.png").bitDepth, 16);
    const Image file = readImage(dir / "cone.png");
    ASSERT_EQ(file.channels(), 2);
    ASSERT_EQ(file.width(), 40);
    ASSERT_EQ(file.height(), 24);
    std::ifstream stream(dir / "cone.png.json");
    const nlohmann::json sidecar = nlohmann::json::parse(stream);
    EXPECT_EQ(sidecar["format"], "strata.cone-map");
    EXPECT_EQ(sidecar["max_ratio"].get<double>(), 40.0);  // the larger side, by default
    EXPECT_EQ(sidecar["depth_levels"].get<int>(), 64);

    // Exactly the library's packing of the 16-bit depth, rows flipped to file order.
    const PackedConeMap packed = packConeMap(readImage(dir / "d.png"));
    for (int r = 0; r < 24; ++r)
        for (int i = 0; i < 40; ++i)
            for (int c = 0; c < 2; ++c)
                ASSERT_EQ(std::lround(file.at(i, r, c) * 65535.0f),
                          std::lround(packed.texels.at(i, 23 - r, c) * 65535.0f))
                    << "file texel " << i << ", " << r << " channel " << c;

    // The sidecar's layout: file texel (i, r) is the cell between file columns i, i + 1 and rows r, r - 1.
    // The deep texel (10, 5) is a corner of the cells (9..10, 5..6) only: their highest point is the flat
    // 0.25 and their cone is narrow (the pit's rim rises above its bottom); the other cells of the flat
    // left part keep the cap (nothing anywhere is higher than 0.25).
    for (int r = 0; r < 24; ++r) {
        for (int i = 0; i < 22; ++i) {
            const bool aroundPit = (i == 9 || i == 10) && (r == 5 || r == 6);
            const float ratio =
                decodeConeRatio(static_cast<std::uint16_t>(std::lround(file.at(i, r, 1) * 65535.0f)), 40.0f);
            EXPECT_NEAR(file.at(i, r, 0), 0.25f, 1.0f / 65535.0f) << i << ", " << r;
            // A lone pit 0.5 deep: along a diagonal from it the depth rises at 0.5 sqrt(2) per texel, the
            // steepest slope anywhere, so the true cone is 1 / (0.5 sqrt(2)) = sqrt(2) texels per unit of
            // depth (ConeMap.LonePitIsExact: 1 / sqrt(2) for a pit 1 deep); 16-bit rounding takes < 1e-3.
            if (aroundPit)
                EXPECT_NEAR(ratio, std::sqrt(2.0f), 2e-3f) << "cell " << i << ", " << r << " touches the pit";
            else
                EXPECT_EQ(ratio, 40.0f) << "cell " << i << ", " << r;
        }
    }
}

TEST(CliConeMap, ErrorsAreDocumentedCodesAndLeaveNothing) {
    test::ScratchDir dir("cli-cone-map-errors");
    writePng(dir / "d.png", testDepth());
    const std::string depth = quoted(dir / "d.png");
    const std::string out = " -o " + quoted(dir / "cone.png");
    EXPECT_EQ(runCli("cone-map " + depth).exitCode, 1);  // no -o
    EXPECT_EQ(runCli("cone-map " + depth + " -o " + quoted(dir / "cone.exr")).exitCode, 1);
    EXPECT_EQ(runCli("cone-map " + depth + out + " --depth-levels 0").exitCode, 1);
    EXPECT_EQ(runCli("cone-map " + depth + out + " --max-ratio -1").exitCode, 1);
    const auto missing = runCli("cone-map " + quoted(dir / "missing.png") + out);
    EXPECT_EQ(missing.exitCode, 2) << missing.output;
    EXPECT_NE(missing.output.find("missing.png"), std::string::npos) << missing.output;
    test::writeBytes(dir / "text.png", "not a png");
    EXPECT_EQ(runCli("cone-map " + quoted(dir / "text.png") + out).exitCode, 3);
    // The output may not be the input: refused, and the input is left as it was.
    const Image before = readImage(dir / "d.png");
    const auto overwrite = runCli("cone-map " + depth + " -o " + depth);
    EXPECT_EQ(overwrite.exitCode, 2) << overwrite.output;
    const Image after = readImage(dir / "d.png");
    EXPECT_TRUE(std::equal(after.pixels().begin(), after.pixels().end(), before.pixels().begin(),
                           before.pixels().end()));
    EXPECT_FALSE(std::filesystem::exists(dir / "cone.png"));
    EXPECT_FALSE(std::filesystem::exists(dir / "cone.png.json"));
}

}  // namespace
}  // namespace strata
