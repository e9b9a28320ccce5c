// SVD compression of a GDM (Wang et al. 2004, Sec. 4.1): the layouts' index maps, the boundary substitution
// and the exit rule, exactness at full rank and on rank-1 inputs, error monotone in the rank, the refusals.
// The inputs are closed-form GDMs (gdm_analytic.h) on small dims, and once the baked built-in weave at the
// paper's size (BuiltinWeaveErrorAgainstRank).
#include "strata/core/error.h"
#include "strata/gdm/gdm_analytic.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"

#include <gtest/gtest.h>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace strata {
namespace {

const GdmDims kDims{8, 8, 4, 8, 16};
constexpr double kHeight = 0.25;
constexpr GdmLayout kLayouts[] = {GdmLayout::XyPhiByThetaZ, GdmLayout::XyzByThetaPhi,
                                  GdmLayout::XyByZThetaPhi};

int fullRank(const GdmDims& dims, GdmLayout layout) {
    return int(std::min(gdmLayoutRows(dims, layout), gdmLayoutCols(dims, layout)));
}

// The raw value with kGdmMiss replaced by the boundary distance: what the SVD approximates.
double substituted(const Gdm& gdm, int i, int j, int k, int t, int s) {
    const float value = gdm.at(i, j, k, t, s);
    return value == kGdmMiss ? gdmBoundaryDistance(gdm.dims, gdm.height, k, t) : double(value);
}

// Calls body(i, j, k, t, s) for every value of a GDM of `dims`.
template <class Body>
void forEachValue(const GdmDims& dims, const Body& body) {
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i)
                for (int t = 0; t < dims.ntheta; ++t)
                    for (int s = 0; s < dims.nphi; ++s) body(i, j, k, t, s);
}

// Largest |substituted raw - reconstruct| over every value.
double maxReconstructionError(const Gdm& gdm, const GdmSvd& svd) {
    double worst = 0.0;
    forEachValue(gdm.dims, [&](int i, int j, int k, int t, int s) {
        worst = std::max(worst,
                         std::abs(substituted(gdm, i, j, k, t, s) - double(reconstruct(svd, i, j, k, t, s))));
    });
    return worst;
}

TEST(GdmSvd, LayoutIndicesAreABijection) {
    const GdmDims dims{3, 2, 4, 2, 5};
    for (const GdmLayout layout : kLayouts) {
        const std::size_t rows = gdmLayoutRows(dims, layout), cols = gdmLayoutCols(dims, layout);
        EXPECT_EQ(rows * cols, dims.valueCount()) << toString(layout);
        std::vector<int> seen(rows * cols, 0);
        forEachValue(dims, [&](int i, int j, int k, int t, int s) {
            const GdmMatrixIndex index = gdmMatrixIndex(dims, layout, i, j, k, t, s);
            EXPECT_LT(index.row, rows);
            EXPECT_LT(index.col, cols);
            if (index.row < rows && index.col < cols) ++seen[index.row * cols + index.col];
        });
        EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(seen.size())) << toString(layout);
    }
    // The paper's layout: rows (x, y, phi) with phi fastest, columns (theta, z) with theta fastest.
    EXPECT_EQ(gdmLayoutRows(dims, GdmLayout::XyPhiByThetaZ), 3u * 2u * 5u);
    EXPECT_EQ(gdmLayoutCols(dims, GdmLayout::XyPhiByThetaZ), 2u * 4u);
    const GdmMatrixIndex index = gdmMatrixIndex(dims, GdmLayout::XyPhiByThetaZ, 1, 1, 3, 1, 2);
    EXPECT_EQ(index.row, 2u + 5u * (1u + 3u * 1u));
    EXPECT_EQ(index.col, 1u + 2u * 3u);
}

TEST(GdmSvd, BoundaryDistanceAndTheClosedFormSlab) {
    // Layer 3 of 4 (z = 3.5 / 4 H), direction t = 0 of 8 (theta = pi / 16, going up): (H - z) / cos(theta).
    EXPECT_NEAR(gdmBoundaryDistance(kDims, kHeight, 3, 0),
                0.5 / 4 * kHeight / std::cos(std::numbers::pi / 16), 1e-12);
    // Going down (t = 7, theta = 15 pi / 16): z / -cos(theta).
    EXPECT_NEAR(gdmBoundaryDistance(kDims, kHeight, 3, 7),
                3.5 / 4 * kHeight / std::cos(std::numbers::pi / 16), 1e-12);
    const Gdm slab = makeSlabGdm(kDims, kHeight, 0.5);
    EXPECT_EQ(slab.at(2, 5, 1, 7, 3), 0.0f);      // z = 1.5 / 4 H is inside the slab below w = .5
    EXPECT_EQ(slab.at(2, 5, 3, 0, 3), kGdmMiss);  // up, above the slab: leaves through the top
    // Down from z = 3.5 / 4 H to the slab's top at H / 2 (float: 1e-7 relative).
    EXPECT_NEAR(slab.at(2, 5, 3, 7, 3), 1.5 / 4 * kHeight / std::cos(std::numbers::pi / 16), 1e-7);
}

