#include "strata/gdm/gdm_svd.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include <Spectra/MatOp/DenseSymMatProd.h>
#include <Spectra/SymEigsSolver.h>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#if defined(__x86_64__)
#define STRATA_GRAM_X86
#include <immintrin.h>  // the AVX2 / FMA intrinsics of the Gram kernel
#endif

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace strata {

namespace {

using RowMatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Rows (or columns) of A per rank update of the Gram matrix: a block of 64 x 256 doubles (128 KiB) stays in
// L2 while it is multiplied by its transpose.
constexpr std::size_t kGramBlock = 64;
// The Gram matrix is summed from this many partial ones, each over a fixed range of blocks, so that the sum
// (and the maps) are the same on any number of threads.
constexpr std::size_t kGramParts = 16;
// ... unless their memory would pass this.
constexpr double kGramPartsMaxBytes = 256.0 * (1 << 20);

std::string rankMessage(const std::string& what) {
    return "GDM SVD: " + what;
}

// Boundary distances, [k * Ntheta + t].
std::vector<double> boundaryTable(const GdmDims& dims, double height) {
    std::vector<double> table(std::size_t(dims.nz) * std::size_t(dims.ntheta));
    for (int k = 0; k < dims.nz; ++k)
        for (int t = 0; t < dims.ntheta; ++t)
            table[std::size_t(k) * std::size_t(dims.ntheta) + std::size_t(t)] =
                gdmBoundaryDistance(dims, height, k, t);
    return table;
}

// Calls body(i, j) for every voxel column, in parallel.
template <typename Body>
void forVoxelColumns(const GdmDims& dims, const Body& body) {
    parallelFor(0, dims.nx * dims.ny, [&](int ij) { body(ij % dims.nx, ij / dims.nx); });
}

// Reads A's entries straight from the raw GDM, with the boundary substitution, never forming A (it is as
// large as the GDM). The GDM's value index is linear in i, j, k, t, s, so entry (row, col) lives at
// rowStart(row) + colOffset[col]; its boundary distance is boundary[k Ntheta + t], k from the row or the
// column.
class LayoutReader {
public:
    LayoutReader(const Gdm& gdm, GdmLayout layout)
        : mGdm(gdm),
          mLayout(layout),
          mBoundary(boundaryTable(gdm.dims, gdm.height)),
          mColOffset(gdmLayoutCols(gdm.dims, layout)),
          mColBoundary(mColOffset.size()) {
        const GdmDims& dims = gdm.dims;
        const std::size_t cols = mColOffset.size();
        const std::size_t layer = std::size_t(dims.nx) * std::size_t(dims.ny) * dims.directionCount();
        for (std::size_t col = 0; col < cols; ++col) {
            // (k, t, s) of the column; k = -1 where k is a row index.
            std::size_t k = 0, t = 0, s = 0;
            switch (layout) {
                case GdmLayout::XyPhiByThetaZ:
                    t = col % dims.ntheta, k = col / dims.ntheta;
                    break;
                case GdmLayout::XyzByThetaPhi:
                    s = col % dims.nphi, t = col / dims.nphi;
                    break;
                case GdmLayout::XyByZThetaPhi:
                    s = col % dims.nphi, t = col / dims.nphi % dims.ntheta, k = col / dims.directionCount();
                    break;
            }
            mColOffset[col] = k * layer + t * std::size_t(dims.nphi) + s;
            mColBoundary[col] = k * std::size_t(dims.ntheta) + t;
        }
    }

    // out[c] = A(row, c) for every column c.
    void readRow(std::size_t row, float* out) const {
        const auto [start, boundaryStart] = rowStart(row);
        for (std::size_t col = 0; col < mColOffset.size(); ++col)
            out[col] = entry(start + mColOffset[col], boundaryStart + mColBoundary[col]);
    }

    // out[r * (to - from) + (c - from)] = A(r, c) for every row r and the columns c in [from, to).
    void readCols(std::size_t from, std::size_t to, float* out) const {
        const std::size_t rows = gdmLayoutRows(mGdm.dims, mLayout);
        for (std::size_t row = 0; row < rows; ++row) {
            const auto [start, boundaryStart] = rowStart(row);
            for (std::size_t col = from; col < to; ++col)
                *out++ = entry(start + mColOffset[col], boundaryStart + mColBoundary[col]);
        }
    }

private:
    // The row's part of the value index, and of the boundary index (k Ntheta where k is a row index).
    std::pair<std::size_t, std::size_t> rowStart(std::size_t row) const {
        const GdmDims& dims = mGdm.dims;
        const std::size_t columnOfVoxels = std::size_t(dims.nx) * std::size_t(dims.ny);
        switch (mLayout) {
            case GdmLayout::XyPhiByThetaZ:
                return {row / dims.nphi * dims.directionCount() + row % dims.nphi, 0};
            case GdmLayout::XyzByThetaPhi:
                return {row * dims.directionCount(), row / columnOfVoxels * std::size_t(dims.ntheta)};
            case GdmLayout::XyByZThetaPhi:
                return {row * dims.directionCount(), 0};
        }
        return {0, 0};
    }

    float entry(std::size_t at, std::size_t boundaryAt) const {
        const float value = mGdm.values[at];
        if (value >= 0.0f && value != kGdmMiss) return value;
        if (value == kGdmMiss) return float(mBoundary[boundaryAt]);
        refuse(at);
    }

    [[noreturn]] void refuse(std::size_t at) const {
        const GdmDims& dims = mGdm.dims;
        const std::size_t voxel = at / dims.directionCount(), direction = at % dims.directionCount();
        throw Error(ErrorKind::InvalidInput,
                    "GDM SVD: value " + formatNumber(mGdm.values[at]) + " at voxel (" +
                        std::to_string(voxel % dims.nx) + ", " + std::to_string(voxel / dims.nx % dims.ny) +
                        ", " + std::to_string(voxel / dims.nx / dims.ny) + "), direction (" +
                        std::to_string(direction / dims.nphi) + ", " + std::to_string(direction % dims.nphi) +
                        ") is not a distance >= 0 or kGdmMiss");
    }

    const Gdm& mGdm;
    GdmLayout mLayout;
    std::vector<double> mBoundary;
    std::vector<std::size_t> mColOffset;
    std::vector<std::size_t> mColBoundary;
};

#ifdef STRATA_GRAM_X86
// gram += block^T block for a row-major block of `rows` x n doubles (n a multiple of 12) and a row-major
// n x n gram; fills the tiles that hold the lower triangle (entries (a, b) with b < a + 4; those above the
// diagonal are right too, the matrix being symmetric). 4 x 12 tiles of the product in twelve AVX
// registers, one FMA per register and row: twelve independent sums hide the FMA latency better than the
// eight of 4 x 8 tiles. The baseline build (SSE2, no FMA) leaves Eigen's rank update at about half this
// speed (bench_gdm_svd: 340 against 165 ms).
// Everything in this region is compiled for AVX2 + FMA and called only where the CPU has both.
#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace avx2 {
// The attribute too: clang ignores `#pragma GCC target` (the fuzz build, docs/fuzzing.md, uses clang).
__attribute__((target("avx2,fma"))) void addGram(const double* block, std::size_t rows, std::size_t n,
                                                 double* gram) {
    for (std::size_t a = 0; a < n; a += 4)
        for (std::size_t b = 0; b < a + 4 && b < n; b += 12) {
            __m256d sum[4][3];
            for (auto& row : sum) row[0] = row[1] = row[2] = _mm256_setzero_pd();
            for (std::size_t r = 0; r < rows; ++r) {
                const double* line = block + r * n;
                const __m256d x0 = _mm256_loadu_pd(line + b), x1 = _mm256_loadu_pd(line + b + 4),
                              x2 = _mm256_loadu_pd(line + b + 8);
                for (std::size_t i = 0; i < 4; ++i) {
                    const __m256d y = _mm256_broadcast_sd(line + a + i);
                    sum[i][0] = _mm256_fmadd_pd(y, x0, sum[i][0]);
                    sum[i][1] = _mm256_fmadd_pd(y, x1, sum[i][1]);
                    sum[i][2] = _mm256_fmadd_pd(y, x2, sum[i][2]);
                }
            }
            for (std::size_t i = 0; i < 4; ++i)
                for (std::size_t v = 0; v < 3; ++v) {
                    double* out = gram + (a + i) * n + b + 4 * v;
                    _mm256_storeu_pd(out, _mm256_add_pd(_mm256_loadu_pd(out), sum[i][v]));
                }
        }
}
}  // namespace avx2
#pragma GCC pop_options
#endif

bool gramKernelRuns() {
#ifdef STRATA_GRAM_X86
    static const bool runs = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return runs;
#else
    return false;
#endif
}

using RowMatrixD = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The Gram matrix of A's shorter side, in double (lower triangle valid): A^T A (cols x cols) when
// cols <= rows, else A A^T (rows x rows). Summed from partial Gram matrices over fixed block ranges.
Eigen::MatrixXd gramMatrix(const LayoutReader& reader, std::size_t rows, std::size_t cols) {
    const bool tall = cols <= rows;
    const std::size_t n = tall ? cols : rows;
    // The AVX2 kernel works on rows padded with zeros to a multiple of 12.
    const bool kernel = tall && gramKernelRuns();
    const std::size_t padded = kernel ? (n + 11) / 12 * 12 : n;
    const std::size_t length = tall ? rows : cols;  // the side that is summed over
    const std::size_t blocks = (length + kGramBlock - 1) / kGramBlock;
    const double partBytes = double(padded) * double(padded) * sizeof(double);
    const std::size_t parts =
        std::max<std::size_t>(1, std::min({kGramParts, blocks, std::size_t(kGramPartsMaxBytes / partBytes)}));
    std::vector<RowMatrixD> partial(parts);
    parallelFor(std::size_t(0), parts, [&](std::size_t part) {
        RowMatrixD& gram = partial[part];
        gram.setZero(Eigen::Index(padded), Eigen::Index(padded));
        RowMatrixF block;
        RowMatrixD wide;
        std::vector<float> line(cols);
        for (std::size_t b = blocks * part / parts; b < blocks * (part + 1) / parts; ++b) {
            const std::size_t from = b * kGramBlock;
            const std::size_t count = std::min(kGramBlock, length - from);
            if (kernel) {
#ifdef STRATA_GRAM_X86
                wide.setZero(Eigen::Index(count), Eigen::Index(padded));
                for (std::size_t r = 0; r < count; ++r) {
                    reader.readRow(from + r, line.data());
                    for (std::size_t c = 0; c < cols; ++c) wide(Eigen::Index(r), Eigen::Index(c)) = line[c];
                }
                avx2::addGram(wide.data(), count, padded, gram.data());
#endif
            } else if (tall) {
                block.resize(Eigen::Index(count), Eigen::Index(cols));
                for (std::size_t r = 0; r < count; ++r)
                    reader.readRow(from + r, block.row(Eigen::Index(r)).data());
                wide = block.cast<double>();
                gram.selfadjointView<Eigen::Lower>().rankUpdate(wide.transpose());
            } else {
                block.resize(Eigen::Index(rows), Eigen::Index(count));
                reader.readCols(from, from + count, block.data());
                wide = block.cast<double>();
                gram.selfadjointView<Eigen::Lower>().rankUpdate(wide);
            }
        }
    });
    for (std::size_t part = 1; part < parts; ++part) partial[0] += partial[part];
    return partial[0].topLeftCorner(Eigen::Index(n), Eigen::Index(n));
}

// Gram matrices up to this size are diagonalised whole (Eigen's SelfAdjointEigenSolver: exact, and fast
// at the paper's 256 x 256); larger ones, e.g. the 4096 x 4096 of (x, y) x (z, theta, phi) at 64 x 64
// voxels, give only their k largest eigenpairs, by Spectra's implicitly restarted Lanczos method.
constexpr Eigen::Index kDenseEigenMax = 1024;

struct Eigenpairs {
    Eigen::VectorXd values;   // the k largest, descending
    Eigen::MatrixXd vectors;  // n x k, unit columns, each one's largest component positive
};

// The `rank` largest eigenpairs of a symmetric matrix given by its lower triangle. Deterministic: Spectra
// starts from its own fixed pseudo-random vector.
Eigenpairs largestEigenpairs(const Eigen::MatrixXd& gram, int rank) {
    const Eigen::Index n = gram.rows();
    Eigenpairs result;
    if (n <= kDenseEigenMax || 4 * Eigen::Index(rank) > n) {
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram);
        if (solver.info() != Eigen::Success)
            throw Error(ErrorKind::Runtime, "GDM SVD: the eigensolver of the Gram matrix did not converge");
        // Eigen sorts them ascending.
        result.values = solver.eigenvalues().tail(rank).reverse();
        result.vectors = solver.eigenvectors().rightCols(rank).rowwise().reverse();
    } else {
        Spectra::DenseSymMatProd<double, Eigen::Lower> product(gram);
        const Eigen::Index subspace = std::min(n, 2 * Eigen::Index(rank) + 32);
        Spectra::SymEigsSolver<Spectra::DenseSymMatProd<double, Eigen::Lower>> solver(product, rank,
                                                                                      subspace);
        solver.init();
        solver.compute(Spectra::SortRule::LargestAlge, 1000, 1e-12);
        if (solver.info() != Spectra::CompInfo::Successful)
            throw Error(ErrorKind::Runtime,
                        "GDM SVD: the Lanczos eigensolver of the Gram matrix did not converge");
        result.values = solver.eigenvalues();  // descending
        result.vectors = solver.eigenvectors();
    }
    // Fix each vector's sign so that its largest component is positive: the maps do not flip sign between
    // builds of Eigen or solvers.
    for (int r = 0; r < rank; ++r) {
        Eigen::Index largest = 0;
        result.vectors.col(r).cwiseAbs().maxCoeff(&largest);
        if (result.vectors(largest, r) < 0.0) result.vectors.col(r) *= -1.0;
    }
    return result;
}

