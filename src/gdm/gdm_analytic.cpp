#include "strata/gdm/gdm_analytic.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace strata {

namespace {

// Fills every value with value(voxel centre, direction), in parallel over voxels.
template <typename Value>
Gdm makeGdm(const GdmDims& dims, double height, const char* what, const Value& value) {
    validateGdmDims(dims, height, what);
    Gdm gdm;
    gdm.dims = dims;
    gdm.height = height;
    gdm.values.resize(dims.valueCount());
    parallelFor(0, dims.ny * dims.nz, [&](int jk) {
        const int j = jk % dims.ny;
        const int k = jk / dims.ny;
        for (int i = 0; i < dims.nx; ++i) {
            const glm::dvec3 p = gdmVoxelCentre(dims, height, i, j, k);
            for (int t = 0; t < dims.ntheta; ++t)
                for (int s = 0; s < dims.nphi; ++s)
                    gdm.values[gdm.valueIndex(i, j, k, t, s)] = value(p, gdmDirection(dims, t, s));
        }
    });
    return gdm;
}

}  // namespace

Gdm makeEmptyGdm(const GdmDims& dims, double height) {
    return makeGdm(dims, height, "empty GDM", [](const glm::dvec3&, const glm::dvec3&) { return kGdmMiss; });
}

Gdm makeSlabGdm(const GdmDims& dims, double height, double level) {
    if (!(level >= 0.0 && level <= 1.0))
        throw Error(ErrorKind::InvalidInput,
                    "slab GDM: the level must be in [0, 1], got " + formatNumber(level));
    const double top = level * height;
    return makeGdm(dims, height, "slab GDM", [top](const glm::dvec3& p, const glm::dvec3& dir) {
        if (p.z < top) return 0.0f;
        if (dir.z >= 0.0 || top <= 0.0) return kGdmMiss;
        return static_cast<float>((p.z - top) / -dir.z);
    });
}

Gdm makeWavySlabGdm(const GdmDims& dims, double height) {
    const auto h = [height](double u, double v) {
        constexpr double kTwoPi = 2.0 * std::numbers::pi;
        return height * (0.3 + 0.3 * std::sin(kTwoPi * u) * std::sin(kTwoPi * v) +
                         0.15 * std::cos(kTwoPi * (u + 2.0 * v)));
    };
    return makeGdm(dims, height, "wavy slab GDM", [&h](const glm::dvec3& p, const glm::dvec3& dir) {
        const double below = h(p.x, p.y);
        if (p.z < below) return 0.0f;
        if (dir.z >= 0.0) return kGdmMiss;
        const glm::dvec3 q = p + dir * ((p.z - below) / -dir.z);
        const double ground = h(q.x, q.y);
        if (ground <= 0.0) return kGdmMiss;
        return static_cast<float>(std::max(0.0, (p.z - ground) / -dir.z));
    });
}

}  // namespace strata
