// The GDM bake (gdm_bake.h) against closed forms: an empty volume, a slab, a sphere and its wrapped
// neighbours, a sphere cut by the slab, cubes whose edges and corners pass a hair from voxel centres, and
// the periodicity of the result.
#include "strata/core/error.h"
#include "strata/gdm/gdm_bake.h"
#include "strata/gdm/solid_mesh_io.h"

#include "test_solids.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace strata {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Embree works in float: origins, directions and hit distances carry a few ulps of 1 tile width (~1e-7
// each); 1e-5 leaves room for their sum over several wrapped segments and is 10x under the 1e-4 that the
// bake must meet.
constexpr double kFloatTolerance = 1e-5;

// How far the tessellated sphere falls inside the true one: radius minus the least distance from the
// centre to a face's plane. The polyhedron contains the ball of radius (radius - this).
double tessellationDepth(const SolidMesh& mesh, glm::dvec3 centre, double radius) {
    double least = radius;
    for (const auto& f : mesh.triangles) {
        const glm::dvec3 a(mesh.positions[f[0]]), b(mesh.positions[f[1]]), c(mesh.positions[f[2]]);
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        least = std::min(least, std::abs(glm::dot(a - centre, n)));
    }
    return radius - least;
}

// Distance from `p` along unit `d` to the periodic spheres (centre + (i, j, 0), radius r) within the slab
// 0 <= z <= H; +inf if none is met before the ray leaves the slab. `wrapped` says whether the nearest is a
// translate rather than the sphere at (0, 0).
double periodicSphereDistance(glm::dvec3 p, glm::dvec3 d, glm::dvec3 centre, double r, double height,
                              bool* wrapped = nullptr) {
    const double tSlab = d.z > 0 ? (height - p.z) / d.z : d.z < 0 ? -p.z / d.z : 1e9;
    const int reach = int(std::ceil(std::min(tSlab, 1e3) * std::hypot(d.x, d.y))) + 2;
    double best = std::numeric_limits<double>::infinity();
    for (int j = -reach; j <= reach; ++j)
        for (int i = -reach; i <= reach; ++i) {
            const glm::dvec3 offset = p - (centre + glm::dvec3(i, j, 0));
            const double b = glm::dot(offset, d);
            const double disc = b * b - (glm::dot(offset, offset) - r * r);
            if (disc < 0) continue;
            const double t = -b - std::sqrt(disc);
            if (t >= 0 && t <= tSlab && t < best) {
                best = t;
                if (wrapped) *wrapped = i != 0 || j != 0;
            }
        }
    return best;
}

// Checks a bake of the tessellated sphere against the true sphere (outer bound) and the ball it contains
// (inner bound): the polyhedron's hit lies between the two. Returns {rays checked, of them wrapped}.
std::pair<int, int> expectSphereBounds(const Gdm& gdm, glm::dvec3 centre, double radius, double depth) {
    int checked = 0, wrappedCount = 0;
    const GdmDims& dims = gdm.dims;
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) {
                const glm::dvec3 p = gdmVoxelCentre(dims, gdm.height, i, j, k);
                // The sphere's translates nearest to p, in u and v.
                glm::dvec3 rel = p - centre;
                rel.x -= std::round(rel.x);
                rel.y -= std::round(rel.y);
                const double distance = glm::length(rel);
                for (int t = 0; t < dims.ntheta; ++t)
                    for (int s = 0; s < dims.nphi; ++s) {
                        const float value = gdm.at(i, j, k, t, s);
                        if (distance < radius - depth) {
                            EXPECT_EQ(value, 0.0f) << i << " " << j << " " << k;
                            continue;
                        }
                        if (distance <= radius) continue;  // between the polyhedron and the sphere: either
                        const glm::dvec3 d = gdmDirection(dims, t, s);
                        bool wrapped = false;
                        const double outer =
                            periodicSphereDistance(p, d, centre, radius, gdm.height, &wrapped);
                        const double inner = periodicSphereDistance(p, d, centre, radius - depth, gdm.height);
                        if (std::isinf(outer)) {
                            EXPECT_EQ(value, kInf) << i << " " << j << " " << k << " " << t << " " << s;
                            ++checked;
                        } else if (!std::isinf(inner)) {
                            EXPECT_GE(value, outer - kFloatTolerance)
                                << i << " " << j << " " << k << " " << t;
                            EXPECT_LE(value, inner + kFloatTolerance)
                                << i << " " << j << " " << k << " " << t;
                            ++checked;
                            wrappedCount += wrapped ? 1 : 0;
                        }  // else it grazes the sphere: hit or miss depends on the tessellation
                    }
            }
    return {checked, wrappedCount};
}