// The product W E as a row-major float matrix (rows x cols), in parallel over row blocks.
std::vector<float> reconstructMatrix(const GdmSvd& svd) {
    std::vector<float> out(svd.rows * svd.cols);
    const Eigen::Map<const RowMatrixF> e(svd.eigen.data(), svd.rank, Eigen::Index(svd.cols));
    parallelForChunks(
        std::size_t(0), svd.rows,
        [&](std::size_t from, std::size_t to) {
            const Eigen::Map<const RowMatrixF> w(svd.weights.data() + from * std::size_t(svd.rank),
                                                 Eigen::Index(to - from), svd.rank);
            Eigen::Map<RowMatrixF>(out.data() + from * svd.cols, Eigen::Index(to - from),
                                   Eigen::Index(svd.cols)) = w * e;
        },
        std::size_t(64));
    return out;
}

// splitmix64: the segment queries' random numbers, a pure function of (seed, query, draw).
std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

}  // namespace

const char* toString(GdmLayout layout) {
    switch (layout) {
        case GdmLayout::XyPhiByThetaZ:
            return "xy-phi x theta-z";
        case GdmLayout::XyzByThetaPhi:
            return "xyz x theta-phi";
        case GdmLayout::XyByZThetaPhi:
            return "xy x z-theta-phi";
    }
    return "unknown";
}

