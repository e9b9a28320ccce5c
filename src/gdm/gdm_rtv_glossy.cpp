#include "strata/gdm/gdm_rtv_glossy.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"
#include "strata/environment/sh_rotation.h"

#include "rtv_common.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace strata {
namespace {

using namespace detail;

constexpr double kPi = std::numbers::pi;
// The lobe quadrature: Gauss-Legendre nodes in z = cos(theta) over [0, 1] times uniform azimuths.
constexpr int kLobeNodes = 64;
constexpr int kLobeAzimuths = 256;

void checkShininess(double shininess, const std::string& what) {
    if (!(shininess >= 0.0 && shininess <= GdmGlossyOptions::kMaxShininess))
        throw Error(ErrorKind::InvalidInput, what + ": shininess " + formatNumber(shininess) +
                                                 " is outside [0, " +
                                                 formatNumber(GdmGlossyOptions::kMaxShininess) + "]");
}

void checkGdm(const Gdm& gdm, const std::string& what) {
    validateGdmDims(gdm.dims, gdm.height, what);
    if (gdm.values.size() != gdm.dims.valueCount())
        throw Error(ErrorKind::InvalidInput, what + ": the GDM has " + std::to_string(gdm.values.size()) +
                                                 " values, its dims need " +
                                                 std::to_string(gdm.dims.valueCount()));
}

// The lobe's angular factor max(x, 0)^s, with x^0 = 1 only where x > 0.
double lobePower(double x, double s) {
    return x > 0.0 ? std::pow(x, s) : 0.0;
}

// The quadrature rule of the lobe projection in the normal's frame (n = +z): the upper hemisphere only
// (the lobe times max(z, 0) is 0 below), its directions, weights and basis values.
struct LobeRule {
    std::vector<glm::dvec3> directions;
    std::vector<double> weights;
    std::vector<ShVector> basis;
};

const LobeRule& lobeRule() {
    static const LobeRule rule = [] {
        // Gauss-Legendre nodes on [-1, 1] by Newton's method on P_n, mapped to [0, 1].
        std::vector<double> nodes(kLobeNodes), weights(kLobeNodes);
        for (int i = 0; i < kLobeNodes; ++i) {
            double x = std::cos(kPi * (i + 0.75) / (kLobeNodes + 0.5));
            double derivative = 0.0;
            for (int iteration = 0; iteration < 100; ++iteration) {
                double p0 = 1.0, p1 = x;
                for (int n = 2; n <= kLobeNodes; ++n) {
                    const double p2 = ((2.0 * n - 1.0) * x * p1 - (n - 1.0) * p0) / n;
                    p0 = p1;
                    p1 = p2;
                }
                derivative = kLobeNodes * (x * p1 - p0) / (x * x - 1.0);
                const double step = p1 / derivative;
                x -= step;
                if (std::abs(step) < 1e-15) break;
            }
            nodes[std::size_t(i)] = 0.5 * (x + 1.0);
            weights[std::size_t(i)] = 0.5 * 2.0 / ((1.0 - x * x) * derivative * derivative);
        }
        LobeRule r;
        for (int i = 0; i < kLobeNodes; ++i) {
            const double z = nodes[std::size_t(i)];
            const double radius = std::sqrt(std::max(1.0 - z * z, 0.0));
            for (int j = 0; j < kLobeAzimuths; ++j) {
                const double phi = (j + 0.5) * 2.0 * kPi / kLobeAzimuths;
                const glm::dvec3 d(radius * std::cos(phi), radius * std::sin(phi), z);
                r.directions.push_back(d);
                r.weights.push_back(weights[std::size_t(i)] * 2.0 * kPi / kLobeAzimuths);
                r.basis.push_back(shEvaluate(d));
            }
        }
        return r;
    }();
    return rule;
}

// b in the normal's frame (n = +z) for the view (sin a, 0, cos a): by symmetry in y only the m >= 0
// coefficients are non-zero.
ShVector localLobe(double shininess, double angle) {
    const LobeRule& rule = lobeRule();
    const glm::dvec3 r(-std::sin(angle), 0.0, std::cos(angle));
    const double scale = (shininess + 2.0) / (2.0 * kPi);
    ShVector b{};
    for (std::size_t n = 0; n < rule.directions.size(); ++n) {
        const glm::dvec3& w = rule.directions[n];
        const double g = lobePower(glm::dot(w, r), shininess);
        if (g == 0.0) continue;
        const double weight = rule.weights[n] * scale * g * w.z;
        for (int k = 0; k < kShCount; ++k) b[std::size_t(k)] += weight * rule.basis[n][std::size_t(k)];
    }
    return b;
}

// A right-handed orthonormal frame (t, s, n) around the unit n (Duff et al. 2017), as the rotation with
// columns t, s, n: it maps the normal's frame to the tangent frame.
glm::dmat3 normalFrame(const glm::dvec3& n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    const glm::dvec3 t = glm::normalize(glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x));
    const glm::dvec3 s = glm::cross(n, t);
    return glm::dmat3(t, s, n);
}

