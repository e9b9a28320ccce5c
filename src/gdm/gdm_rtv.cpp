#include "strata/gdm/gdm_rtv.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include "rtv_common.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace strata {
namespace {

using namespace detail;

constexpr int kCoefficients = kShCount * 3;  // floats per voxel

// Adds scale * (the stencil's transfer) to out[0 .. kCoefficients).
void accumulate(const std::vector<float>& transfer, const RtvStencil& s, double scale, double* out) {
    for (int c = 0; c < s.count; ++c) {
        const float* t = transfer.data() + s.voxel[std::size_t(c)] * kCoefficients;
        const double w = scale * s.weight[std::size_t(c)];
        for (int n = 0; n < kCoefficients; ++n) out[n] += w * double(t[n]);
    }
}

}  // namespace

GdmRtv bakeGdmRtv(const Gdm& gdm, const std::vector<float>& distance, const GdmAlbedo& albedo,
                  const GdmRtvOptions& options) {
    const GdmDims& dims = gdm.dims;
    const std::string what = "GDM RTV";
    validateGdmDims(dims, gdm.height, what);
    if (gdm.values.size() != dims.valueCount())
        throw Error(ErrorKind::InvalidInput, what + ": the GDM has " + std::to_string(gdm.values.size()) +
                                                 " values, its dims need " +
                                                 std::to_string(dims.valueCount()));
    if (distance.size() != dims.voxelCount())
        throw Error(ErrorKind::InvalidInput, what + ": the distance volume has " +
                                                 std::to_string(distance.size()) + " voxels, the GDM " +
                                                 std::to_string(dims.voxelCount()));
    if (!albedo) throw Error(ErrorKind::InvalidInput, what + ": no albedo");
    if (options.bounces < 0 || options.bounces > GdmRtvOptions::kMaxBounces)
        throw Error(ErrorKind::InvalidInput, what + ": bounces " + std::to_string(options.bounces) +
                                                 " is outside [0, " +
                                                 std::to_string(GdmRtvOptions::kMaxBounces) + "]");

    GdmRtv rtv;
    rtv.dims = dims;
    rtv.height = gdm.height;
    rtv.distance = distance;
    rtv.transfer.assign(dims.voxelCount() * kCoefficients, 0.0f);

    // Per direction sample: its vector, its exact cell solid angle, and its 16 basis values.
    const int directions = int(dims.directionCount());
    const auto directionCount = dims.directionCount();
    std::vector<glm::dvec3> dir(directionCount, glm::dvec3(0.0));
    std::vector<double> solidAngle(directionCount, 0.0);
    std::vector<ShVector> basis(directionCount);
    for (int t = 0; t < dims.ntheta; ++t) {
        const double theta0 = t * std::numbers::pi / dims.ntheta,
                     theta1 = (t + 1) * std::numbers::pi / dims.ntheta;
        const double omega = 2.0 * std::numbers::pi / dims.nphi * (std::cos(theta0) - std::cos(theta1));
        for (int s = 0; s < dims.nphi; ++s) {
            const std::size_t n = std::size_t(t * dims.nphi + s);
            dir[n] = gdmDirection(dims, t, s);
            solidAngle[n] = omega;
            basis[n] = shEvaluate(dir[n]);
        }
    }

    // Per voxel: the normal and rho / pi (linear RGB); inside voxels are skipped throughout.
    std::vector<glm::dvec3> normal(dims.voxelCount()), rho(dims.voxelCount());
    parallelFor(0, dims.nz * dims.ny, [&](int row) {
        const int j = row % dims.ny, k = row / dims.ny;
        for (int i = 0; i < dims.nx; ++i) {
            const std::size_t v = rtv.voxelIndex(i, j, k);
            if (distance[v] < 0.0f) continue;
            normal[v] = rtvDistanceNormal(rtv.dims, rtv.height, rtv.distance, i, j, k);
            // The albedo of the surface point the voxel stands for, not of the empty space at its centre
            // (a texture's albedo off the surface is whatever its volume holds there): the centre moved
            // along -n by its distance, wrapped in u, v and clamped to the slab.
            glm::dvec3 c = gdmVoxelCentre(dims, gdm.height, i, j, k) - double(distance[v]) * normal[v];
            c.x -= std::floor(c.x);
            c.y -= std::floor(c.y);
            rho[v] = albedo({c.x, c.y, std::clamp(c.z / gdm.height, 0.0, 1.0)});
        }
    });

    // Direct transfer: the sky seen through the top, cosine-weighted.
    parallelFor(0, dims.nz * dims.ny, [&](int row) {
        const int j = row % dims.ny, k = row / dims.ny;
        for (int i = 0; i < dims.nx; ++i) {
            const std::size_t v = rtv.voxelIndex(i, j, k);
            if (distance[v] < 0.0f) continue;
            ShVector sum{};
            for (int n = 0; n < directions; ++n) {
                const glm::dvec3& w = dir[std::size_t(n)];
                if (w.z <= 0.0 || gdm.values[v * dims.directionCount() + std::size_t(n)] != kGdmMiss)
                    continue;
                const double cosine = glm::dot(normal[v], w);
                if (cosine <= 0.0) continue;
                const double weight = cosine * solidAngle[std::size_t(n)];
                for (int q = 0; q < kShCount; ++q)
                    sum[std::size_t(q)] += weight * basis[std::size_t(n)][std::size_t(q)];
            }
            float* out = rtv.transfer.data() + v * kCoefficients;
            for (int q = 0; q < kShCount; ++q)
                for (int c = 0; c < 3; ++c) out[q * 3 + c] = float(sum[std::size_t(q)] / std::numbers::pi);
        }
    });
    if (options.bounces == 0) return rtv;

    // Interreflection: gather the previous iterate at the first hits, Jacobi style (each pass reads only the
    // previous one, so the result does not depend on the order or the thread count).
    const std::vector<float> direct = rtv.transfer;
    const double backOff = kGdmRtvBackOff * gdm.height / dims.nz;
    for (int b = 0; b < options.bounces; ++b) {
        // The previous iterate's outgoing transfer, rho T (the albedo of the voxel's surface point).
        std::vector<float> previous = rtv.transfer;
        for (std::size_t v = 0; v < dims.voxelCount(); ++v)
            for (int q = 0; q < kShCount; ++q)
                for (int c = 0; c < 3; ++c) {
                    float& value = previous[v * kCoefficients + std::size_t(q * 3 + c)];
                    value = float(double(value) * rho[v][c]);
                }
        parallelFor(0, dims.nz * dims.ny, [&](int row) {
            const int j = row % dims.ny, k = row / dims.ny;
            for (int i = 0; i < dims.nx; ++i) {
                const std::size_t v = rtv.voxelIndex(i, j, k);
                if (distance[v] < 0.0f) continue;
                const glm::dvec3 p = gdmVoxelCentre(dims, gdm.height, i, j, k);
                std::array<double, kCoefficients> gathered{};
                for (int n = 0; n < directions; ++n) {
                    const float d = gdm.values[v * dims.directionCount() + std::size_t(n)];
                    if (!(d > 0.0f) || d == kGdmMiss) continue;
                    const glm::dvec3& w = dir[std::size_t(n)];
                    const double cosine = glm::dot(normal[v], w);
                    if (cosine <= 0.0) continue;
                    glm::dvec3 q = p + std::max(double(d) - backOff, 0.0) * w;
                    q.x -= std::floor(q.x);
                    q.y -= std::floor(q.y);
                    accumulate(previous, rtvStencilAt(rtv.dims, rtv.height, rtv.distance, q),
                               cosine * solidAngle[std::size_t(n)], gathered.data());
                }
                float* out = rtv.transfer.data() + v * kCoefficients;
                const float* first = direct.data() + v * kCoefficients;
                for (int q = 0; q < kShCount; ++q)
                    for (int c = 0; c < 3; ++c) {
                        const std::size_t m = std::size_t(q * 3 + c);
                        out[m] = float(double(first[m]) + gathered[m] / std::numbers::pi);
                    }
            }
        });
    }
    return rtv;
}