TEST(GdmBake, EmptyVolumeIsAMissEverywhere) {
    SolidMesh empty;
    empty.source = "nothing";
    std::vector<double> reported;
    const Gdm gdm = bakeGdm(empty, GdmDims{4, 3, 2, 4, 8}, [&](double f) { reported.push_back(f); });
    EXPECT_EQ(gdm.values.size(), GdmDims({4, 3, 2, 4, 8}).valueCount());
    for (const float value : gdm.values) EXPECT_EQ(value, kInf);
    ASSERT_FALSE(reported.empty());
    EXPECT_EQ(reported.back(), 1.0);
}

TEST(GdmBake, HandCheckedSmallCase) {
    // H = 1, a box filling the tile up to w = 0.5; one voxel column of 2: k = 0 at z = 0.25 (inside),
    // k = 1 at z = 0.75. Directions 2 x 4: theta = pi / 4 (up, misses) and 3 pi / 4 (down, meets the top
    // face after 0.25 / cos(pi / 4) = 0.25 sqrt(2)).
    const Gdm gdm = bakeGdm(boxMesh({0, 0, 0}, {1, 1, 0.5f}, 1.0), GdmDims{1, 1, 2, 2, 4});
    for (int s = 0; s < 4; ++s) {
        EXPECT_EQ(gdm.at(0, 0, 0, 0, s), 0.0f);
        EXPECT_EQ(gdm.at(0, 0, 0, 1, s), 0.0f);
        EXPECT_EQ(gdm.at(0, 0, 1, 0, s), kInf);
        EXPECT_NEAR(gdm.at(0, 0, 1, 1, s), 0.25 * std::sqrt(2.0), kFloatTolerance);
    }
}

TEST(GdmBake, SlabBelowHalfHeightCrossingTheTileSides) {
    // The box reaches a quarter tile past every side, so its translates overlap: the solid is their
    // union, the slab 0 <= z <= H / 2 (the winding number is 2 where copies overlap, still inside).
    const double height = 0.25;
    const GdmDims dims{8, 8, 8, 8, 16};
    const Gdm gdm = bakeGdm(boxMesh({-0.25f, -0.25f, 0}, {1.25f, 1.25f, float(height / 2)}, height), dims);
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) {
                const double z = gdmVoxelCentre(dims, height, i, j, k).z;
                for (int t = 0; t < dims.ntheta; ++t)
                    for (int s = 0; s < dims.nphi; ++s) {
                        const double cosTheta = gdmDirection(dims, t, s).z;
                        const float value = gdm.at(i, j, k, t, s);
                        if (z < height / 2)
                            EXPECT_EQ(value, 0.0f);
                        else if (cosTheta > 0)
                            EXPECT_EQ(value, kInf);
                        else
                            EXPECT_NEAR(value, (z - height / 2) / -cosTheta, kFloatTolerance)
                                << i << " " << j << " " << k << " " << t << " " << s;
                    }
            }
}