// Turns the m >= 0 coefficients of a function symmetric about the x-z plane by the azimuth psi about +z:
// cos(m phi) -> cos(m (phi - psi)), whose coefficients are a cos(m psi) (cos term) and a sin(m psi) (sin
// term).
ShVector turnAboutZ(const ShVector& b, double psi) {
    ShVector out{};
    for (int l = 0; l < kShBands; ++l) {
        out[std::size_t(shIndex(l, 0))] = b[std::size_t(shIndex(l, 0))];
        for (int m = 1; m <= l; ++m) {
            const double a = b[std::size_t(shIndex(l, m))];
            out[std::size_t(shIndex(l, m))] = a * std::cos(m * psi);
            out[std::size_t(shIndex(l, -m))] = a * std::sin(m * psi);
        }
    }
    return out;
}

// The view w_o in the normal's frame: its angle to n and its azimuth about n.
void viewAngles(const glm::dmat3& frame, const glm::dvec3& view, double& angle, double& azimuth) {
    const double x = glm::dot(frame[0], view), y = glm::dot(frame[1], view), z = glm::dot(frame[2], view);
    angle = std::acos(std::clamp(z, -1.0, 1.0));
    azimuth = (x * x + y * y) > 1e-24 ? std::atan2(y, x) : 0.0;
}

// The lobe table over the angle a: kGdmGlossyLobeAngles rows, linear between them.
struct LobeTable {
    std::vector<ShVector> rows;
    LobeTable(double shininess, int angles) : rows(std::size_t(angles)) {
        parallelFor(0, angles, [&](int i) {
            rows[std::size_t(i)] = localLobe(shininess, angles > 1 ? i * kPi / (angles - 1) : 0.0);
        });
    }
    ShVector at(double angle) const {
        // Linear between the rows (at least 2: the M b bake's kGdmGlossyLobeAngles).
        const int angles = int(rows.size());
        const double f = std::clamp(angle / kPi * (angles - 1), 0.0, double(angles - 1));
        const int i = std::min(int(f), angles - 2);
        const double t = f - i;
        ShVector out{};
        for (int k = 0; k < kShCount; ++k)
            out[std::size_t(k)] = (1.0 - t) * rows[std::size_t(i)][std::size_t(k)] +
                                  t * rows[std::size_t(i + 1)][std::size_t(k)];
        return out;
    }
};

// The direction samples: vectors, exact cell solid angles and basis values (as bakeGdmRtv).
struct Directions {
    std::vector<glm::dvec3> dir;
    std::vector<double> solidAngle;
    std::vector<ShVector> basis;
    explicit Directions(const GdmDims& dims) {
        for (int t = 0; t < dims.ntheta; ++t) {
            const double theta0 = t * kPi / dims.ntheta, theta1 = (t + 1) * kPi / dims.ntheta;
            const double omega = 2.0 * kPi / dims.nphi * (std::cos(theta0) - std::cos(theta1));
            for (int s = 0; s < dims.nphi; ++s) {
                dir.push_back(gdmDirection(dims, t, s));
                solidAngle.push_back(omega);
                basis.push_back(shEvaluate(dir.back()));
            }
        }
    }
};

