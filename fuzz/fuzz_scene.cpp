// Fuzz target of the scene JSON reader (src/scene/scene.cpp): readScene, which parses and checks every key.
#include "fuzz_common.h"

#include "strata/scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace strata;
    const std::filesystem::path file = fuzz::writeInput(fuzz::scratchDir() / "scene.json", data, size);
    return fuzz::expectOnlyErrors([&] { (void)readScene(file); });
}