TEST(GdmBake, SphereMatchesTheRaySphereDistanceIncludingItsWrappedNeighbours) {
    const glm::dvec3 centre(0.5, 0.5, 0.25);
    const double radius = 0.2;
    const SolidMesh sphere = icosphere(centre, radius, 6, 0.5);
    // 6 subdivisions (81920 faces): the faces sit at most 2e-5 inside the sphere (1.4e-5 measured), so
    // that a ray meeting the ball at an incidence cosine >= 0.2 meets the polyhedron within 1e-4 of the
    // sphere. The bounds below hold whatever the incidence: the hit lies between the sphere and the ball
    // of radius (r - depth) that the polyhedron contains.
    const double depth = tessellationDepth(sphere, centre, radius);
    ASSERT_LT(depth, 2e-5);
    const Gdm gdm = bakeGdm(sphere, GdmDims{12, 12, 6, 8, 16});
    const auto [checked, wrapped] = expectSphereBounds(gdm, centre, radius, depth);
    // Most rays are checked (the rest graze the sphere within the tessellation band), and many of those meet
    // a neighbour one tile over: the bake wraps.
    EXPECT_GT(checked, 12 * 12 * 6 * 8 * 16 / 2);
    EXPECT_GT(wrapped, 1000);
}

TEST(GdmBake, GeometryOutsideTheSlabIsClippedAway) {
    // The same sphere in a shell of H = 0.25: it pokes out of the top and the bottom. Rays stop at the
    // slab, so they see only the part inside it, and voxels inside the sphere are inside.
    const glm::dvec3 centre(0.5, 0.5, 0.125);
    const double radius = 0.2;
    const SolidMesh sphere = icosphere(centre, radius, 6, 0.25);
    const double depth = tessellationDepth(sphere, centre, radius);
    const Gdm gdm = bakeGdm(sphere, GdmDims{8, 8, 4, 8, 16});
    const auto [checked, wrapped] = expectSphereBounds(gdm, centre, radius, depth);
    // As above: most rays are checked, some of them against neighbours.
    EXPECT_GT(checked, 8 * 8 * 4 * 8 * 16 / 4);
    EXPECT_GT(wrapped, 100);
}

TEST(GdmBake, InsideTestNearEdgesAndCorners) {
    // Voxel centres at 0.125 + 0.25 n (H = 1). Cube `in` reaches 1e-5 past the centres of voxels
    // i = 1..3, j, k = 1..2: those at i = 1 and 3 lie 1e-5 inside a corner, those at i = 2 1e-5 inside an
    // edge. Cube `out` stops 1e-5 short of the same centres, which are then outside, 1e-5 from an edge or
    // a corner.
    const GdmDims dims{4, 4, 4, 4, 8};
    const float e = 1e-5f;
    const Gdm in = bakeGdm(
        boxMesh({0.375f - e, 0.375f - e, 0.375f - e}, {0.875f + e, 0.625f + e, 0.625f + e}, 1.0), dims);
    const Gdm out = bakeGdm(
        boxMesh({0.375f + e, 0.375f + e, 0.375f + e}, {0.875f - e, 0.625f - e, 0.625f - e}, 1.0), dims);
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                const bool near = i >= 1 && j >= 1 && j <= 2 && k >= 1 && k <= 2;
                for (int t = 0; t < dims.ntheta; ++t)
                    for (int s = 0; s < dims.nphi; ++s) {
                        if (near)
                            EXPECT_EQ(in.at(i, j, k, t, s), 0.0f) << i << " " << j << " " << k;
                        else
                            EXPECT_GT(in.at(i, j, k, t, s), 0.0f) << i << " " << j << " " << k;
                        // Outside, at least the 1e-5 to the nearest face away (less the float tolerance
                        // of the hit, as a fraction of 1e-5: 1e-7).
                        EXPECT_GE(out.at(i, j, k, t, s), 1e-5f - 1e-7f) << i << " " << j << " " << k;
                    }
            }
}