using Matrix16 = Eigen::Matrix<double, kShCount, kShCount, Eigen::RowMajor>;

Matrix16 shadowedMatrix(const Gdm& gdm, const Directions& directions, std::size_t voxel) {
    Matrix16 m = Matrix16::Zero();
    const std::size_t count = gdm.dims.directionCount();
    for (std::size_t n = 0; n < count; ++n) {
        if (directions.dir[n].z <= 0.0 || gdm.values[voxel * count + n] != kGdmMiss) continue;
        const Eigen::Map<const Eigen::Matrix<double, kShCount, 1>> y(directions.basis[n].data());
        m.selfadjointView<Eigen::Lower>().rankUpdate(y, directions.solidAngle[n]);
    }
    return m.selfadjointView<Eigen::Lower>();
}

// The bilinear view stencil: 4 views and weights.
struct ViewStencil {
    std::array<std::size_t, 4> view{};
    std::array<double, 4> weight{};
};

ViewStencil viewStencil(const GdmDims& d, const glm::dvec3& direction) {
    const glm::dvec3 w = glm::normalize(direction);
    const double theta = std::acos(std::clamp(w.z, -1.0, 1.0));
    double phi = std::atan2(w.y, w.x);
    if (phi < 0.0) phi += 2.0 * kPi;
    const int rows = d.ntheta / 2;
    const double ft = std::clamp(theta / kPi * d.ntheta - 0.5, 0.0, double(rows - 1));
    const double fp = phi / (2.0 * kPi) * d.nphi - 0.5;
    const double t0 = std::floor(ft), p0 = std::floor(fp);
    const double at = ft - t0, ap = fp - p0;
    const int ti = int(t0), si = int(p0);
    ViewStencil s;
    for (int c = 0; c < 4; ++c) {
        const int dt = c & 1, dp = (c >> 1) & 1;
        const int t = std::min(ti + dt, rows - 1), p = wrapIndex(si + dp, d.nphi);
        s.view[std::size_t(c)] = std::size_t(t) * std::size_t(d.nphi) + std::size_t(p);
        s.weight[std::size_t(c)] = (dt ? at : 1.0 - at) * (dp ? ap : 1.0 - ap);
    }
    return s;
}

// sum over the stencils of weight * value(k, voxel, view), per k.
template <class Value>
ShVector lookup(const GdmDims& d, double height, const std::vector<float>& distance, const glm::dvec3& point,
                const glm::dvec3& view, const Value& value) {
    const RtvStencil s = rtvStencilAt(d, height, distance, point);
    const ViewStencil vs = viewStencil(d, view);
    ShVector out{};
    for (int c = 0; c < s.count; ++c)
        for (int e = 0; e < 4; ++e) {
            const double w = s.weight[std::size_t(c)] * vs.weight[std::size_t(e)];
            if (w == 0.0) continue;
            for (int k = 0; k < kShCount; ++k)
                out[std::size_t(k)] += w * value(k, s.voxel[std::size_t(c)], vs.view[std::size_t(e)]);
        }
    return out;
}

glm::dvec3 radianceOf(const ShVector& g, const ShColor& lighting, double specular) {
    glm::dvec3 radiance(0.0);
    for (int k = 0; k < kShCount; ++k) radiance += g[std::size_t(k)] * lighting[std::size_t(k)];
    return specular * radiance;
}

template <class Rtv>
Image shadeScene(const GdmSceneImages& hits, const Rtv& rtv, const Camera& camera, const ShColor& lighting,
                 double specular) {
    if (!(std::isfinite(specular) && specular >= 0.0))
        throw Error(ErrorKind::InvalidInput,
                    "GDM glossy shading: specular " + formatNumber(specular) + " is not finite and >= 0");
    const int width = hits.uvw.width(), height = hits.uvw.height();
    Image out(width, height, 3);
    parallelFor(0, height, [&](int j) {
        for (int i = 0; i < width; ++i) {
            if (hits.mask.at(i, j) <= 0.0f) continue;
            const glm::dvec3 point(hits.uvw.at(i, j, 0), hits.uvw.at(i, j, 1),
                                   double(hits.uvw.at(i, j, 2)) * rtv.height);
            const glm::dvec3 view = -pixelRayDirection(camera, width, height, i + 0.5, j + 0.5);
            const glm::dvec3 radiance = gdmGlossyRadiance(rtv, point, view, lighting, specular);
            for (int c = 0; c < 3; ++c) out.at(i, j, c) = float(radiance[c]);
        }
    });
    return out;
}

}  // namespace

