// The GDM asset (docs/gdm.md, "The GDM asset"): a baked, compressed generalized displacement map on disk, as
// a directory of a JSON sidecar and little-endian binary payloads:
//
//   gdm.json        the sidecar: "format": "strata.gdm", "version": 1, dims, H, convention, rank, layout,
//                   exit tolerance, singular values, source, bake record, and every payload's file, shape,
//                   element type and byte size.
//   weights.f32     W, rows x rank float32, row-major (GdmSvd::weights).
//   eigen.f32       E, rank x cols float32, row-major (GdmSvd::eigen).
//   occupancy.u8    Nx x Ny x Nz bytes, x fastest (CONVENTIONS §8): 1 where the voxel centre is inside the
//                   solid (the raw GDM's value is 0), else 0.
//   albedo.rgb8     optional: Nx x Ny x Nz x 3 bytes, x fastest, sRGB-encoded RGB of the part nearest to
//                   each voxel centre (Mesostructure::sample), for the built-ins.
//   raw.f32         optional: the raw GDM, Gdm::values in Gdm::valueIndex order, kGdmMiss as +inf.
//   distance.f32    optional: Nx x Ny x Nz float32, x fastest: the signed distance to the solid at each voxel
//                   centre in tile widths, negative inside (bakeGdmDistance, gdm_distance.h), for the GL
//                   renderer's refine technique. `strata gdm bake` writes it; older assets read without it.
//   solid.obj       optional: the solid mesh the GDM was baked from, as baked (CONVENTIONS §8 tile units,
//                   solidObjText of solid_mesh_io.h: every float reads back exactly), for the exact reference
//                   of the GDM verification scene (renderGdmReference). `strata gdm bake` always writes it.
//
// Writing is all or nothing (staged beside the directory, renamed into place, the sidecar last); reading
// checks every key and every payload's size, and the solid as readSolidObj does (validateSolidMesh).
#pragma once

#include "strata/gdm/gdm.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/solid_mesh.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata {

inline constexpr const char* kGdmAssetFormat = "strata.gdm";
inline constexpr int kGdmAssetVersion = 1;
inline constexpr const char* kGdmAssetSidecar = "gdm.json";

// How the asset was baked, recorded as such.
struct GdmBakeInfo {
    std::string settings;  // free text: the command line options that matter ("--size 64x64x16 ...")
    double seconds = 0.0;  // wall time of the bake and compression, >= 0
    std::string date;      // UTC, ISO 8601 ("2026-12-04T19:00:00Z"); empty: not recorded
};

struct GdmAsset {
    GdmSvd svd;                           // the compressed GDM (its dims and H are the asset's)
    std::optional<Gdm> raw;               // the raw GDM, when kept (same dims and H)
    std::vector<std::uint8_t> occupancy;  // Nx Ny Nz, x fastest; 1 inside the solid, 0 outside
    std::vector<std::uint8_t> albedo;     // Nx Ny Nz x RGB, x fastest, sRGB 8-bit; empty: none
    std::vector<float> distance;          // Nx Ny Nz, x fastest; signed distance, tile widths; empty: none
    std::optional<SolidMesh> solid;       // the solid as baked (its height is the SVD's H); none: not stored
    std::string source;                   // where the solid came from: "meso weave", an OBJ path
    GdmBakeInfo bake;
};

// The occupancy volume of a raw GDM: 1 where every direction's value is 0 (inside), else 0.
std::vector<std::uint8_t> gdmOccupancy(const Gdm& gdm);

// The albedo volume of a mesostructure at `dims`: toUnorm8 of Mesostructure::sample(centre).albedo at each
// voxel centre (gdmVoxelCentre with H = meso.height()), RGB interleaved, voxels in §8 order.
std::vector<std::uint8_t> mesostructureAlbedo(const Mesostructure& meso, const GdmDims& dims);

// Writes `asset` to the directory `dir`, atomically: every file is staged in a sibling directory first, then
// renamed into `dir` (created if needed), gdm.json last; any failure leaves `dir` as it was. Throws
// Error(InvalidInput) for an asset whose parts disagree (payload sizes, raw dims, a solid whose H is not the
// SVD's, a distance volume of another size or with a value that is not finite) or a solid that
// validateSolidMesh refuses (it could not be read back), Error(Io) when `dir`
// exists and is not a directory, exists and is neither empty nor a GDM asset (it is never overwritten), is
// one of `inputs`, or cannot be written.
void writeGdmAsset(const std::filesystem::path& dir, const GdmAsset& asset,
                   const std::vector<std::filesystem::path>& inputs = {});

// Reads and validates an asset. Throws Error(Io) naming the file if a file cannot be read, and
// Error(InvalidInput) naming the file and key for a sidecar that is not valid JSON, another format, an
// unknown version, a key missing, unknown or of the wrong type or range, a payload whose size is not the
// one its shape (for solid.obj: the sidecar's "bytes") needs, or a solid.obj that readSolidObj would refuse
// (naming solid.obj, the line or the element). An asset without solid.obj (older ones) reads with no solid;
// one without distance.f32 with an empty distance volume.
GdmAsset readGdmAsset(const std::filesystem::path& dir);

// True when `dir` is a directory holding a gdm.json whose "format" is "strata.gdm". Never throws.
bool isGdmAsset(const std::filesystem::path& dir);

}  // namespace strata