TEST(GdmSvd, FullRankReproducesTheSubstitutedGdm) {
    const Gdm gdm = makeWavySlabGdm(kDims, kHeight);
    ASSERT_GT(std::count(gdm.values.begin(), gdm.values.end(), kGdmMiss), 0);
    for (const GdmLayout layout : kLayouts) {
        const GdmSvd svd = compressGdm(gdm, fullRank(kDims, layout), layout);
        // Values are below 1.3 tile widths (the longest boundary distance); W and E are float (6e-8
        // relative) and the Gram is diagonalised in double: 1e-4 leaves two orders of magnitude of margin.
        EXPECT_LT(maxReconstructionError(gdm, svd), 1e-4) << toString(layout);
    }
}

TEST(GdmSvd, FullRankDecompressGivesTheMissesBackExactly) {
    // The flat slab: its hits lie at least H / 2 from the boundary, far beyond the exit tolerance, so the
    // exit rule must classify every value right.
    for (const Gdm& gdm : {makeSlabGdm(kDims, kHeight, 0.5), makeEmptyGdm(kDims, kHeight)}) {
        for (const GdmLayout layout : kLayouts) {
            const Gdm back = decompress(compressGdm(gdm, fullRank(kDims, layout), layout));
            ASSERT_EQ(back.dims, gdm.dims);
            ASSERT_EQ(back.values.size(), gdm.values.size());
            for (std::size_t at = 0; at < gdm.values.size(); ++at) {
                ASSERT_EQ(back.values[at] == kGdmMiss, gdm.values[at] == kGdmMiss) << toString(layout) << at;
                // As FullRankReproducesTheSubstitutedGdm.
                if (gdm.values[at] != kGdmMiss) {
                    ASSERT_NEAR(back.values[at], gdm.values[at], 1e-4);
                }
            }
        }
    }
}

TEST(GdmSvd, RankOneOfARankOneMatrixIsExact) {
    // The empty tile in the paper's layout: every value is the boundary distance of (k, t), and (theta, z)
    // are both columns, so A = 1 b^T.
    const Gdm empty = makeEmptyGdm(kDims, kHeight);
    const GdmSvd svd = compressGdm(empty, 1, GdmLayout::XyPhiByThetaZ);
    // As FullRankReproducesTheSubstitutedGdm.
    EXPECT_LT(maxReconstructionError(empty, svd), 1e-4);
    const Gdm back = decompress(svd);
    EXPECT_EQ(std::count(back.values.begin(), back.values.end(), kGdmMiss),
              std::ptrdiff_t(back.values.size()));

    // A literal outer product f(row) g(col), no misses, in each layout (tall and wide).
    for (const GdmLayout layout : kLayouts) {
        Gdm product;
        product.dims = kDims;
        product.height = kHeight;
        product.values.resize(kDims.valueCount());
        const std::size_t rows = gdmLayoutRows(kDims, layout), cols = gdmLayoutCols(kDims, layout);
        forEachValue(kDims, [&](int i, int j, int k, int t, int s) {
            const GdmMatrixIndex index = gdmMatrixIndex(kDims, layout, i, j, k, t, s);
            const double f = 0.5 + 0.4 * std::sin(0.7 * double(index.row) / double(rows) * 9.0);
            const double g = 0.2 + 0.1 * std::cos(double(index.col) / double(cols) * 5.0);
            product.values[product.valueIndex(i, j, k, t, s)] = float(f * g);
        });
        const GdmSvd one = compressGdm(product, 1, layout);
        // Values below 0.3; float maps: 1e-5 is a hundred times their rounding.
        EXPECT_LT(maxReconstructionError(product, one), 1e-5) << toString(layout);
    }
}