glm::dvec3 gdmGlossyView(const GdmDims& dims, int t, int s) {
    return gdmDirection(dims, t, s);
}

ShVector gdmPhongLobeSh(double shininess, const glm::dvec3& normal, const glm::dvec3& view) {
    checkShininess(shininess, "Phong lobe SH");
    const glm::dvec3 n = glm::normalize(normal), w = glm::normalize(view);
    // The normal's frame with w_o in its x-z plane: x along w_o's tangential part.
    glm::dvec3 x = w - glm::dot(w, n) * n;
    const glm::dmat3 base = normalFrame(n);
    x = glm::dot(x, x) > 1e-24 ? glm::normalize(x) : base[0];
    const glm::dmat3 frame(x, glm::cross(n, x), n);
    const double angle = std::acos(std::clamp(glm::dot(w, n), -1.0, 1.0));
    return shRotate(localLobe(shininess, angle), frame);
}

std::vector<double> gdmShadowedTransferMatrix(const Gdm& gdm, int i, int j, int k) {
    const std::string what = "GDM shadowed transfer matrix";
    checkGdm(gdm, what);
    const GdmDims& d = gdm.dims;
    if (i < 0 || i >= d.nx || j < 0 || j >= d.ny || k < 0 || k >= d.nz)
        throw Error(ErrorKind::InvalidInput, what + ": voxel (" + std::to_string(i) + ", " +
                                                 std::to_string(j) + ", " + std::to_string(k) +
                                                 ") is outside the grid");
    const Directions directions(d);
    const std::size_t voxel =
        std::size_t(i) + std::size_t(d.nx) * (std::size_t(j) + std::size_t(d.ny) * std::size_t(k));
    const Matrix16 m = shadowedMatrix(gdm, directions, voxel);
    std::vector<double> out(std::size_t(kShCount * kShCount));
    for (int r = 0; r < kShCount; ++r)
        for (int c = 0; c < kShCount; ++c) out[std::size_t(r * kShCount + c)] = m(r, c);
    return out;
}

namespace {

// The glossy bake's per-voxel work (bakeGdmGlossyRtv's contract), shared by the whole-volume bake and the
// chunked one (bakeCompressedGdmGlossyRtv), so that both give the same floats.
class GlossyBaker {
public:
    GlossyBaker(const Gdm& gdm, const std::vector<float>& distance, const GdmGlossyOptions& options)
        : mGdm(gdm),
          mDistance(distance),
          mOptions(options),
          mDirections(gdm.dims),
          // The lobe table only for G = M b (one empty row otherwise).
          mTable(options.shininess, options.method == GdmGlossyMethod::DirectSum ? 1 : kGdmGlossyLobeAngles),
          mScale((options.shininess + 2.0) / (2.0 * kPi)) {
        const GdmDims& dims = gdm.dims;
        for (int t = 0; t < dims.ntheta / 2; ++t)
            for (int s = 0; s < dims.nphi; ++s) mViews.push_back(gdmGlossyView(dims, t, s));
    }

    // Throws as bakeGdmGlossyRtv for its arguments.
    static void check(const Gdm& gdm, const std::vector<float>& distance, const GdmGlossyOptions& options,
                      const std::string& what) {
        checkGdm(gdm, what);
        const GdmDims& dims = gdm.dims;
        if (dims.ntheta < 2)
            throw Error(ErrorKind::InvalidInput,
                        what + ": Ntheta " + std::to_string(dims.ntheta) + " < 2 leaves no view row");
        if (distance.size() != dims.voxelCount())
            throw Error(ErrorKind::InvalidInput, what + ": the distance volume has " +
                                                     std::to_string(distance.size()) + " voxels, the GDM " +
                                                     std::to_string(dims.voxelCount()));
        checkShininess(options.shininess, what);
    }