ShColor gdmRtvTransferAt(const GdmRtv& rtv, const glm::dvec3& point) {
    std::array<double, kCoefficients> sum{};
    glm::dvec3 q = point;
    q.x -= std::floor(q.x);
    q.y -= std::floor(q.y);
    accumulate(rtv.transfer, rtvStencilAt(rtv.dims, rtv.height, rtv.distance, q), 1.0, sum.data());
    ShColor out{};
    for (int k = 0; k < kShCount; ++k)
        out[std::size_t(k)] =
            glm::dvec3(sum[std::size_t(k * 3)], sum[std::size_t(k * 3 + 1)], sum[std::size_t(k * 3 + 2)]);
    return out;
}

glm::dvec3 gdmRtvRadiance(const GdmRtv& rtv, const glm::dvec3& point, const ShColor& lighting) {
    const ShColor t = gdmRtvTransferAt(rtv, point);
    glm::dvec3 radiance(0.0);
    for (int k = 0; k < kShCount; ++k) radiance += t[std::size_t(k)] * lighting[std::size_t(k)];
    return radiance;
}

Image shadeGdmSceneRtv(const GdmSceneImages& hits, const GdmRtv& rtv, const ShColor& lighting,
                       const GdmAlbedo& albedo) {
    if (!albedo) throw Error(ErrorKind::InvalidInput, "GDM RTV shading: no albedo");
    const int width = hits.uvw.width(), height = hits.uvw.height();
    Image out(width, height, 3);
    parallelFor(0, height, [&](int j) {
        for (int i = 0; i < width; ++i) {
            if (hits.mask.at(i, j) <= 0.0f) continue;
            const glm::dvec3 point(hits.uvw.at(i, j, 0), hits.uvw.at(i, j, 1),
                                   double(hits.uvw.at(i, j, 2)) * rtv.height);
            const glm::dvec3 radiance = albedo({point.x, point.y, double(hits.uvw.at(i, j, 2))}) *
                                        gdmRtvRadiance(rtv, point, lighting);
            for (int c = 0; c < 3; ++c) out.at(i, j, c) = float(radiance[c]);
        }
    });
    return out;
}