TEST(GdmSvd, ErrorDoesNotIncreaseWithRank) {
    const Gdm gdm = makeWavySlabGdm(kDims, kHeight);
    for (const GdmLayout layout : kLayouts) {
        double previous = HUGE_VAL;
        for (const int rank : {1, 2, 3, 4, 8, 16, 32, 64}) {
            if (rank > fullRank(kDims, layout)) break;
            const GdmSvdError error = measureGdmSvd(gdm, compressGdm(gdm, rank, layout), {1000, 1});
            // The truncated SVD's Frobenius error never grows with k; the maps' float rounding (1e-7 of a
            // value, 1e-5 voxels) may add noise of that order.
            EXPECT_LE(error.rmseVoxels, previous + 1e-5) << toString(layout) << " rank " << rank;
            previous = error.rmseVoxels;
        }
        // At full rank the RMSE is the float rounding (as above): far below a thousandth of a voxel.
        EXPECT_LT(previous, 1e-3) << toString(layout);
    }
}

TEST(GdmSvd, TruncationIsTheLowerRankCompression) {
    const Gdm gdm = makeWavySlabGdm(kDims, kHeight);
    const GdmSvd full = compressGdm(gdm, 8);
    for (const int rank : {1, 3, 8}) {
        const GdmSvd truncated = truncateGdmSvd(full, rank);
        const GdmSvd direct = compressGdm(gdm, rank);
        ASSERT_EQ(truncated.rank, rank);
        ASSERT_EQ(truncated.weights.size(), direct.weights.size());
        ASSERT_EQ(truncated.eigen.size(), direct.eigen.size());
        // The leading terms of an SVD are the lower-rank SVD (the same deterministic solver, the same
        // singular vectors): every reconstructed value agrees to float rounding of the sum (values below
        // 0.3; 1e-5 is a hundred times that).
        float worst = 0.0f;
        for (int k = 0; k < kDims.nz; ++k)
            for (int t = 0; t < kDims.ntheta; ++t)
                for (int i = 0; i < kDims.nx; i += 3)
                    worst = std::max(worst, std::abs(reconstruct(truncated, i, 1, k, t, 2) -
                                                     reconstruct(direct, i, 1, k, t, 2)));
        EXPECT_LT(worst, 1e-5f) << rank;
        EXPECT_EQ(truncated.singularValues,
                  std::vector<double>(full.singularValues.begin(), full.singularValues.begin() + rank));
        EXPECT_EQ(truncated.exitTolerance, full.exitTolerance);
    }
    EXPECT_THROW(truncateGdmSvd(full, 0), Error);
    try {
        truncateGdmSvd(full, 9);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("9"), std::string::npos) << e.what();
    }
}

TEST(GdmSvd, LargeGramGivesTheLargestSingularValues) {
    // (x, y) x (z, theta, phi) at 33 x 33 voxels: a 1089 x 2048 matrix whose 1089 x 1089 Gram is past the
    // size diagonalised whole, so its k largest eigenpairs come from the Lanczos solver. The singular
    // values must be A's largest, as a full SVD of the explicit matrix gives them, and the maps must give
    // the optimal error: sum over the values of (A - A_k)^2 = |A|^2 - sum of sigma_i^2 (Eckart-Young).
    const GdmDims dims{33, 33, 4, 16, 32};
    const Gdm gdm = makeWavySlabGdm(dims, kHeight);
    const GdmLayout layout = GdmLayout::XyByZThetaPhi;
    Eigen::MatrixXd a(Eigen::Index(gdmLayoutRows(dims, layout)), Eigen::Index(gdmLayoutCols(dims, layout)));
    forEachValue(dims, [&](int i, int j, int k, int t, int s) {
        const GdmMatrixIndex index = gdmMatrixIndex(dims, layout, i, j, k, t, s);
        a(Eigen::Index(index.row), Eigen::Index(index.col)) = substituted(gdm, i, j, k, t, s);
    });
    const Eigen::VectorXd sigma = Eigen::BDCSVD<Eigen::MatrixXd>(a).singularValues();
    constexpr int kRank = 8;
    const GdmSvd svd = compressGdm(gdm, kRank, layout);
    ASSERT_EQ(svd.singularValues.size(), std::size_t(kRank));
    double kept = 0.0;
    for (int r = 0; r < kRank; ++r) {
        // compressGdm reads A's entries as float (rounding 6e-8 of a value) and squares it in the Gram: the
        // two agree to about 1e-7 of sigma_1, two orders below the gaps between these singular values.
        EXPECT_NEAR(svd.singularValues[std::size_t(r)], sigma(r), 1e-6 * sigma(0)) << "sigma " << r;
        if (r > 0) {
            EXPECT_GT(sigma(r - 1) - sigma(r), 1e-4 * sigma(0)) << "gap below sigma " << r - 1;
        }
        kept += sigma(r) * sigma(r);
    }
    const double voxel = kHeight / dims.nz;
    const double optimal = std::sqrt((a.squaredNorm() - kept) / double(a.size())) / voxel;
    // The maps are float: their rounding adds about 1e-7 of a value, 1e-5 voxels here.
    EXPECT_NEAR(measureGdmSvd(gdm, svd, {0, 1}).rmseVoxels, optimal, 1e-4);
}