    std::size_t viewCount() const { return mViews.size(); }

    // G of voxel v (x fastest): store(view, g) with the 16 coefficients g for each view; nothing for a voxel
    // inside the solid (its rows stay 0).
    template <class Store>
    void voxel(std::size_t v, const Store& store) const {
        const GdmDims& dims = mGdm.dims;
        if (mDistance[v] < 0.0f) return;
        const std::size_t nx = std::size_t(dims.nx), ny = std::size_t(dims.ny);
        const int i = int(v % nx), j = int((v / nx) % ny), k = int(v / (nx * ny));
        const glm::dvec3 n = rtvDistanceNormal(dims, mGdm.height, mDistance, i, j, k);
        const std::size_t views = mViews.size();
        if (mOptions.method == GdmGlossyMethod::DirectSum) {
            // G_k = sum over the visible direction samples of Y_k f_s max(n . w, 0) dOmega.
            std::vector<std::size_t> visible;
            for (std::size_t q = 0; q < dims.directionCount(); ++q)
                if (mDirections.dir[q].z > 0.0 && mGdm.values[v * dims.directionCount() + q] == kGdmMiss &&
                    glm::dot(n, mDirections.dir[q]) > 0.0)
                    visible.push_back(q);
            for (std::size_t view = 0; view < views; ++view) {
                const glm::dvec3& wo = mViews[view];
                const glm::dvec3 mirror = 2.0 * glm::dot(n, wo) * n - wo;
                ShVector g{};
                for (const std::size_t q : visible) {
                    const glm::dvec3& w = mDirections.dir[q];
                    const double f = lobePower(glm::dot(w, mirror), mOptions.shininess);
                    if (f == 0.0) continue;
                    const double weight = mScale * f * glm::dot(n, w) * mDirections.solidAngle[q];
                    for (int c = 0; c < kShCount; ++c)
                        g[std::size_t(c)] += weight * mDirections.basis[q][std::size_t(c)];
                }
                store(view, g.data());
            }
            return;
        }
        // G = M b = (M R) b_n: R (the ShRotation of the normal's frame) takes b from the normal's frame,
        // where the table holds it, to the tangent frame.
        const glm::dmat3 frame = normalFrame(n);
        const ShRotation rotation(frame);
        Matrix16 r;
        for (int c = 0; c < kShCount; ++c) {
            ShVector e{};
            e[std::size_t(c)] = 1.0;
            const ShVector column = rotation.apply(e);
            for (int q = 0; q < kShCount; ++q) r(q, c) = column[std::size_t(q)];
        }
        const Matrix16 m = shadowedMatrix(mGdm, mDirections, v) * r;
        for (std::size_t view = 0; view < views; ++view) {
            double angle = 0.0, azimuth = 0.0;
            viewAngles(frame, mViews[view], angle, azimuth);
            const ShVector b = turnAboutZ(mTable.at(angle), azimuth);
            const Eigen::Map<const Eigen::Matrix<double, kShCount, 1>> bv(b.data());
            const Eigen::Matrix<double, kShCount, 1> g = m * bv;
            store(view, g.data());
        }
    }

private:
    const Gdm& mGdm;
    const std::vector<float>& mDistance;
    GdmGlossyOptions mOptions;
    Directions mDirections;
    LobeTable mTable;
    double mScale;
    std::vector<glm::dvec3> mViews;
};

using MatrixD = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic>;
using RowsF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// Rows (voxels) of one coefficient's matrix converted to double at a time; the chunked bake bakes this many
// voxels at a time, so that both paths sum the Gram matrix in the same order.
constexpr std::size_t kChunk = 2048;

// An SVD with its sizes set and its maps zero, for `rank` terms.
GdmGlossyRtvSvd emptySvd(const GdmDims& dims, double height, double shininess, int rank, std::size_t views,
                         const std::vector<float>& distance) {
    GdmGlossyRtvSvd svd;
    svd.dims = dims;
    svd.height = height;
    svd.shininess = shininess;
    svd.rank = rank;
    svd.viewCount = views;
    svd.distance = distance;
    const std::size_t voxels = dims.voxelCount();
    svd.weights.assign(std::size_t(kShCount) * voxels * std::size_t(rank), 0.0f);
    svd.basis.assign(std::size_t(kShCount) * std::size_t(rank) * views, 0.0f);
    svd.singularValues.assign(std::size_t(kShCount) * views, 0.0);
    return svd;
}

// Adds rows^T rows to the lower half of `gram`.
void addToGram(MatrixD& gram, const Eigen::Map<const RowsF>& rows) {
    const MatrixD chunk = rows.cast<double>();
    gram.selfadjointView<Eigen::Lower>().rankUpdate(chunk.transpose());
}

// Coefficient k's singular values and E_k from its Gram matrix (lower half summed), into `svd`; returns
// E_k^T (views x rank) for the weights.
MatrixD finishBasis(MatrixD& gram, int k, GdmGlossyRtvSvd& svd) {
    const Eigen::Index columns = gram.cols();
    const std::size_t views = std::size_t(columns);
    gram = gram.selfadjointView<Eigen::Lower>();
    const Eigen::SelfAdjointEigenSolver<MatrixD> solver(gram);
    // Ascending eigenvalues; the singular values are their square roots, descending.
    for (Eigen::Index n = 0; n < columns; ++n)
        svd.singularValues[std::size_t(k) * views + std::size_t(n)] =
            std::sqrt(std::max(solver.eigenvalues()(columns - 1 - n), 0.0));
    const int rank = svd.rank;
    MatrixD basis = solver.eigenvectors().rightCols(rank).rowwise().reverse();  // views x rank
    for (int r = 0; r < rank; ++r)
        for (std::size_t v = 0; v < views; ++v)
            svd.basis[(std::size_t(k) * std::size_t(rank) + std::size_t(r)) * views + v] =
                float(basis(Eigen::Index(v), r));
    return basis;
}

// W_k's rows from `from` on: rows (of A_k) times E_k^T.
void storeWeights(const Eigen::Map<const RowsF>& rows, const MatrixD& basis, int k, std::size_t from,
                  GdmGlossyRtvSvd& svd) {
    const std::size_t voxels = svd.dims.voxelCount(), rank = std::size_t(svd.rank);
    const MatrixD w = rows.cast<double>() * basis;
    for (Eigen::Index row = 0; row < rows.rows(); ++row)
        for (std::size_t r = 0; r < rank; ++r)
            svd.weights[(std::size_t(k) * voxels + from + std::size_t(row)) * rank + r] =
                float(w(row, Eigen::Index(r)));
}

}  // namespace