std::size_t gdmLayoutRows(const GdmDims& dims, GdmLayout layout) {
    const std::size_t xy = std::size_t(dims.nx) * std::size_t(dims.ny);
    switch (layout) {
        case GdmLayout::XyPhiByThetaZ:
            return xy * std::size_t(dims.nphi);
        case GdmLayout::XyzByThetaPhi:
            return xy * std::size_t(dims.nz);
        case GdmLayout::XyByZThetaPhi:
            return xy;
    }
    return 0;
}

std::size_t gdmLayoutCols(const GdmDims& dims, GdmLayout layout) {
    return dims.valueCount() / gdmLayoutRows(dims, layout);
}

GdmMatrixIndex gdmMatrixIndex(const GdmDims& dims, GdmLayout layout, int i, int j, int k, int t, int s) {
    const std::size_t nx = std::size_t(dims.nx), ny = std::size_t(dims.ny);
    const std::size_t ntheta = std::size_t(dims.ntheta), nphi = std::size_t(dims.nphi);
    switch (layout) {
        case GdmLayout::XyPhiByThetaZ:
            return {std::size_t(s) + nphi * (std::size_t(i) + nx * std::size_t(j)),
                    std::size_t(t) + ntheta * std::size_t(k)};
        case GdmLayout::XyzByThetaPhi:
            return {std::size_t(i) + nx * (std::size_t(j) + ny * std::size_t(k)),
                    std::size_t(s) + nphi * std::size_t(t)};
        case GdmLayout::XyByZThetaPhi:
            return {std::size_t(i) + nx * std::size_t(j),
                    std::size_t(s) + nphi * (std::size_t(t) + ntheta * std::size_t(k))};
    }
    return {};
}

