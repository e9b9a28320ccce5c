// Fuzz target of the GDM asset reader (src/gdm/gdm_asset.cpp): readGdmAsset on a tiny valid asset (2 x 2 x 2
// voxels, 2 x 2 directions, rank 2, with the raw GDM, albedo and distance volumes, written once per process
// by writeGdmAsset) whose gdm.json is replaced by the input, so that a sidecar that parses goes on to read
// and check the payloads it names.
#include "fuzz_common.h"

#include "strata/gdm/gdm_asset.h"

#include <cstdlib>

namespace {

const std::filesystem::path& assetDir() {
    static const std::filesystem::path dir = [] {
        using namespace strata;
        const std::filesystem::path path = fuzz::scratchDir() / "asset";
        Gdm gdm;
        gdm.dims = {2, 2, 2, 2, 2};
        gdm.height = 0.25;
        gdm.values.resize(gdm.dims.valueCount());
        for (std::size_t n = 0; n < gdm.values.size(); ++n)
            gdm.values[n] = n < 4 ? 0.0f : (n % 3 == 0 ? kGdmMiss : 0.01f * static_cast<float>(n));
        GdmAsset asset;
        asset.svd = compressGdm(gdm, 2);
        asset.occupancy = gdmOccupancy(gdm);
        asset.raw = gdm;
        for (std::size_t n = 0; n < 8 * 3; ++n) asset.albedo.push_back(static_cast<std::uint8_t>(n * 10));
        for (std::size_t n = 0; n < 8; ++n) asset.distance.push_back(0.01f * static_cast<float>(n) - 0.02f);
        asset.source = "fuzz";
        asset.bake = {"--size 2x2x2", 0.5, "2026-12-04T00:00:00Z"};
        writeGdmAsset(path, asset);
        fuzz::exportSeed(path / kGdmAssetSidecar);
        return path;
    }();
    return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace strata;
    const std::filesystem::path& dir = assetDir();
    fuzz::writeInput(dir / kGdmAssetSidecar, data, size);
    return fuzz::expectOnlyErrors([&] { (void)readGdmAsset(dir); });
}