TEST(GdmSvd, BuiltinWeaveErrorAgainstRank) {
    // Issue 17's case: the built-in weave meshed at 64 per tile width, baked at 64 x 64 x 16 x 16 x 32,
    // compressed in the paper's layout. Measured: rank 8 2.10 voxels RMSE, 13 1.70, 14 1.64 (docs/gdm.md).
    // The truncated SVD is the best rank-k approximation (LargeGramGivesTheLargestSingularValues), so these
    // are the weave's own numbers; the bounds leave 3 % for changes to the mesh or the bake's float rounding.
    // The 1.7 voxels is not met at its rank 8, and is at 14 with that margin.
    const Gdm gdm = bakeGdm(meshMesostructure(makeMesostructure("weave"), 64), GdmDims{});
    const GdmSvdErrorParams noSegments{0, 1};
    EXPECT_LT(measureGdmSvd(gdm, compressGdm(gdm, 8), noSegments).rmseVoxels, 2.16);
    EXPECT_LE(measureGdmSvd(gdm, compressGdm(gdm, 14), noSegments).rmseVoxels, 1.7);
}

TEST(GdmSvd, MeasuresAndMemory) {
    const Gdm slab = makeSlabGdm(kDims, kHeight, 0.5);
    const int rank = fullRank(kDims, GdmLayout::XyPhiByThetaZ);  // 32 columns
    const GdmSvd svd = compressGdm(slab, rank, GdmLayout::XyPhiByThetaZ);
    EXPECT_DOUBLE_EQ(svd.exitTolerance, 0.5 * kHeight / kDims.nz);
    const GdmSvdError error = measureGdmSvd(slab, svd, {10000, 7});
    EXPECT_DOUBLE_EQ(error.voxelLength, kHeight / kDims.nz);
    // Exact up to float rounding (as FullRankReproducesTheSubstitutedGdm, in voxels of 1 / 16).
    EXPECT_LT(error.maxVoxels, 1e-3);
    EXPECT_EQ(error.exitFalseHitPercent, 0.0);
    EXPECT_EQ(error.exitFalseMissPercent, 0.0);
    EXPECT_EQ(error.segmentFalseHitPercent, 0.0);
    EXPECT_EQ(error.segmentFalseMissPercent, 0.0);
    // W: 1024 rows x 32, E: 32 x 32 floats.
    EXPECT_DOUBLE_EQ(error.memoryMiB, (1024.0 * 32.0 + 32.0 * 32.0) * 4.0 / (1 << 20));
    EXPECT_EQ(svd.singularValues.size(), 32u);
    EXPECT_TRUE(std::is_sorted(svd.singularValues.rbegin(), svd.singularValues.rend()));
}

TEST(GdmSvd, RefusesBadRanksAndBadGdms) {
    const Gdm gdm = makeSlabGdm(kDims, kHeight, 0.5);
    const auto message = [](const Gdm& input, int rank, GdmLayout layout) {
        try {
            compressGdm(input, rank, layout);
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message(gdm, 0, GdmLayout::XyPhiByThetaZ).find("rank 0"), std::string::npos);
    EXPECT_NE(message(gdm, -3, GdmLayout::XyPhiByThetaZ).find("rank -3"), std::string::npos);
    // 32 columns in the paper's layout, 64 rows in (x, y) x (z, theta, phi).
    EXPECT_NE(message(gdm, 33, GdmLayout::XyPhiByThetaZ).find("rank 33 must be in [1, 32]"),
              std::string::npos);
    EXPECT_EQ(message(gdm, 32, GdmLayout::XyPhiByThetaZ), "");
    EXPECT_NE(message(gdm, 65, GdmLayout::XyByZThetaPhi).find("rank 65 must be in [1, 64]"),
              std::string::npos);
    Gdm truncated = gdm;
    truncated.values.pop_back();
    EXPECT_NE(message(truncated, 4, GdmLayout::XyPhiByThetaZ).find("values"), std::string::npos);
    Gdm negative = gdm;
    negative.values[5] = -1.0f;
    EXPECT_NE(message(negative, 4, GdmLayout::XyPhiByThetaZ).find("value -1"), std::string::npos);
    Gdm nan = gdm;
    nan.values[5] = std::nanf("");
    EXPECT_NE(message(nan, 4, GdmLayout::XyPhiByThetaZ).find("value nan"), std::string::npos);
}

}  // namespace
}  // namespace strata