TEST(GdmBake, PeriodicShiftsGiveTheSameBake) {
    // A sphere on the tile's corner crosses all four sides; the same solid is the sphere at the corner
    // (1, 0), and, moved by half a tile, the sphere at the centre with the voxels rolled by half the grid.
    const GdmDims dims{8, 8, 4, 8, 16};
    const Gdm corner = bakeGdm(icosphere({0, 0, 0.25}, 0.2, 3, 0.5), dims);
    const Gdm shifted = bakeGdm(icosphere({1, 0, 0.25}, 0.2, 3, 0.5), dims);
    const Gdm centred = bakeGdm(icosphere({0.5, 0.5, 0.25}, 0.2, 3, 0.5), dims);
    int misses = 0, zeros = 0;
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i)
                for (int t = 0; t < dims.ntheta; ++t)
                    for (int s = 0; s < dims.nphi; ++s) {
                        const float value = corner.at(i, j, k, t, s);
                        misses += value == kInf ? 1 : 0;
                        zeros += value == 0.0f ? 1 : 0;
                        // The three meshes' vertices differ by float rounding of the shifted positions
                        // (ulps of 1, ~1e-7): the float tolerance.
                        if (std::isinf(value)) {
                            EXPECT_EQ(shifted.at(i, j, k, t, s), kInf);
                            EXPECT_EQ(centred.at((i + 4) % 8, (j + 4) % 8, k, t, s), kInf);
                        } else {
                            EXPECT_NEAR(shifted.at(i, j, k, t, s), value, kFloatTolerance);
                            EXPECT_NEAR(centred.at((i + 4) % 8, (j + 4) % 8, k, t, s), value,
                                        kFloatTolerance);
                        }
                    }
    // Not a vacuous comparison: the bake has hits, misses and inside voxels.
    EXPECT_GT(misses, 0);
    EXPECT_GT(zeros, 0);
}

