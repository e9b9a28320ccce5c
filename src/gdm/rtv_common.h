// What the diffuse and the glossy RTV (gdm_rtv.cpp, gdm_rtv_glossy.cpp) share: the voxel stencil of their
// lookups and the voxel normals, one definition for both (gdm_rtv.h states the rules).
#pragma once

#include "strata/gdm/gdm.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace strata::detail {

inline int wrapIndex(int i, int n) {
    const int r = i % n;
    return r < 0 ? r + n : r;
}

// The normal at voxel (i, j, k): the normalised central-difference gradient of the signed distance volume
// (wrapping in u, v; one-sided at the bottom and top layers); +w where the gradient vanishes.
inline glm::dvec3 rtvDistanceNormal(const GdmDims& d, double height, const std::vector<float>& distance,
                                    int i, int j, int k) {
    const auto at = [&](int a, int b, int c) {
        return double(distance[std::size_t(wrapIndex(a, d.nx)) +
                               std::size_t(d.nx) *
                                   (std::size_t(wrapIndex(b, d.ny)) + std::size_t(d.ny) * std::size_t(c))]);
    };
    const int kLo = std::max(k - 1, 0), kHi = std::min(k + 1, d.nz - 1);
    const double dz = height / d.nz;
    const glm::dvec3 g((at(i + 1, j, k) - at(i - 1, j, k)) * d.nx / 2.0,
                       (at(i, j + 1, k) - at(i, j - 1, k)) * d.ny / 2.0,
                       kHi > kLo ? (at(i, j, kHi) - at(i, j, kLo)) / (double(kHi - kLo) * dz) : 0.0);
    const double length = glm::length(g);
    return length > 0.0 ? g / length : glm::dvec3(0.0, 0.0, 1.0);
}

// The RTV lookup's trilinear stencil at an isotropic-frame point (u, v, z): between the voxel centres,
// wrapping in u and v, clamped in w; the corners inside the solid (distance < 0) left out and the others'
// weights renormalised; a cell whose corners all lie inside reads the nearest outside voxel centre of the
// 4 x 4 x 4 block around it (none: count 0).
struct RtvStencil {
    std::array<std::size_t, 8> voxel{};
    std::array<double, 8> weight{};
    int count = 0;
};

inline RtvStencil rtvStencilAt(const GdmDims& d, double height, const std::vector<float>& distance,
                               const glm::dvec3& point) {
    const auto index = [&](int i, int j, int k) {
        return std::size_t(i) + std::size_t(d.nx) * (std::size_t(j) + std::size_t(d.ny) * std::size_t(k));
    };
    const double px = point.x - std::floor(point.x), py = point.y - std::floor(point.y);
    const double fx = px * d.nx - 0.5, fy = py * d.ny - 0.5;
    const double fz = std::clamp(point.z / height * d.nz - 0.5, 0.0, double(d.nz - 1));
    const double x0 = std::floor(fx), y0 = std::floor(fy), z0 = std::floor(fz);
    const double tx = fx - x0, ty = fy - y0, tz = fz - z0;
    const int i0 = int(x0), j0 = int(y0), k0 = int(z0);
    RtvStencil s;
    double total = 0.0;
    for (int c = 0; c < 8; ++c) {
        const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
        const double w = (di ? tx : 1.0 - tx) * (dj ? ty : 1.0 - ty) * (dk ? tz : 1.0 - tz);
        if (w <= 0.0) continue;
        const std::size_t v =
            index(wrapIndex(i0 + di, d.nx), wrapIndex(j0 + dj, d.ny), std::min(k0 + dk, d.nz - 1));
        if (distance[v] < 0.0f) continue;
        s.voxel[std::size_t(s.count)] = v;
        s.weight[std::size_t(s.count)] = w;
        ++s.count;
        total += w;
    }
    if (s.count == 0) {
        double best = std::numeric_limits<double>::infinity();
        for (int dk = -1; dk <= 2; ++dk)
            for (int dj = -1; dj <= 2; ++dj)
                for (int di = -1; di <= 2; ++di) {
                    const int kk = k0 + dk;
                    if (kk < 0 || kk >= d.nz) continue;
                    const std::size_t v = index(wrapIndex(i0 + di, d.nx), wrapIndex(j0 + dj, d.ny), kk);
                    if (distance[v] < 0.0f) continue;
                    const glm::dvec3 offset((di - tx) / d.nx, (dj - ty) / d.ny, (dk - tz) * height / d.nz);
                    const double length = glm::dot(offset, offset);
                    if (length < best) {
                        best = length;
                        s.voxel[0] = v;
                        s.weight[0] = 1.0;
                        s.count = 1;
                        total = 1.0;
                    }
                }
    }
    for (int c = 0; c < s.count; ++c) s.weight[std::size_t(c)] /= total;
    return s;
}

}  // namespace strata::detail
