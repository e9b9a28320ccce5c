// The preview picture and the `strata meso` output directory.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gdm/mesostructure_preview.h"
#include "strata/image/image_io.h"

#include <gtest/gtest.h>

#include <fstream>

namespace strata {
namespace {

TEST(MesostructurePreview, ShowsTheTilesOverTheBackground) {
    MesostructurePreviewParams params;
    params.size = 32;
    const Image image = renderMesostructurePreview(makeMesostructure("weave"), params);
    ASSERT_EQ(image.width(), 32);
    ASSERT_EQ(image.channels(), 3);
    // The corner shows the background's grey gradient (R < G < B, R >= 0.55); the centre a yarn: indigo
    // (B clearly above R) or cream (R above B). Colours are sRGB in [0, 1].
    EXPECT_LT(image.at(0, 0, 0), image.at(0, 0, 2));
    EXPECT_GT(image.at(0, 0, 0), 0.5f);
    const float r = image.at(16, 16, 0), b = image.at(16, 16, 2);
    EXPECT_GT(std::abs(r - b), 0.05f) << r << " " << b;
    for (float value : image.pixels()) {
        EXPECT_GE(value, 0.0f);
        EXPECT_LE(value, 1.0f);
    }
    params.size = 8;
    EXPECT_THROW(renderMesostructurePreview(makeMesostructure("weave"), params), Error);
}

TEST(MesostructurePreview, OutputsAreWrittenAllOrNothing) {
    test::ScratchDir dir("meso-outputs");
    const Mesostructure grid = makeMesostructure("grid");
    const SolidMesh mesh = meshMesostructure(grid, 16);
    MesostructurePreviewParams params;
    params.size = 16;
    const Image preview = renderMesostructurePreview(grid, params);
    const auto written = writeMesostructureOutputs(dir / "a" / "b", mesh, preview);
    ASSERT_EQ(written.size(), 2u);
    EXPECT_EQ(written[0], dir / "a" / "b" / "mesh.obj");
    EXPECT_EQ(readImage(written[1]).width(), 16);
    EXPECT_EQ(test::countEntries(dir.path()), 1);  // no staging directory left beside it
    // Under a file: nothing can be created, and nothing is left.
    test::writeBytes(dir / "file", "x");
    try {
        writeMesostructureOutputs(dir / "file" / "out", mesh, preview);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io) << e.what();
    }
    EXPECT_EQ(test::countEntries(dir.path()), 2);
}

}  // namespace
}  // namespace strata