double gdmBoundaryDistance(const GdmDims& dims, double height, int k, int t) {
    const double z = (k + 0.5) / dims.nz * height;
    const double cosTheta = gdmDirection(dims, t, 0).z;
    return cosTheta > 0.0 ? (height - z) / cosTheta : z / -cosTheta;
}

GdmSvd compressGdm(const Gdm& gdm, int rank, GdmLayout layout) {
    validateGdmDims(gdm.dims, gdm.height, "GDM SVD");
    if (gdm.values.size() != gdm.dims.valueCount())
        throw Error(ErrorKind::InvalidInput, "GDM SVD: the GDM holds " + std::to_string(gdm.values.size()) +
                                                 " values, its dims need " +
                                                 std::to_string(gdm.dims.valueCount()));
    GdmSvd svd;
    svd.dims = gdm.dims;
    svd.height = gdm.height;
    svd.layout = layout;
    svd.rows = gdmLayoutRows(gdm.dims, layout);
    svd.cols = gdmLayoutCols(gdm.dims, layout);
    const std::size_t n = std::min(svd.rows, svd.cols);
    if (rank < 1 || std::size_t(rank) > n)
        throw Error(ErrorKind::InvalidInput,
                    rankMessage("rank " + std::to_string(rank) + " must be in [1, " + std::to_string(n) +
                                "], min(rows, cols) of the " + std::to_string(svd.rows) + " x " +
                                std::to_string(svd.cols) + " layout " + toString(layout)));
    svd.rank = rank;
    svd.exitTolerance = 0.5 * gdm.height / gdm.dims.nz;

    const LayoutReader reader(gdm, layout);
    Eigenpairs pairs = largestEigenpairs(gramMatrix(reader, svd.rows, svd.cols), rank);
    Eigen::MatrixXd& basis = pairs.vectors;
    svd.singularValues.resize(std::size_t(rank));
    for (int r = 0; r < rank; ++r)
        svd.singularValues[std::size_t(r)] = std::sqrt(std::max(0.0, pairs.values(r)));

    svd.weights.resize(svd.rows * std::size_t(rank));
    svd.eigen.resize(std::size_t(rank) * svd.cols);
    Eigen::Map<RowMatrixF> weights(svd.weights.data(), Eigen::Index(svd.rows), rank);
    Eigen::Map<RowMatrixF> eigen(svd.eigen.data(), rank, Eigen::Index(svd.cols));
    if (svd.cols <= svd.rows) {
        // basis = V: E = V^T, W = A V = U Sigma. In float: A is float, and the sums of cols products lose
        // about sqrt(cols) 6e-8 of a value, far below what a truncation to rank k does.
        eigen = basis.transpose().cast<float>();
        const Eigen::MatrixXf basisF = basis.cast<float>();
        parallelForChunks(
            std::size_t(0), svd.rows,
            [&](std::size_t from, std::size_t to) {
                RowMatrixF block(Eigen::Index(to - from), Eigen::Index(svd.cols));
                for (std::size_t r = from; r < to; ++r)
                    reader.readRow(r, block.row(Eigen::Index(r - from)).data());
                weights.middleRows(Eigen::Index(from), Eigen::Index(to - from)) = block * basisF;
            },
            kGramBlock);
    } else {
        // basis = U: S = U^T A = Sigma V^T; E_i = S_i / |S_i|, W_i = U_i |S_i| (a zero row of S stays zero).
        Eigen::MatrixXd scaled(rank, Eigen::Index(svd.cols));
        parallelForChunks(
            std::size_t(0), svd.cols,
            [&](std::size_t from, std::size_t to) {
                RowMatrixF block(Eigen::Index(svd.rows), Eigen::Index(to - from));
                reader.readCols(from, to, block.data());
                scaled.middleCols(Eigen::Index(from), Eigen::Index(to - from)) =
                    basis.transpose() * block.cast<double>();
            },
            kGramBlock);
        for (int r = 0; r < rank; ++r) {
            const double sigma = scaled.row(r).norm();
            if (sigma > 0.0) scaled.row(r) /= sigma;
            basis.col(r) *= sigma;
        }
        eigen = scaled.cast<float>();
        weights = basis.cast<float>();
    }
    return svd;
}