GdmGlossyRtv bakeGdmGlossyRtv(const Gdm& gdm, const std::vector<float>& distance,
                              const GdmGlossyOptions& options) {
    GlossyBaker::check(gdm, distance, options, "GDM glossy RTV");
    const GdmDims& dims = gdm.dims;
    GdmGlossyRtv rtv;
    rtv.dims = dims;
    rtv.height = gdm.height;
    rtv.shininess = options.shininess;
    rtv.distance = distance;
    const std::size_t voxels = dims.voxelCount(), views = rtv.viewCount();
    rtv.transfer.assign(std::size_t(kShCount) * voxels * views, 0.0f);
    const GlossyBaker baker(gdm, distance, options);
    parallelFor(0, dims.nz * dims.ny, [&](int row) {
        const std::size_t first = std::size_t(row) * std::size_t(dims.nx);
        for (std::size_t v = first; v < first + std::size_t(dims.nx); ++v)
            baker.voxel(v, [&](std::size_t view, const double* g) {
                for (int q = 0; q < kShCount; ++q)
                    rtv.transfer[(std::size_t(q) * voxels + v) * views + view] = float(g[q]);
            });
    });
    return rtv;
}

GdmGlossyRtvSvd bakeCompressedGdmGlossyRtv(const Gdm& gdm, const std::vector<float>& distance,
                                           const GdmGlossyOptions& options, int rank) {
    const std::string what = "GDM glossy RTV";
    GlossyBaker::check(gdm, distance, options, what);
    const GdmDims& dims = gdm.dims;
    const std::size_t voxels = dims.voxelCount();
    const std::size_t views = std::size_t(dims.ntheta / 2) * std::size_t(dims.nphi);
    if (rank < 1 || std::size_t(rank) > views)
        throw Error(ErrorKind::InvalidInput, what + " SVD: rank " + std::to_string(rank) +
                                                 " is outside [1, " + std::to_string(views) + "]");
    const GlossyBaker baker(gdm, distance, options);
    GdmGlossyRtvSvd svd = emptySvd(dims, gdm.height, options.shininess, rank, views, distance);
    // One chunk of kChunk voxels, all coefficients: chunk[(k * count + row) * views + view].
    std::vector<float> chunk;
    const auto bakeChunk = [&](std::size_t from, std::size_t count) {
        chunk.assign(std::size_t(kShCount) * count * views, 0.0f);
        parallelFor(0, int(count), [&](int row) {
            baker.voxel(from + std::size_t(row), [&](std::size_t view, const double* g) {
                for (int q = 0; q < kShCount; ++q)
                    chunk[(std::size_t(q) * count + std::size_t(row)) * views + view] = float(g[q]);
            });
        });
    };
    const auto rowsOf = [&](int k, std::size_t count) {
        return Eigen::Map<const RowsF>(chunk.data() + std::size_t(k) * count * views, Eigen::Index(count),
                                       Eigen::Index(views));
    };
    // Pass 1: the Gram matrices, chunk by chunk (as compressGdmGlossyRtv sums them).
    std::vector<MatrixD> grams(std::size_t(kShCount),
                               MatrixD::Zero(Eigen::Index(views), Eigen::Index(views)));
    for (std::size_t from = 0; from < voxels; from += kChunk) {
        const std::size_t count = std::min(kChunk, voxels - from);
        bakeChunk(from, count);
        parallelFor(0, kShCount, [&](int k) { addToGram(grams[std::size_t(k)], rowsOf(k, count)); });
    }
    std::vector<MatrixD> bases(static_cast<std::size_t>(kShCount));
    parallelFor(0, kShCount, [&](int k) {
        bases[std::size_t(k)] = finishBasis(grams[std::size_t(k)], k, svd);
        grams[std::size_t(k)] = MatrixD();
    });
    // Pass 2: the same chunks baked again, their weights W_k = A_k E_k^T.
    for (std::size_t from = 0; from < voxels; from += kChunk) {
        const std::size_t count = std::min(kChunk, voxels - from);
        bakeChunk(from, count);
        parallelFor(0, kShCount,
                    [&](int k) { storeWeights(rowsOf(k, count), bases[std::size_t(k)], k, from, svd); });
    }
    return svd;
}

