// Fuzz target of the solid-mesh OBJ reader (src/gdm/solid_mesh_io.cpp): parseSolidObj on the input as text,
// with H = 0.5, which runs validateSolidMesh on whatever parses.
#include "fuzz_common.h"

#include "strata/gdm/solid_mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace strata;
    const std::string text(reinterpret_cast<const char*>(data), size);
    return fuzz::expectOnlyErrors([&] { (void)parseSolidObj(text, "fuzz.obj", 0.5); });
}