GdmSvd truncateGdmSvd(const GdmSvd& svd, int rank) {
    if (rank < 1 || rank > svd.rank)
        throw Error(ErrorKind::InvalidInput, "GDM rank " + std::to_string(rank) + " is not in [1, " +
                                                 std::to_string(svd.rank) + "], the ranks this SVD stores");
    GdmSvd out;
    out.dims = svd.dims;
    out.height = svd.height;
    out.layout = svd.layout;
    out.rank = rank;
    out.rows = svd.rows;
    out.cols = svd.cols;
    out.exitTolerance = svd.exitTolerance;
    const auto k = std::size_t(rank), stored = std::size_t(svd.rank);
    out.weights.resize(svd.rows * k);
    for (std::size_t row = 0; row < svd.rows; ++row)
        std::copy_n(svd.weights.begin() + std::ptrdiff_t(row * stored), k,
                    out.weights.begin() + std::ptrdiff_t(row * k));
    out.eigen.assign(svd.eigen.begin(), svd.eigen.begin() + std::ptrdiff_t(k * svd.cols));
    out.singularValues.assign(svd.singularValues.begin(), svd.singularValues.begin() + std::ptrdiff_t(k));
    return out;
}

float reconstruct(const GdmSvd& svd, int i, int j, int k, int t, int s) {
    STRATA_CHECK(i >= 0 && i < svd.dims.nx && j >= 0 && j < svd.dims.ny && k >= 0 && k < svd.dims.nz);
    STRATA_CHECK(t >= 0 && t < svd.dims.ntheta && s >= 0 && s < svd.dims.nphi);
    const GdmMatrixIndex index = gdmMatrixIndex(svd.dims, svd.layout, i, j, k, t, s);
    double sum = 0.0;
    for (int r = 0; r < svd.rank; ++r)
        sum += double(svd.weights[index.row * std::size_t(svd.rank) + std::size_t(r)]) *
               double(svd.eigen[std::size_t(r) * svd.cols + index.col]);
    return float(sum);
}