ShVector gdmGlossyTransferAt(const GdmGlossyRtv& rtv, const glm::dvec3& point, const glm::dvec3& view) {
    const std::size_t voxels = rtv.dims.voxelCount(), views = rtv.viewCount();
    return lookup(rtv.dims, rtv.height, rtv.distance, point, view,
                  [&](int k, std::size_t voxel, std::size_t v) {
                      return double(rtv.transfer[(std::size_t(k) * voxels + voxel) * views + v]);
                  });
}

glm::dvec3 gdmGlossyRadiance(const GdmGlossyRtv& rtv, const glm::dvec3& point, const glm::dvec3& view,
                             const ShColor& lighting, double specular) {
    return radianceOf(gdmGlossyTransferAt(rtv, point, view), lighting, specular);
}

ShVector gdmGlossyTransferAt(const GdmGlossyRtvSvd& svd, const glm::dvec3& point, const glm::dvec3& view) {
    const std::size_t voxels = svd.dims.voxelCount(), rank = std::size_t(svd.rank);
    return lookup(
        svd.dims, svd.height, svd.distance, point, view, [&](int k, std::size_t voxel, std::size_t v) {
            double sum = 0.0;
            const float* w = svd.weights.data() + (std::size_t(k) * voxels + voxel) * rank;
            for (std::size_t r = 0; r < rank; ++r)
                sum += double(w[r]) * double(svd.basis[(std::size_t(k) * rank + r) * svd.viewCount + v]);
            return sum;
        });
}

