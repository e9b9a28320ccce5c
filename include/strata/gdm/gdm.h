// The generalized displacement map (Wang et al. 2004, Sec. 3.1) and its sampling, as CONVENTIONS §8 fixes
// them. Everything here is in the tile's isotropic frame (u, v, z) with z = w H: one tile is the box
// [0, 1) x [0, 1) x [0, H], u and v wrap, lengths are in tile widths.
//
//   - Voxels: Nx x Ny x Nz samples at the cell centres ((i + .5) / Nx, (j + .5) / Ny, (k + .5) / Nz) in
//     (u, v, w); storage x fastest, then y, then z; k = 0 is the bottom layer.
//   - Directions: Ntheta x Nphi samples at theta = (t + .5) pi / Ntheta (polar angle from +w: 0 points up,
//     away from the base) and phi = (s + .5) 2 pi / Nphi (azimuth from +u towards +v).
//   - The value d(x, y, z, theta, phi): 0 where the voxel centre lies inside the solid; else the distance
//     along the ray (wrapping in u and v) to the first solid surface; kGdmMiss where the ray leaves the slab
//     0 <= z <= H through its top or bottom without a hit.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace strata {

// dmax of the paper: the ray leaves the slab without a hit. Recorded as +infinity, never as a large number.
inline constexpr float kGdmMiss = std::numeric_limits<float>::infinity();

// Sampling of a GDM (CONVENTIONS §8). Defaults are the paper's: 64 x 64 x 16 voxels, 16 x 32 directions.
struct GdmDims {
    int nx = 64;      // voxels along u, >= 1
    int ny = 64;      // voxels along v, >= 1
    int nz = 16;      // voxels along w, >= 1
    int ntheta = 16;  // polar direction samples, >= 1
    int nphi = 32;    // azimuth direction samples, >= 1

    std::size_t voxelCount() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
    std::size_t directionCount() const { return std::size_t(ntheta) * std::size_t(nphi); }
    std::size_t valueCount() const { return voxelCount() * directionCount(); }
    bool operator==(const GdmDims&) const = default;
};

// The refusal before allocating: throws Error(InvalidInput) naming `what` for a dimension < 1, a shell
// thickness H that is not finite and > 0, or a GDM whose raw values would need more than `maxBytes` (the
// message says how many bytes it would need).
void validateGdmDims(const GdmDims& dims, double height, const std::string& what,
                     std::size_t maxBytes = std::size_t(4) << 30);

// Unit direction of sample (t, s) in the isotropic frame: (sin th cos ph, sin th sin ph, cos th).
glm::dvec3 gdmDirection(const GdmDims& dims, int t, int s);
// Centre of voxel (i, j, k) in the isotropic frame: ((i + .5) / Nx, (j + .5) / Ny, (k + .5) / Nz * H).
glm::dvec3 gdmVoxelCentre(const GdmDims& dims, double height, int i, int j, int k);

// A raw 5-D GDM. values[valueIndex(i, j, k, t, s)] is d at voxel (i, j, k) and direction (t, s): the
// voxels in §8 storage order, each holding its Ntheta x Nphi directions with phi fastest.
struct Gdm {
    GdmDims dims;
    double height = 0.25;  // H, tile widths
    std::vector<float> values;

    std::size_t valueIndex(int i, int j, int k, int t, int s) const {
        const std::size_t voxel =
            std::size_t(i) + std::size_t(dims.nx) * (std::size_t(j) + std::size_t(dims.ny) * std::size_t(k));
        return voxel * dims.directionCount() + std::size_t(t) * std::size_t(dims.nphi) + std::size_t(s);
    }
    float at(int i, int j, int k, int t, int s) const { return values[valueIndex(i, j, k, t, s)]; }
};

}  // namespace strata