GdmRtvSvd compressGdmRtv(const GdmRtv& rtv, int rank) {
    const std::size_t voxels = rtv.dims.voxelCount();
    if (rank < 1 || rank > kCoefficients)
        throw Error(ErrorKind::InvalidInput, "GDM RTV SVD: rank " + std::to_string(rank) +
                                                 " is outside [1, " + std::to_string(kCoefficients) + "]");
    if (rtv.transfer.size() != voxels * kCoefficients || rtv.distance.size() != voxels)
        throw Error(ErrorKind::InvalidInput, "GDM RTV SVD: the RTV's size does not match its dims");
    // A^T A, 48 x 48, in double.
    Eigen::Matrix<double, kCoefficients, kCoefficients> gram =
        Eigen::Matrix<double, kCoefficients, kCoefficients>::Zero();
    for (std::size_t v = 0; v < voxels; ++v) {
        const Eigen::Map<const Eigen::Matrix<float, kCoefficients, 1>> row(rtv.transfer.data() +
                                                                           v * kCoefficients);
        const Eigen::Matrix<double, kCoefficients, 1> r = row.cast<double>();
        gram.selfadjointView<Eigen::Lower>().rankUpdate(r);
    }
    gram = gram.selfadjointView<Eigen::Lower>();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, kCoefficients, kCoefficients>> solver(gram);
    // Eigen sorts the eigenvalues ascending; the singular values are their square roots, descending.
    GdmRtvSvd svd;
    svd.dims = rtv.dims;
    svd.height = rtv.height;
    svd.rank = rank;
    svd.distance = rtv.distance;
    svd.singularValues.resize(std::size_t(kCoefficients));
    for (int n = 0; n < kCoefficients; ++n)
        svd.singularValues[std::size_t(n)] =
            std::sqrt(std::max(solver.eigenvalues()(kCoefficients - 1 - n), 0.0));
    svd.basis.resize(std::size_t(rank) * kCoefficients);
    for (int r = 0; r < rank; ++r)
        for (int c = 0; c < kCoefficients; ++c)
            svd.basis[std::size_t(r * kCoefficients + c)] =
                float(solver.eigenvectors()(c, kCoefficients - 1 - r));
    // W = A V (= U S): the projection of each row on the kept right singular vectors.
    svd.weights.assign(voxels * std::size_t(rank), 0.0f);
    parallelForChunks(
        std::size_t(0), voxels,
        [&](std::size_t from, std::size_t to) {
            for (std::size_t v = from; v < to; ++v)
                for (int r = 0; r < rank; ++r) {
                    double sum = 0.0;
                    for (int c = 0; c < kCoefficients; ++c)
                        sum += double(rtv.transfer[v * kCoefficients + std::size_t(c)]) *
                               solver.eigenvectors()(c, kCoefficients - 1 - r);
                    svd.weights[v * std::size_t(rank) + std::size_t(r)] = float(sum);
                }
        },
        std::size_t(1024));
    return svd;
}