bool isGdmExit(const GdmSvd& svd, float value, int k, int t) {
    return double(value) >= gdmBoundaryDistance(svd.dims, svd.height, k, t) - svd.exitTolerance;
}

Gdm decompress(const GdmSvd& svd) {
    const std::vector<float> rec = reconstructMatrix(svd);
    const std::vector<double> boundary = boundaryTable(svd.dims, svd.height);
    Gdm gdm;
    gdm.dims = svd.dims;
    gdm.height = svd.height;
    gdm.values.resize(svd.dims.valueCount());
    forVoxelColumns(svd.dims, [&](int i, int j) {
        for (int k = 0; k < svd.dims.nz; ++k)
            for (int t = 0; t < svd.dims.ntheta; ++t) {
                const double exitAt =
                    boundary[std::size_t(k) * std::size_t(svd.dims.ntheta) + std::size_t(t)] -
                    svd.exitTolerance;
                for (int s = 0; s < svd.dims.nphi; ++s) {
                    const GdmMatrixIndex index = gdmMatrixIndex(svd.dims, svd.layout, i, j, k, t, s);
                    const float value = rec[index.row * svd.cols + index.col];
                    gdm.values[gdm.valueIndex(i, j, k, t, s)] =
                        double(value) >= exitAt ? kGdmMiss : std::max(0.0f, value);
                }
            }
    });
    return gdm;
}

