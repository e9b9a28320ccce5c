// SVD compression of a generalized displacement map (Wang et al. 2004, Sec. 4.1, "Data Compression").
//
// The 5-D GDM d(x, y, z, theta, phi) (gdm.h, CONVENTIONS §8) is laid out as a 2-D matrix A (GdmLayout) and
// replaced by its best rank-k approximation A ~ W E: k weight maps W_i over the rows (the singular values
// folded in) and k eigen-maps E_i over the columns, d ~ sum_i W_i(row) E_i(col).
//
// Boundary substitution (the paper's Sec. 4.1): kGdmMiss (dmax) would put a jump of +infinity into A.
// Before decomposing, every kGdmMiss is replaced by the distance from the voxel centre along the direction
// to the slab boundary, gdmBoundaryDistance(): to z = H for a direction going up, to z = 0 for one going
// down. Sample directions never have theta = pi / 2 exactly, so that distance is always finite.
//
// Exit rule: a reconstructed value that reaches the boundary distance, within GdmSvd::exitTolerance, is a
// boundary exit (kGdmMiss), anything shorter is a hit:
//     exit  <=>  reconstruct(...) >= gdmBoundaryDistance(...) - exitTolerance.
// The default tolerance is half a voxel's z extent, 0.5 H / Nz, measured along the ray. A real hit closer
// than that to the boundary is then read as an exit (a false miss), and a boundary exit reconstructed more
// than that short of the boundary is read as a hit (a false hit); measureGdmSvd() counts both.
//
// The decomposition: the Gram matrix of A's shorter side (A^T A when A has no more columns than rows, else
// A A^T) is formed in double, in parallel over fixed row (or column) blocks, and diagonalised with Eigen's
// SelfAdjointEigenSolver; no SVD of the long matrix is ever computed. W and E are stored as float.
#pragma once

#include "strata/gdm/gdm.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace strata {

// How the five GDM indices (i, j, k) voxel and (t, s) direction become a row and a column of A. In each
// name the first listed index varies fastest (the formulas below).
enum class GdmLayout {
    // The paper's: rows (x, y, phi), columns (theta, z). Default.
    //   row = s + Nphi (i + Nx j),  col = t + Ntheta k.
    XyPhiByThetaZ,
    // Rows (x, y, z), columns (theta, phi): one row per voxel, its directions as columns.
    //   row = i + Nx (j + Ny k),  col = s + Nphi t  (the raw GDM's own order).
    XyzByThetaPhi,
    // Rows (x, y), columns (z, theta, phi): one row per voxel column.
    //   row = i + Nx j,  col = s + Nphi (t + Ntheta k).
    XyByZThetaPhi,
};

// "xy-phi x theta-z", "xyz x theta-phi", "xy x z-theta-phi": for tables and messages.
const char* toString(GdmLayout layout);

// Rows and columns of A for `dims` in `layout`.
std::size_t gdmLayoutRows(const GdmDims& dims, GdmLayout layout);
std::size_t gdmLayoutCols(const GdmDims& dims, GdmLayout layout);

struct GdmMatrixIndex {
    std::size_t row = 0;
    std::size_t col = 0;
};
// The row and column of value (i, j, k, t, s) in `layout` (the formulas of GdmLayout).
GdmMatrixIndex gdmMatrixIndex(const GdmDims& dims, GdmLayout layout, int i, int j, int k, int t, int s);

// Distance, in tile widths, from the centre of voxel layer k along direction sample t to the slab boundary
// it leaves through: (H - z) / cos(theta) going up, z / -cos(theta) going down, z = (k + .5) H / Nz.
// Depends on k and t only. Always finite (sample directions never have cos(theta) = 0).
double gdmBoundaryDistance(const GdmDims& dims, double height, int k, int t);

