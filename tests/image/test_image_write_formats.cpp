// Output formats by extension (image_io.h): checkOutputExtension refuses before any work, writeImage writes
// the format the extension names (never PNG bytes under a .jpg name).
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"

#include <gtest/gtest.h>

namespace strata {
namespace {

TEST(ImageWriteFormats, CheckOutputExtensionNamesTheFlagAndTheAllowedOnes) {
    EXPECT_EQ(checkOutputExtension("a/b.PNG", "-o", {ImageFormat::Png}), ImageFormat::Png);
    EXPECT_EQ(checkOutputExtension("b.jpeg", "-o", {ImageFormat::Png, ImageFormat::Jpeg}), ImageFormat::Jpeg);
    try {
        checkOutputExtension("x.tif", "render: -o", {ImageFormat::Png, ImageFormat::Exr, ImageFormat::Jpeg});
        FAIL() << "x.tif accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Usage);
        EXPECT_STREQ(e.what(), "render: -o x.tif: cannot write .tif; use .png, .exr or .jpg");
    }
    try {
        checkOutputExtension("x.exr", "ao: -o", {ImageFormat::Png});
        FAIL() << "x.exr accepted";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "ao: -o x.exr: cannot write .exr; use .png");
    }
}

TEST(ImageWriteFormats, WriteImageWritesTheFormatOfTheExtension) {
    test::ScratchDir dir("write-formats");
    Image image(24, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x)
            for (int c = 0; c < 3; ++c) image.at(x, y, c) = 0.25f + 0.25f * static_cast<float>(c);
    writeImage(dir / "a.jpg", image);
    writeImage(dir / "a.exr", image);
    writeImage(dir / "a.png", image);
    EXPECT_EQ(readImageInfo(dir / "a.jpg").format, ImageFormat::Jpeg);
    EXPECT_EQ(readImageInfo(dir / "a.exr").format, ImageFormat::Exr);
    EXPECT_EQ(readImageInfo(dir / "a.png").format, ImageFormat::Png);
    // A flat colour survives JPEG at quality 95 (stb uses no chroma subsampling above 90) within a few
    // 8-bit steps: the dither's +-0.5 LSB plus the DCT's and the colour transform's rounding: 3 LSB.
    EXPECT_LE(test::maxAbsDiff(readImage(dir / "a.jpg"), image), 3.0 / 255.0);
    // float32 EXR: exact.
    EXPECT_EQ(test::maxAbsDiff(readImage(dir / "a.exr"), image), 0.0);
    EXPECT_THROW(writeImage(dir / "a.bmp", image), Error);
    EXPECT_FALSE(std::filesystem::exists(dir / "a.bmp"));
}

}  // namespace
}  // namespace strata