GdmSvdError measureGdmSvd(const Gdm& raw, const GdmSvd& svd, const GdmSvdErrorParams& params) {
    if (!(raw.dims == svd.dims) || raw.height != svd.height || raw.values.size() != raw.dims.valueCount())
        throw Error(ErrorKind::InvalidInput, "GDM SVD error: the raw GDM's dims, H or value count (" +
                                                 std::to_string(raw.values.size()) +
                                                 ") do not match the compressed one");
    if (params.segmentQueries < 0)
        throw Error(ErrorKind::InvalidInput, "GDM SVD error: segmentQueries must be >= 0, got " +
                                                 std::to_string(params.segmentQueries));
    const GdmDims& dims = raw.dims;
    const std::vector<double> boundary = boundaryTable(dims, raw.height);
    const std::vector<float> rec = reconstructMatrix(svd);
    const Gdm decompressed = decompress(svd);
    GdmSvdError error;
    error.voxelLength = raw.height / dims.nz;
    error.memoryMiB = double(svd.mapBytes()) / double(1 << 20);

    // Per value, in the raw GDM's order; per voxel column sums, added in a fixed order.
    std::vector<float> differences(dims.valueCount());
    struct Sums {
        double squares = 0.0;
        std::size_t falseHits = 0;
        std::size_t falseMisses = 0;
    };
    std::vector<Sums> columnSums(std::size_t(dims.nx) * std::size_t(dims.ny));
    forVoxelColumns(dims, [&](int i, int j) {
        Sums& sums = columnSums[std::size_t(i) + std::size_t(dims.nx) * std::size_t(j)];
        for (int k = 0; k < dims.nz; ++k)
            for (int t = 0; t < dims.ntheta; ++t)
                for (int s = 0; s < dims.nphi; ++s) {
                    const std::size_t at = raw.valueIndex(i, j, k, t, s);
                    const float value = raw.values[at];
                    const bool rawMiss = value == kGdmMiss;
                    const double substituted =
                        rawMiss ? boundary[std::size_t(k) * std::size_t(dims.ntheta) + std::size_t(t)]
                                : double(value);
                    const GdmMatrixIndex index = gdmMatrixIndex(dims, svd.layout, i, j, k, t, s);
                    const double difference =
                        std::abs(substituted - double(rec[index.row * svd.cols + index.col])) /
                        error.voxelLength;
                    differences[at] = float(difference);
                    sums.squares += difference * difference;
                    const bool decompressedMiss = decompressed.values[at] == kGdmMiss;
                    sums.falseHits += rawMiss && !decompressedMiss;
                    sums.falseMisses += !rawMiss && decompressedMiss;
                }
    });
    Sums total;
    for (const Sums& sums : columnSums) {
        total.squares += sums.squares;
        total.falseHits += sums.falseHits;
        total.falseMisses += sums.falseMisses;
    }
    const double count = double(dims.valueCount());
    error.rmseVoxels = std::sqrt(total.squares / count);
    error.exitFalseHitPercent = 100.0 * double(total.falseHits) / count;
    error.exitFalseMissPercent = 100.0 * double(total.falseMisses) / count;
    error.maxVoxels = double(*std::max_element(differences.begin(), differences.end()));
    const auto p99 = differences.begin() + std::ptrdiff_t(0.99 * double(differences.size() - 1));
    std::nth_element(differences.begin(), p99, differences.end());
    error.p99Voxels = double(*p99);

    // Segment queries, summed over fixed ranges.
    const std::size_t queries = std::size_t(params.segmentQueries);
    constexpr std::size_t kParts = 64;
    std::vector<Sums> partSums(kParts);
    parallelFor(std::size_t(0), kParts, [&](std::size_t part) {
        Sums& sums = partSums[part];
        for (std::size_t q = queries * part / kParts; q < queries * (part + 1) / kParts; ++q) {
            const std::uint64_t key = mix(params.seed ^ mix(q));
            const std::uint64_t voxelDraw = mix(key + 1), directionDraw = mix(key + 2),
                                lengthDraw = mix(key + 3);
            const std::size_t voxel = voxelDraw % dims.voxelCount();
            const std::size_t direction = directionDraw % dims.directionCount();
            const int k = int(voxel / (std::size_t(dims.nx) * std::size_t(dims.ny)));
            const int t = int(direction / std::size_t(dims.nphi));
            // dt uniform in (0, boundary]: 53 random bits, shifted off 0.
            const double unit = (double(lengthDraw >> 11) + 1.0) / 9007199254740992.0;
            const double dt = unit * boundary[std::size_t(k) * std::size_t(dims.ntheta) + std::size_t(t)];
            const std::size_t at = voxel * dims.directionCount() + direction;
            const bool rawHit = double(raw.values[at]) < dt;
            const bool decompressedHit = double(decompressed.values[at]) < dt;
            sums.falseHits += decompressedHit && !rawHit;
            sums.falseMisses += rawHit && !decompressedHit;
        }
    });
    Sums segments;
    for (const Sums& sums : partSums) {
        segments.falseHits += sums.falseHits;
        segments.falseMisses += sums.falseMisses;
    }
    if (queries > 0) {
        error.segmentFalseHitPercent = 100.0 * double(segments.falseHits) / double(queries);
        error.segmentFalseMissPercent = 100.0 * double(segments.falseMisses) / double(queries);
    }
    return error;
}

}  // namespace strata
