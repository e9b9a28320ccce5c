// The signed distance volume (strata/gdm/gdm_distance.h): exact on a box that wraps across the tile's side,
// within the in- and circumscribed spheres' bounds on an icosphere, negative exactly where the bake's
// occupancy is 1; and its optional file in the GDM asset.
#include "strata/gdm/gdm_distance.h"

#include "strata/core/error.h"
#include "strata/gdm/gdm_asset.h"
#include "strata/gdm/gdm_bake.h"

#include "test_solids.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace strata {
namespace {

namespace fs = std::filesystem;

// The signed distance from p to the box [lo, hi] (negative inside).
double boxDistance(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    const glm::dvec3 q = glm::abs(p - centre) - half;
    const double outside = glm::length(glm::max(q, glm::dvec3(0.0)));
    const double inside = std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
    return outside + inside;
}

std::size_t voxelAt(const GdmDims& dims, int i, int j, int k) {
    return (std::size_t(k) * std::size_t(dims.ny) + std::size_t(j)) * std::size_t(dims.nx) + std::size_t(i);
}

TEST(GdmDistance, IsExactOnABoxThatWraps) {
    // The box crosses x = 1: its translate by -1 covers x in [0, 0.2], so voxels near x = 0 are inside.
    const glm::dvec3 lo(0.7, 0.2, 0.05), hi(1.2, 0.6, 0.15);
    const double height = 0.25;
    const GdmDims dims{16, 16, 8, 2, 4};
    const std::vector<float> distance = bakeGdmDistance(boxMesh(glm::vec3(lo), glm::vec3(hi), height), dims);
    ASSERT_EQ(distance.size(), dims.voxelCount());
    int inside = 0, clamped = 0;
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) {
                const glm::dvec3 p = gdmVoxelCentre(dims, height, i, j, k);
                double expected = std::numeric_limits<double>::max();
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const glm::dvec3 shift(di, dj, 0.0);
                        expected = std::min(expected, boxDistance(p, lo + shift, hi + shift));
                    }
                expected = std::min(expected, kGdmDistanceReach);
                inside += expected < 0.0;
                clamped += expected == kGdmDistanceReach;
                // The closest point is computed in double from float corners (the box's are exact in float
                // up to 1.2f - 1 ~ 3e-8) and stored as float (values <= 0.2: ulp 1.5e-8).
                EXPECT_NEAR(distance[voxelAt(dims, i, j, k)], expected, 1e-6) << i << " " << j << " " << k;
            }
    EXPECT_GT(inside, 0);
    EXPECT_GT(clamped, 0);  // the far corner of the tile is more than kGdmDistanceReach from every copy
    // The wrapped part: voxel (1, 6, 3), centre (0.09375, 0.40625, 0.109375), lies in the translate
    // [-0.3, 0.2] x [0.2, 0.6] x [0.05, 0.15], nearest to its top face.
    EXPECT_NEAR(distance[voxelAt(dims, 1, 6, 3)], 0.109375 - 0.15, 1e-6);
}

TEST(GdmDistance, LiesBetweenTheSpheresAroundAnIcosphereAndAgreesWithTheBake) {
    const glm::dvec3 centre(0.5, 0.45, 0.12);
    const double radius = 0.1, height = 0.25;
    const SolidMesh sphere = icosphere(centre, radius, 2, height);
    // Its insphere: the smallest distance from the centre to a face's plane.
    double inner = radius;
    for (const auto& t : sphere.triangles) {
        const glm::dvec3 a(sphere.positions[t[0]]), b(sphere.positions[t[1]]), c(sphere.positions[t[2]]);
        inner = std::min(inner, glm::dot(a - centre, glm::normalize(glm::cross(b - a, c - a))));
    }
    ASSERT_GT(inner, 0.95 * radius);
    const GdmDims dims{16, 16, 8, 2, 4};
    const std::vector<float> distance = bakeGdmDistance(sphere, dims);
    const std::vector<std::uint8_t> occupancy = gdmOccupancy(bakeGdm(sphere, dims));
    int inside = 0;
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) {
                const glm::dvec3 p = gdmVoxelCentre(dims, height, i, j, k);
                double r = std::numeric_limits<double>::max();
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di)
                        r = std::min(r, glm::length(p - centre - glm::dvec3(di, dj, 0)));
                const float d = distance[voxelAt(dims, i, j, k)];
                // The insphere lies in the polyhedron, which lies in the sphere: its signed distance is
                // between theirs (1e-6: float corners and storage, as above), clamped at the reach.
                EXPECT_GE(d, std::min(r - radius, kGdmDistanceReach) - 1e-6) << i << " " << j << " " << k;
                EXPECT_LE(d, std::min(r - inner, kGdmDistanceReach) + 1e-6) << i << " " << j << " " << k;
                // The sign is the bake's inside test, voxel for voxel.
                const bool occupied = occupancy[voxelAt(dims, i, j, k)] == 1;
                inside += occupied;
                EXPECT_EQ(occupied, d <= 0.0f) << i << " " << j << " " << k;
            }
    EXPECT_GT(inside, 8);
    // No triangles: nothing within reach.
    SolidMesh empty = sphere;
    empty.triangles.clear();
    for (const float d : bakeGdmDistance(empty, dims)) ASSERT_EQ(d, float(kGdmDistanceReach));
}

TEST(GdmDistance, RoundTripsInTheAssetAndIsOptional) {
    test::ScratchDir dir("gdm-asset-distance");
    const SolidMesh box = boxMesh({0.2f, 0.2f, 0.05f}, {0.6f, 0.7f, 0.2f}, 0.25);
    const GdmDims dims{4, 4, 2, 2, 4};
    const Gdm gdm = bakeGdm(box, dims);
    GdmAsset asset;
    asset.svd = compressGdm(gdm, 2);
    asset.occupancy = gdmOccupancy(gdm);
    asset.distance = bakeGdmDistance(box, dims);
    asset.source = "box";
    writeGdmAsset(dir / "a", asset);
    EXPECT_TRUE(fs::exists(dir / "a" / "distance.f32"));
    const GdmAsset back = readGdmAsset(dir / "a");
    ASSERT_EQ(back.distance.size(), asset.distance.size());
    EXPECT_EQ(std::memcmp(back.distance.data(), asset.distance.data(), asset.distance.size() * sizeof(float)),
              0);
    // Rewritten without it (an older bake's asset): the file goes, and the asset reads with none.
    asset.distance.clear();
    writeGdmAsset(dir / "a", asset);
    EXPECT_FALSE(fs::exists(dir / "a" / "distance.f32"));
    EXPECT_TRUE(readGdmAsset(dir / "a").distance.empty());
    // What could not be read back is not written.
    asset.distance.assign(dims.voxelCount() - 1, 0.0f);
    EXPECT_THROW(writeGdmAsset(dir / "b", asset), Error);
    asset.distance.assign(dims.voxelCount(), std::numeric_limits<float>::infinity());
    EXPECT_THROW(writeGdmAsset(dir / "b", asset), Error);
}

}  // namespace
}  // namespace strata
