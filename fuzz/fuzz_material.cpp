// Fuzz target of the material JSON reader (src/scene/material.cpp): readMaterial, which parses and checks
// every key (files it names are checked for existence, not read).
#include "fuzz_common.h"

#include "strata/scene/material.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace strata;
    const std::filesystem::path file = fuzz::writeInput(fuzz::scratchDir() / "material.json", data, size);
    return fuzz::expectOnlyErrors([&] { (void)readMaterial(file); });
}
