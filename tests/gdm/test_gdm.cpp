// The GDM's sampling as CONVENTIONS §8 fixes it: voxel centres, direction samples, storage order, and the
// refusal of impossible sizes before anything is allocated.
#include "strata/core/error.h"
#include "strata/gdm/gdm.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <string>

namespace strata {
namespace {

TEST(GdmDims, DirectionsFollowTheConvention) {
    const GdmDims dims;  // 16 x 32
    // theta = (t + .5) pi / 16 from +w, phi = (s + .5) 2 pi / 32 from +u towards +v.
    const glm::dvec3 up = gdmDirection(dims, 0, 0);
    EXPECT_NEAR(up.z, std::cos(std::numbers::pi / 32), 1e-12);
    EXPECT_GT(up.x, 0.0);
    EXPECT_GT(up.y, 0.0);
    const glm::dvec3 down = gdmDirection(dims, 15, 8);  // phi = 8.5 / 32 turns: towards +v, a little -u
    EXPECT_NEAR(down.z, -std::cos(std::numbers::pi / 32), 1e-12);
    EXPECT_LT(down.x, 0.0);
    EXPECT_GT(down.y, 0.0);
    for (int t = 0; t < dims.ntheta; ++t)
        for (int s = 0; s < dims.nphi; ++s) EXPECT_NEAR(glm::length(gdmDirection(dims, t, s)), 1.0, 1e-12);
}

TEST(GdmDims, VoxelCentresAndStorageOrder) {
    const GdmDims dims{4, 2, 8, 2, 3};
    const glm::dvec3 c = gdmVoxelCentre(dims, 0.25, 1, 0, 7);
    EXPECT_DOUBLE_EQ(c.x, 1.5 / 4);
    EXPECT_DOUBLE_EQ(c.y, 0.5 / 2);
    EXPECT_DOUBLE_EQ(c.z, 7.5 / 8 * 0.25);  // z = w H, the top layer
    Gdm gdm;
    gdm.dims = dims;
    // x fastest, then y, then z; within a voxel phi fastest.
    EXPECT_EQ(gdm.valueIndex(0, 0, 0, 0, 1), 1u);
    EXPECT_EQ(gdm.valueIndex(0, 0, 0, 1, 0), 3u);
    EXPECT_EQ(gdm.valueIndex(1, 0, 0, 0, 0), 6u);
    EXPECT_EQ(gdm.valueIndex(0, 1, 0, 0, 0), 4u * 6u);
    EXPECT_EQ(gdm.valueIndex(0, 0, 1, 0, 0), 8u * 6u);
    EXPECT_EQ(dims.valueCount(), 4u * 2u * 8u * 6u);
}

TEST(GdmDims, RefusesZeroSizesBadThicknessAndAbsurdMemory) {
    const auto message = [](const GdmDims& dims, double height) {
        try {
            validateGdmDims(dims, height, "bake");
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(message(GdmDims{}, 0.25), "");
    EXPECT_NE(message(GdmDims{0, 64, 16, 16, 32}, 0.25).find("Nx must be >= 1"), std::string::npos);
    EXPECT_NE(message(GdmDims{64, 64, 16, 16, 0}, 0.25).find("Nphi"), std::string::npos);
    EXPECT_NE(message(GdmDims{}, 0.0).find("H must be a number > 0"), std::string::npos);
    EXPECT_NE(message(GdmDims{}, std::nan("")).find("H must be"), std::string::npos);
    // 4096^2 x 1024 voxels x 16 x 32 directions: 32 PiB, refused with the amount, before allocating.
    const std::string absurd = message(GdmDims{4096, 4096, 1024, 16, 32}, 0.25);
    EXPECT_NE(absurd.find("would need"), std::string::npos) << absurd;
    EXPECT_NE(absurd.find("MiB"), std::string::npos) << absurd;
}

}  // namespace
}  // namespace strata