// A GDM compressed to rank k.
struct GdmSvd {
    GdmDims dims;
    double height = 0.25;  // H, tile widths
    GdmLayout layout = GdmLayout::XyPhiByThetaZ;
    int rank = 0;          // k, 1 <= k <= min(rows, cols)
    std::size_t rows = 0;  // gdmLayoutRows(dims, layout)
    std::size_t cols = 0;  // gdmLayoutCols(dims, layout)
    // W: rows x k, row-major (weights[row * k + i] = W_i(row)), singular values folded in.
    std::vector<float> weights;
    // E: k x cols, row-major (eigen[i * cols + col] = E_i(col)): each eigen-map contiguous, unit norm.
    std::vector<float> eigen;
    // sigma_i, descending, k of them (sigma_i^2 are the Gram matrix's largest eigenvalues).
    std::vector<double> singularValues;
    // The exit rule's tolerance, tile widths, along the ray (see the top of this file). compressGdm sets
    // 0.5 H / Nz; a caller may change it before querying.
    double exitTolerance = 0.0;

    // Bytes of W and E as stored (float), the compressed maps' memory.
    std::size_t mapBytes() const { return (weights.size() + eigen.size()) * sizeof(float); }
};

// Rank-`rank` SVD compression of `gdm` in `layout` (Sec. 4.1), after the boundary substitution.
// Throws Error(InvalidInput): when gdm.values does not hold dims.valueCount() values, when dims or H are
// invalid (validateGdmDims), when a value is NaN or negative, and when rank < 1 or rank > min(rows, cols)
// (the message names the rank and the limit). Deterministic: the same input gives the same maps on any
// number of threads.
GdmSvd compressGdm(const Gdm& gdm, int rank = 8, GdmLayout layout = GdmLayout::XyPhiByThetaZ);

// The first `rank` terms of `svd`: the best rank-`rank` approximation of the same matrix (Eckart-Young: the
// terms are in descending order of sigma), without compressing again. The exit tolerance is kept. Throws
// Error(InvalidInput) naming both ranks when rank < 1 or rank > svd.rank.
GdmSvd truncateGdmSvd(const GdmSvd& svd, int rank);

// The reconstructed value sum_i W_i E_i at (i, j, k, t, s), in the substituted form: finite, a boundary
// exit reads as (about) the boundary distance. Indices must be in range (STRATA_CHECK).
float reconstruct(const GdmSvd& svd, int i, int j, int k, int t, int s);

// True where the exit rule reads `value` (a reconstruct() at voxel layer k, direction t) as a boundary exit.
bool isGdmExit(const GdmSvd& svd, float value, int k, int t);

// The GDM back: reconstruct() everywhere, with kGdmMiss where isGdmExit() and values below 0 clamped to 0.
Gdm decompress(const GdmSvd& svd);

// Parameters of measureGdmSvd's random segment queries.
struct GdmSvdErrorParams {
    int segmentQueries = 1 << 20;  // number of random queries, >= 0
    std::uint64_t seed = 1;        // the queries are a pure function of it (and of the dims)
};

// How well `svd` reproduces `raw`. Lengths are in voxels of length H / Nz (the voxel's z extent; at the
// paper's 64 x 64 x 16, H = 0.25 it equals the u extent 1 / Nx).
struct GdmSvdError {
    double voxelLength = 0.0;  // H / Nz, tile widths
    // |d_raw - d_rec| over every value, d_raw with the boundary substitution, d_rec = reconstruct().
    double rmseVoxels = 0.0;
    double p99Voxels = 0.0;  // 99th percentile
    double maxVoxels = 0.0;
    // The exit rule against the raw GDM, % of all values: a raw kGdmMiss read as a hit (false hit), a raw
    // hit (finite, including 0) read as an exit (false miss).
    double exitFalseHitPercent = 0.0;
    double exitFalseMissPercent = 0.0;
    // Random segment queries, % of all queries: a random voxel, a random direction sample, and a length dt
    // uniform in (0, gdmBoundaryDistance] (the segment stays inside the slab, as a segment to a prism's exit
    // point does); "does the segment meet the solid, d < dt?" asked of raw and of decompress(). False hit:
    // decompressed yes, raw no; false miss: the other way.
    double segmentFalseHitPercent = 0.0;
    double segmentFalseMissPercent = 0.0;
    double memoryMiB = 0.0;  // mapBytes() / 2^20
};

// Compares `svd` with the `raw` GDM it was compressed from. Throws Error(InvalidInput) when their dims or H
// differ, when raw's value count is wrong, or when params.segmentQueries < 0.
GdmSvdError measureGdmSvd(const Gdm& raw, const GdmSvd& svd, const GdmSvdErrorParams& params = {});

}  // namespace strata
