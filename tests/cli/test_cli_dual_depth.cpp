// `strata dual-depth` end to end: the files match the library, the documented errors leave nothing behind.
#include "test_support.h"

#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/dual_depth.h"

#include <gtest/gtest.h>

namespace strata {
namespace {

using test::runCli;

using test::quoted;

TEST(CliDualDepth, WritesWhatTheLibraryMakes) {
    test::ScratchDir dir("cli-dual-depth");
    const auto result = runCli("dual-depth --mesh sphere --axis y --size 48 -o " + quoted(dir / "sphere"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_NE(result.output.find("packed.png"), std::string::npos) << result.output;
    ASSERT_TRUE(isDualDepth(dir / "sphere"));
    const DualDepthTexture read = readDualDepth(dir / "sphere");
    const DualDepthTexture expected = makeDualDepth(makeBuiltinMesh("sphere"), Axis::Y, 48);
    EXPECT_EQ(read.axis, Axis::Y);
    EXPECT_DOUBLE_EQ(read.depthScale, expected.depthScale);
    // The file is the library's texture at 16 bits: half a step for depths.
    EXPECT_LE(test::maxAbsDiff(read.front, expected.front), 0.5 / 65535 + 1e-7);
    EXPECT_LE(test::maxAbsDiff(read.back, expected.back), 0.5 / 65535 + 1e-7);
}

TEST(CliDualDepth, ErrorsUseTheDocumentedCodesAndWriteNothing) {
    test::ScratchDir dir("cli-dual-depth-errors");
    // 1: usage (no -o; a size out of range; an unknown axis).
    EXPECT_EQ(runCli("dual-depth --mesh sphere").exitCode, 1);
    EXPECT_EQ(runCli("dual-depth --mesh sphere --size 0 -o " + quoted(dir / "a")).exitCode, 1);
    EXPECT_EQ(runCli("dual-depth --mesh sphere --axis w -o " + quoted(dir / "a")).exitCode, 1);
    // 2: a mesh file that does not exist.
    const auto missing = runCli("dual-depth --mesh " + quoted(dir / "nope.obj") + " -o " + quoted(dir / "a"));
    EXPECT_EQ(missing.exitCode, 2);
    EXPECT_NE(missing.output.find("nope.obj"), std::string::npos) << missing.output;
    // 3: a flat mesh, and an unknown built-in.
    const auto flat = runCli("dual-depth --mesh plane -o " + quoted(dir / "a"));
    EXPECT_EQ(flat.exitCode, 3);
    EXPECT_NE(flat.output.find("flat along z"), std::string::npos) << flat.output;
    EXPECT_EQ(runCli("dual-depth --mesh blob -o " + quoted(dir / "a")).exitCode, 3);
    // 5: a mesh format Strata does not read.
    test::writeBytes(dir / "m.stl", "solid x\nendsolid x\n");
    EXPECT_EQ(runCli("dual-depth --mesh " + quoted(dir / "m.stl") + " -o " + quoted(dir / "a")).exitCode, 5);
    EXPECT_EQ(test::countEntries(dir.path()), 1);  // only m.stl: no output, no staging directory
}

}  // namespace
}  // namespace strata