GdmRtv GdmRtvSvd::reconstruct() const {
    GdmRtv rtv;
    rtv.dims = dims;
    rtv.height = height;
    rtv.distance = distance;
    const std::size_t voxels = dims.voxelCount();
    rtv.transfer.assign(voxels * kCoefficients, 0.0f);
    for (std::size_t v = 0; v < voxels; ++v)
        for (int c = 0; c < kCoefficients; ++c) {
            double sum = 0.0;
            for (int r = 0; r < rank; ++r)
                sum += double(weights[v * std::size_t(rank) + std::size_t(r)]) *
                       double(basis[std::size_t(r * kCoefficients + c)]);
            rtv.transfer[v * kCoefficients + std::size_t(c)] = float(sum);
        }
    return rtv;
}

double GdmRtvSvd::relativeError() const {
    double kept = 0.0, total = 0.0;
    for (std::size_t n = 0; n < singularValues.size(); ++n) {
        const double s2 = singularValues[n] * singularValues[n];
        total += s2;
        if (int(n) < rank) kept += s2;
    }
    return total > 0.0 ? std::sqrt(std::max(total - kept, 0.0) / total) : 0.0;
}

Image gdmSurfaceHitMask(const GdmSceneImages& hits) {
    Image mask = hits.mask;
    constexpr float kEdge = 1e-6f;  // the reference stores a side's u or v as 0 (or the float below 1)
    for (int j = 0; j < mask.height(); ++j)
        for (int i = 0; i < mask.width(); ++i) {
            const float u = hits.uvw.at(i, j, 0), v = hits.uvw.at(i, j, 1);
            if (u < kEdge || u > 1.0f - kEdge || v < kEdge || v > 1.0f - kEdge) mask.at(i, j) = 0.0f;
        }
    return mask;
}

double gdmRelativeRmse(const Image& test, const Image& testMask, const Image& reference,
                       const Image& referenceMask) {
    const int width = reference.width(), height = reference.height();
    if (test.width() != width || test.height() != height || testMask.width() != width ||
        testMask.height() != height || referenceMask.width() != width || referenceMask.height() != height ||
        test.channels() != 3 || reference.channels() != 3)
        throw Error(ErrorKind::InvalidInput, "GDM relative RMSE: the images' sizes differ");
    double error = 0.0, norm = 0.0;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            if (testMask.at(i, j) <= 0.0f || referenceMask.at(i, j) <= 0.0f) continue;
            for (int c = 0; c < 3; ++c) {
                const double a = test.at(i, j, c), b = reference.at(i, j, c);
                error += (a - b) * (a - b);
                norm += b * b;
            }
        }
    return norm > 0.0 ? std::sqrt(error / norm) : 0.0;
}

}  // namespace strata
