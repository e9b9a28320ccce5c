#include "strata/gdm/mesostructure_mesh.h"

#include "level_set_mesh.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace strata {

namespace {

// Exact signed distance to the box [lo, hi].
double boxDistance(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const glm::dvec3 d = glm::abs(p - centre) - 0.5 * (hi - lo);
    return glm::length(glm::max(d, glm::dvec3(0.0))) + std::min(std::max(d.x, std::max(d.y, d.z)), 0.0);
}

}  // namespace

SolidMesh meshMesostructure(const Mesostructure& meso, int resolution) {
    if (resolution < kMinMeshResolution || resolution > kMaxMeshResolution)
        throw Error(ErrorKind::InvalidInput,
                    "mesostructure " + meso.name() + ": the mesh resolution must be in [" +
                        std::to_string(kMinMeshResolution) + ", " + std::to_string(kMaxMeshResolution) +
                        "], got " + std::to_string(resolution));
    detail::initializeOpenVdb();
    const double h = meso.height();
    const double dx = 1.0 / resolution;
    constexpr int kMargin = 3;
    const int nxy = resolution + 2 * kMargin;
    const int nz = static_cast<int>(std::ceil(h * resolution - 1e-9)) + 2 * kMargin;
    const glm::dvec3 lo(0.0), hi(1.0, 1.0, h);

    // Sample index (i, j, k) is voxel (i - margin, ...) whose centre is ((i - margin + .5) dx, ...):
    // OpenVDB's index-space point (i', j', k') maps to world (i' + .5) dx.
    std::vector<float> values(std::size_t(nxy) * std::size_t(nxy) * std::size_t(nz));
    parallelFor(0, nz, [&](int k) {
        for (int j = 0; j < nxy; ++j)
            for (int i = 0; i < nxy; ++i) {
                const glm::dvec3 p((i - kMargin + 0.5) * dx, (j - kMargin + 0.5) * dx,
                                   (k - kMargin + 0.5) * dx);
                const double d = std::max(meso.distance(p), boxDistance(p, lo, hi));
                values[(std::size_t(k) * nxy + std::size_t(j)) * nxy + std::size_t(i)] =
                    static_cast<float>(d);
            }
    });

    const float background = static_cast<float>(3.0 * dx);
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
    openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(dx);
    transform->postTranslate(openvdb::Vec3d(0.5 * dx));
    grid->setTransform(transform);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    {
        openvdb::FloatGrid::Accessor accessor = grid->getAccessor();
        for (int k = 0; k < nz; ++k)
            for (int j = 0; j < nxy; ++j)
                for (int i = 0; i < nxy; ++i) {
                    const float d = values[(std::size_t(k) * nxy + std::size_t(j)) * nxy + std::size_t(i)];
                    const openvdb::Coord c(i - kMargin, j - kMargin, k - kMargin);
                    if (std::abs(d) < background)
                        accessor.setValue(c, d);
                    else if (d < 0.0f)
                        accessor.setValueOff(c, -background);
                }
    }
    grid->pruneGrid();

    SolidMesh mesh = detail::meshLevelSet(*grid);
    if (mesh.triangles.empty())
        throw Error(ErrorKind::Runtime,
                    "mesostructure " + meso.name() + ": the mesh at resolution " +
                        std::to_string(resolution) +
                        " is empty (every part thinner than a voxel? use a higher resolution)");
    // volumeToMesh puts one vertex in each cell the surface crosses, at the mean of its edge crossings, so
    // where the solid meets a tile side the rim of the cut face is chamfered towards the inside: a groove
    // along the seam. A vertex within half a voxel of a tile side (in the cells that straddle it) is moved
    // onto it: the rims then lie on the sides (opposite sides get the same cut face, the samples being
    // periodic), though still about 0.3 voxel inside the true section in the side's plane.
    const float snap = static_cast<float>(0.5 * dx);
    for (glm::vec3& p : mesh.positions) {
        p = glm::clamp(p, glm::vec3(0.0f), glm::vec3(1.0f, 1.0f, static_cast<float>(h)));
        for (int c = 0; c < 2; ++c) {
            if (p[c] < snap) p[c] = 0.0f;
            if (p[c] > 1.0f - snap) p[c] = 1.0f;
        }
    }
    mesh.source = meso.name();
    mesh.height = h;
    return mesh;
}

}  // namespace strata
