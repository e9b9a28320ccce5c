// Fuzz target of the texture-set sidecar (src/relief/texture_set.cpp): readTextureSet on a tiny valid set
// (4 x 4, depth, normal, colour and AO, written once per process by writeTextureSet) whose strata.json is
// replaced by the input, so that a sidecar that parses goes on to read the maps it names.
#include "fuzz_common.h"

#include "strata/relief/texture_set.h"

#include <cstdlib>

namespace {

const std::filesystem::path& setDir() {
    static const std::filesystem::path dir = [] {
        using namespace strata;
        const std::filesystem::path path = fuzz::scratchDir() / "set";
        ReliefTexture texture;
        texture.depth = Image(4, 4, 1, 0.25f);
        texture.depth.at(1, 2, 0) = 0.75f;
        texture.normal = normalsFromDepth(texture.depth, texture.depthScale);
        texture.color = Image(4, 4, 3, 0.5f);
        texture.ao = Image(4, 4, 1, 0.9f);
        TextureSetWriteOptions options;
        options.ao = AoRecord{};
        options.ao->method = "sweep";
        options.ao->directions = 8;
        writeTextureSet(path, texture, options);
        fuzz::exportSeed(path / kSidecarName);
        return path;
    }();
    return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace strata;
    const std::filesystem::path& dir = setDir();
    fuzz::writeInput(dir / kSidecarName, data, size);
    return fuzz::expectOnlyErrors([&] { (void)readTextureSet(dir); });
}
