// Fuzz target of the mesh loaders (src/mesh/mesh_loader*.cpp): loadMesh of one format, chosen by the file
// extension STRATA_FUZZ_EXTENSION (".obj", ".gltf", ".glb", ".off"), one target each. Without uvs required,
// so that the repair and tangent steps after parsing run too.
#include "fuzz_common.h"

#include "strata/mesh/mesh_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace strata;
    const std::filesystem::path file =
        fuzz::writeInput(fuzz::scratchDir() / ("input" STRATA_FUZZ_EXTENSION), data, size);
    MeshLoadOptions options;
    options.requireUvs = false;
    return fuzz::expectOnlyErrors([&] {
        MeshRepairReport report;
        (void)loadMesh(file, options, report);
    });
}