// Two closed meshes as one (a solid of separate parts).
SolidMesh joined(SolidMesh a, const SolidMesh& b) {
    const auto offset = std::uint32_t(a.positions.size());
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (const auto& t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    return a;
}

// The mesh as `strata gdm bake --mesh` reads it: written as OBJ, read back and checked (validateSolidMesh).
SolidMesh throughObj(const SolidMesh& mesh) {
    test::ScratchDir dir("gdm-bake-obj");
    writeSolidObj(dir / "mesh.obj", mesh);
    return readSolidObj(dir / "mesh.obj", mesh.height);
}

// Expects two bakes to agree value for value (to the float tolerance); returns the number of inside values
// (0), of misses and of hits, so that a caller can check the comparison is not vacuous.
std::array<int, 3> expectSameBake(const Gdm& a, const Gdm& b) {
    std::array<int, 3> counts{};
    EXPECT_EQ(a.values.size(), b.values.size());
    for (std::size_t n = 0; n < a.values.size() && n < b.values.size(); ++n) {
        if (std::isinf(a.values[n]))
            EXPECT_EQ(b.values[n], kInf) << n;
        else
            EXPECT_NEAR(b.values[n], a.values[n], kFloatTolerance) << n;
        ++counts[a.values[n] == 0.0f ? 0 : std::isinf(a.values[n]) ? 1 : 2];
    }
    return counts;
}

TEST(GdmBake, BoxCrossingASideBakesLikeItsTwoWrappedPieces) {
    // CONVENTIONS §8: geometry that crosses x = 1 wraps. The box [0.6, 1.3] x [0.2, 0.7] x [0, 0.1] (accepted
    // by readSolidObj: it lies less than a tile width out) is the same periodic solid as its two pieces cut
    // at the side, [0.6, 1] and [0, 0.3] in x, and as the box moved a tile back, [-0.4, 0.3]. Box sides lie
    // between voxel centres ((i + .5) / 10), the top (0.1) between layers.
    const double height = 0.25;
    const GdmDims dims{10, 10, 4, 8, 16};
    const Gdm crossing = bakeGdm(throughObj(boxMesh({0.6f, 0.2f, 0}, {1.3f, 0.7f, 0.1f}, height)), dims);
    const Gdm movedBack = bakeGdm(throughObj(boxMesh({-0.4f, 0.2f, 0}, {0.3f, 0.7f, 0.1f}, height)), dims);
    const Gdm pieces = bakeGdm(throughObj(joined(boxMesh({0.6f, 0.2f, 0}, {1.0f, 0.7f, 0.1f}, height),
                                                 boxMesh({0.0f, 0.2f, 0}, {0.3f, 0.7f, 0.1f}, height))),
                               dims);
    const auto counts = expectSameBake(pieces, crossing);
    expectSameBake(pieces, movedBack);
    EXPECT_GT(counts[0], 0);
    EXPECT_GT(counts[1], 0);
    EXPECT_GT(counts[2], 0);
    // The wrapped piece is solid: voxel (1, 4, 0), at (0.15, 0.45, 0.03), lies inside it.
    for (int t = 0; t < dims.ntheta; ++t) EXPECT_EQ(crossing.at(1, 4, 0, t, 0), 0.0f);
    // Straight-ish down from above the wrapped piece, voxel (1, 4, 3) at z = 0.21875 meets its top at 0.1.
    const glm::dvec3 down = gdmDirection(dims, dims.ntheta - 1, 0);
    EXPECT_NEAR(crossing.at(1, 4, 3, dims.ntheta - 1, 0), (0.21875 - 0.1) / -down.z, kFloatTolerance);
}

TEST(GdmBake, BoxOutOfTheShellBakesLikeTheClippedBox) {
    // CONVENTIONS §8: geometry outside 0 <= z <= H is clipped away. A box poking out of the top (z up to
    // H + 0.35) or the bottom (down to -0.3) bakes like the box cut at the slab.
    const double height = 0.25;
    const GdmDims dims{10, 10, 4, 8, 16};
    const Gdm above = bakeGdm(throughObj(boxMesh({0.2f, 0.3f, 0.12f}, {0.7f, 0.8f, 0.6f}, height)), dims);
    const Gdm cutTop = bakeGdm(throughObj(boxMesh({0.2f, 0.3f, 0.12f}, {0.7f, 0.8f, 0.25f}, height)), dims);
    const auto counts = expectSameBake(cutTop, above);
    EXPECT_GT(counts[0], 0);
    EXPECT_GT(counts[1], 0);
    EXPECT_GT(counts[2], 0);
    const Gdm below = bakeGdm(throughObj(boxMesh({0.2f, 0.3f, -0.3f}, {0.7f, 0.8f, 0.12f}, height)), dims);
    const Gdm cutBottom = bakeGdm(throughObj(boxMesh({0.2f, 0.3f, 0.0f}, {0.7f, 0.8f, 0.12f}, height)), dims);
    expectSameBake(cutBottom, below);
    // Up from under the box, voxel (4, 5, 1) at z = 0.09375 meets its bottom at 0.12.
    const glm::dvec3 up = gdmDirection(dims, 0, 0);
    EXPECT_NEAR(above.at(4, 5, 1, 0, 0), (0.12 - 0.09375) / up.z, kFloatTolerance);
}

TEST(GdmBake, ReportsProgressAndCancelsOnAnException) {
    const SolidMesh box = boxMesh({0.2f, 0.2f, 0}, {0.6f, 0.6f, 0.1f}, 0.25);
    std::vector<double> reported;
    (void)bakeGdm(box, GdmDims{4, 4, 4, 4, 8}, [&](double f) { reported.push_back(f); });
    ASSERT_FALSE(reported.empty());
    EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
    EXPECT_EQ(reported.back(), 1.0);
    EXPECT_THROW((void)bakeGdm(box, GdmDims{4, 4, 4, 4, 8}, [](double) { throw std::runtime_error("stop"); }),
                 std::runtime_error);
}

TEST(GdmBake, RefusesBadInputNamingTheSource) {
    const auto message = [](const SolidMesh& mesh, const GdmDims& dims) {
        try {
            (void)bakeGdm(mesh, dims);
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
            return std::string(e.what());
        }
        return std::string();
    };
    SolidMesh box = boxMesh({0, 0, 0}, {1, 1, 0.1f}, 0.25);
    EXPECT_NE(message(box, GdmDims{0, 4, 4, 4, 4}).find("GDM bake of box: Nx"), std::string::npos);
    box.triangles[3][1] = 8;
    EXPECT_NE(message(box, GdmDims{2, 2, 2, 2, 2}).find("refers to position 8 of 8"), std::string::npos);
    box = boxMesh({0, 0, 0}, {1, 1, 0.1f}, 0.25);
    box.positions[2].z = std::nanf("");
    EXPECT_NE(message(box, GdmDims{2, 2, 2, 2, 2}).find("position 2 is not finite"), std::string::npos);
}

}  // namespace
}  // namespace strata
