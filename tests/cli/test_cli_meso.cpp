// `strata meso` end to end: the list, the two outputs, and the documented errors, which write nothing.
#include "test_support.h"

#include "strata/image/image_io.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace strata {
namespace {

using test::runCli;

using test::quoted;

TEST(CliMeso, ListsTheFiveBuiltIns) {
    const auto result = runCli("meso --list");
    ASSERT_EQ(result.exitCode, 0) << result.output;
    for (const char* name : {"weave", "chain", "grid", "scales", "bark"})
        EXPECT_NE(result.output.find(name), std::string::npos) << name;
}

TEST(CliMeso, WritesTheMeshAndThePreview) {
    test::ScratchDir dir("cli-meso");
    const auto result =
        runCli("meso grid --height 0.3 --resolution 16 --preview-size 48 -o " + quoted(dir / "out"));
    ASSERT_EQ(result.exitCode, 0) << result.output;
    EXPECT_EQ(test::countEntries(dir / "out"), 2);  // mesh.obj, preview.png, nothing else (no staging left)
    EXPECT_EQ(test::countEntries(dir.path()), 1);
    std::ifstream obj(dir / "out" / "mesh.obj");
    std::stringstream text;
    text << obj.rdbuf();
    EXPECT_NE(text.str().find("# strata solid mesh: grid"), std::string::npos);
    EXPECT_NE(text.str().find("H = 0.3"), std::string::npos);
    EXPECT_NE(text.str().find("\nf "), std::string::npos);
    const Image preview = readImage(dir / "out" / "preview.png");
    EXPECT_EQ(preview.width(), 48);
    EXPECT_EQ(preview.height(), 48);
    EXPECT_EQ(preview.channels(), 3);
}

TEST(CliMeso, ErrorsAreDocumentedCodesAndWriteNothing) {
    test::ScratchDir dir("cli-meso-errors");
    const auto unknown = runCli("meso tweed -o " + quoted(dir / "out"));
    EXPECT_EQ(unknown.exitCode, 3) << unknown.output;  // invalid input
    EXPECT_NE(unknown.output.find("tweed"), std::string::npos) << unknown.output;
    EXPECT_NE(unknown.output.find("weave"), std::string::npos) << unknown.output;  // the known names
    for (const char* height : {"0", "-0.25"}) {
        const auto bad = runCli(std::string("meso weave --height ") + height + " -o " + quoted(dir / "out"));
        EXPECT_EQ(bad.exitCode, 3) << bad.output;
        EXPECT_NE(bad.output.find("--height"), std::string::npos) << bad.output;
    }
    EXPECT_EQ(runCli("meso weave --resolution 2 -o " + quoted(dir / "out")).exitCode, 1);  // out of range
    EXPECT_EQ(runCli("meso weave").exitCode, 1);                                           // no -o
    EXPECT_EQ(runCli("meso -o " + quoted(dir / "out")).exitCode, 1);                       // no name
    EXPECT_EQ(test::countEntries(dir.path()), 0);
}

}  // namespace
}  // namespace strata
