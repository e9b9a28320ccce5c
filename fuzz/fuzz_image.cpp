// Fuzz target of the image readers (src/image/image_io.cpp): readImageInfo and readImage of one format,
// chosen by the file extension STRATA_FUZZ_EXTENSION (".png", ".jpg", ".tga", ".bmp", ".exr"), one target
// each.
#include "fuzz_common.h"

#include "strata/image/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace strata;
    const std::filesystem::path file =
        fuzz::writeInput(fuzz::scratchDir() / ("input" STRATA_FUZZ_EXTENSION), data, size);
    fuzz::expectOnlyErrors([&] { (void)readImageInfo(file); });
    return fuzz::expectOnlyErrors([&] { (void)readImage(file); });
}