glm::dvec3 gdmGlossyRadiance(const GdmGlossyRtvSvd& svd, const glm::dvec3& point, const glm::dvec3& view,
                             const ShColor& lighting, double specular) {
    return radianceOf(gdmGlossyTransferAt(svd, point, view), lighting, specular);
}

GdmGlossyRtvSvd compressGdmGlossyRtv(const GdmGlossyRtv& rtv, int rank) {
    const std::string what = "GDM glossy RTV SVD";
    const std::size_t voxels = rtv.dims.voxelCount(), views = rtv.viewCount();
    if (views == 0 || rtv.transfer.size() != std::size_t(kShCount) * voxels * views ||
        rtv.distance.size() != voxels)
        throw Error(ErrorKind::InvalidInput, what + ": the RTV's sizes do not match its dims");
    if (rank < 1 || std::size_t(rank) > views)
        throw Error(ErrorKind::InvalidInput, what + ": rank " + std::to_string(rank) + " is outside [1, " +
                                                 std::to_string(views) + "]");
    GdmGlossyRtvSvd svd = emptySvd(rtv.dims, rtv.height, rtv.shininess, rank, views, rtv.distance);
    const auto rowsOf = [&](int k, std::size_t from, std::size_t count) {
        return Eigen::Map<const RowsF>(rtv.transfer.data() + (std::size_t(k) * voxels + from) * views,
                                       Eigen::Index(count), Eigen::Index(views));
    };
    // One coefficient per task: A_k^T A_k in double, its eigenvectors, W_k = A_k V_k.
    parallelFor(0, kShCount, [&](int k) {
        MatrixD gram = MatrixD::Zero(Eigen::Index(views), Eigen::Index(views));
        for (std::size_t from = 0; from < voxels; from += kChunk)
            addToGram(gram, rowsOf(k, from, std::min(kChunk, voxels - from)));
        const MatrixD basis = finishBasis(gram, k, svd);
        for (std::size_t from = 0; from < voxels; from += kChunk)
            storeWeights(rowsOf(k, from, std::min(kChunk, voxels - from)), basis, k, from, svd);
    });
    return svd;
}

GdmGlossyRtv GdmGlossyRtvSvd::reconstruct() const {
    GdmGlossyRtv rtv;
    rtv.dims = dims;
    rtv.height = height;
    rtv.shininess = shininess;
    rtv.distance = distance;
    const std::size_t voxels = dims.voxelCount(), views = viewCount, r = std::size_t(rank);
    rtv.transfer.assign(std::size_t(kShCount) * voxels * views, 0.0f);
    parallelFor(0, kShCount, [&](int k) {
        for (std::size_t v = 0; v < voxels; ++v) {
            const float* w = weights.data() + (std::size_t(k) * voxels + v) * r;
            float* out = rtv.transfer.data() + (std::size_t(k) * voxels + v) * views;
            for (std::size_t view = 0; view < views; ++view) {
                double sum = 0.0;
                for (std::size_t q = 0; q < r; ++q)
                    sum += double(w[q]) * double(basis[(std::size_t(k) * r + q) * views + view]);
                out[view] = float(sum);
            }
        }
    });
    return rtv;
}

double GdmGlossyRtvSvd::relativeError() const {
    double kept = 0.0, total = 0.0;
    for (std::size_t n = 0; n < singularValues.size(); ++n) {
        const double s2 = singularValues[n] * singularValues[n];
        total += s2;
        if (viewCount > 0 && n % viewCount < std::size_t(rank)) kept += s2;
    }
    return total > 0.0 ? std::sqrt(std::max(total - kept, 0.0) / total) : 0.0;
}

Image shadeGdmSceneGlossy(const GdmSceneImages& hits, const GdmGlossyRtv& rtv, const Camera& camera,
                          const ShColor& lighting, double specular) {
    return shadeScene(hits, rtv, camera, lighting, specular);
}

Image shadeGdmSceneGlossy(const GdmSceneImages& hits, const GdmGlossyRtvSvd& svd, const Camera& camera,
                          const ShColor& lighting, double specular) {
    return shadeScene(hits, svd, camera, lighting, specular);
}

}  // namespace strata
