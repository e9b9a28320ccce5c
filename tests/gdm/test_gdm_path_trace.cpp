// The GDM path tracer (gdm_path_trace.h) against closed forms: a flat slab under a constant sky (zero
// variance) and under a cosine sky, the floor of an infinitely long slot and the side of a wall (2-D view
// factors to the sky), the energy of the bounces, determinism, the albedo helpers and bad input.
#include "strata/core/error.h"
#include "strata/gdm/gdm_path_trace.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/image/srgb.h"

#include "test_solids.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace strata {
namespace {

constexpr double kHeight = 0.5;
constexpr int kSize = 12;

// Two closed meshes as one (their union: the inside test counts winding >= 1).
SolidMesh unionOf(SolidMesh a, const SolidMesh& b) {
    const auto offset = std::uint32_t(a.positions.size());
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (auto t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    return a;
}

// The slab 0 <= z <= H / 2, reaching a quarter tile past every side (its translates overlap: a union).
SolidMesh halfSlab() {
    return boxMesh({-0.25f, -0.25f, 0.0f}, {1.25f, 1.25f, float(kHeight / 2)}, kHeight);
}

// A wall x in [0, 0.2], full height, infinitely long in y (its translates overlap in y): with its translates,
// slots of width kSlotWidth between x = 0.2 and x = 1.
constexpr double kWallEnd = 0.2;
constexpr double kSlotWidth = 1.0 - kWallEnd;
SolidMesh wall() {
    return boxMesh({0.0f, -0.25f, 0.0f}, {float(kWallEnd), 1.25f, float(kHeight)}, kHeight);
}

// The walls on a floor 0 <= z <= kFloor: the slot is kSlotWidth wide and kHeight - kFloor deep.
constexpr double kFloor = 0.1;
SolidMesh slot() {
    return unionOf(wall(), boxMesh({-0.25f, -0.25f, 0.0f}, {1.25f, 1.25f, float(kFloor)}, kHeight));
}

// Straight down from high above (x0, 0.5), with a narrow view: at kSize pixels it sees only the plane below
// within `halfWidth` of x0 (no wall: the rays are too steep to reach x = 0.2).
Camera downCamera(double x0, double halfWidth) {
    Camera camera;
    camera.eye = {x0, 0.5, 3.0};
    camera.target = {x0, 0.5, 0.0};
    camera.fovYDegrees = 2.0 * std::atan(halfWidth / 3.0) * 180.0 / 3.14159265358979;
    return camera;
}

GdmAlbedo gray(double rho) {
    return [rho](const glm::dvec3&) { return glm::dvec3(rho); };
}
EnvironmentRadiance constantSky(double l) {
    return [l](const glm::dvec3&) { return glm::dvec3(l); };
}

GdmPathTraceImages trace(const SolidMesh& solid, const GdmAlbedo& albedo, const EnvironmentRadiance& sky,
                         const Camera& camera, int samples, int bounces, std::uint64_t seed = 7) {
    GdmPathTraceOptions options;
    options.samplesPerPixel = samples;
    options.bounces = bounces;
    options.seed = seed;
    return pathTraceGdm(solid, albedo, sky, camera, kSize, kSize, options);
}

// The 2-D view factor (cosine-weighted fraction of the hemisphere, the directions being infinitely long in
// y) from a strip to the directions between the in-plane angles a1 < a2 from its normal: (sin a2 - sin a1)/2.
// A point of the slot's floor at distance a from one wall and b from the other, walls `depth` above it:
// the opening spans sin a = -a / sqrt(a^2 + depth^2) .. b / sqrt(b^2 + depth^2).
double floorSkyFraction(double a, double b, double depth) {
    return 0.5 * (a / std::hypot(a, depth) + b / std::hypot(b, depth));
}

TEST(GdmPathTrace, FlatSlabUnderAConstantSkyIsAlbedoTimesSky) {
    const double rho = 0.6, sky = 1.7;
    const Camera camera = downCamera(0.5, 0.3);
    const SolidMesh solid = halfSlab();
    const GdmSceneImages reference = renderGdmReference(solid, camera, {0.5, 0.5, 3.0}, kSize, kSize);
    for (int bounces : {0, 2}) {
        const GdmPathTraceImages images = trace(solid, gray(rho), constantSky(sky), camera, 8, bounces);
        for (int j = 0; j < kSize; ++j)
            for (int i = 0; i < kSize; ++i) {
                ASSERT_EQ(images.mask.at(i, j), 1.0f);
                ASSERT_EQ(reference.mask.at(i, j), 1.0f);
                // The top face sees only sky (nothing above it in the slab), every path escapes on its first
                // ray with weight rho: zero variance, and no interreflection to add. 1e-6: float storage of
                // a value ~1 (ulp 1.2e-7) after a sum of 8 doubles.
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(images.radiance.at(i, j, c), rho * sky, 1e-6);
            }
    }
}

TEST(GdmPathTrace, FlatSlabUnderACosineSkyIsTwoThirdsAlbedo) {
    // L(direction) = cos(theta) = direction.z above the horizon: radiance = rho / pi * integral of cos^2 over
    // the hemisphere = 2 rho / 3. It checks the cosine-weighted sampling and that +z is up.
    const double rho = 0.9;
    const EnvironmentRadiance sky = [](const glm::dvec3& d) { return glm::dvec3(std::max(d.z, 0.0)); };
    const int samples = 64;
    const GdmPathTraceImages images = trace(halfSlab(), gray(rho), sky, downCamera(0.5, 0.3), samples, 0);
    double mean = 0.0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) mean += double(images.radiance.at(i, j, 0));
    mean /= kSize * kSize;
    // One path's value is rho cos(theta) with cos(theta) drawn with density 2 cos (cosine-weighted): mean
    // 2/3, variance 1/2 - 4/9 = 1/18. The image mean averages 144 x 64 independent paths: sigma = rho
    // sqrt(1/18 / 9216) = 0.0022. 4 sigma.
    const double sigma = rho * std::sqrt(1.0 / 18.0 / (kSize * kSize * samples));
    EXPECT_NEAR(mean, 2.0 * rho / 3.0, 4.0 * sigma);
}

TEST(GdmPathTrace, SlotFloorSeesTheSkyFractionOfItsOpening) {
    // 0 bounces, white, L = 1: the radiance at a floor point is the cosine-weighted fraction of its
    // hemisphere open to the sky, the 2-D view factor through the slot's opening (floorSkyFraction). At the
    // slot's centre, a = b = 0.4 and depth 0.4: 1 / sqrt(2).
    const SolidMesh solid = slot();
    const Camera camera = downCamera(0.6, 0.15);
    const int samples = 256;
    const GdmPathTraceImages images = trace(solid, gray(1.0), constantSky(1.0), camera, samples, 0);
    const GdmSceneImages reference = renderGdmReference(solid, camera, {0.6, 0.5, 3.0}, kSize, kSize);
    const double depth = kHeight - kFloor;
    double error = 0.0, variance = 0.0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            ASSERT_EQ(images.mask.at(i, j), 1.0f);
            // Every pixel sees the floor (w = kFloor / H), 0.45 .. 0.75 in x.
            ASSERT_NEAR(reference.uvw.at(i, j, 2), kFloor / kHeight, 1e-6);
            const double x = reference.uvw.at(i, j, 0);
            const double f = floorSkyFraction(x - kWallEnd, 1.0 - x, depth);
            const double value = images.radiance.at(i, j, 0);
            // Each path is a Bernoulli draw (1 escapes, 0 blocked) of mean f: sigma = sqrt(f (1 - f) / N)
            // <= 0.5 / 16 = 0.031 per pixel. 5 sigma per pixel (one in 1.7 million).
            const double sigma = std::sqrt(f * (1.0 - f) / samples);
            EXPECT_NEAR(value, f, 5.0 * sigma) << i << ", " << j;
            error += value - f;
            variance += sigma * sigma;
        }
    // The mean over the 144 independent pixels: sigma = sqrt(sum of variances) / 144 (about 0.0026). 4 sigma.
    EXPECT_NEAR(error / (kSize * kSize), 0.0, 4.0 * std::sqrt(variance) / (kSize * kSize));
    EXPECT_NEAR(floorSkyFraction(0.4, 0.4, 0.4), 1.0 / std::sqrt(2.0), 1e-15);  // the closed form's check
}

TEST(GdmPathTrace, WallSideSeesOnlyTheSkyAboveTheOppositeWall) {
    // The walls alone (no floor), L = 1 in every direction, below the horizon too. A point of the wall's
    // side x = 0.2 at height z faces +x; the opposite wall (x = 1, up to H) hides the directions up to
    // angle a0 above the normal, sin a0 = (H - z) / sqrt(w^2 + (H - z)^2); what goes downwards leaves through
    // z = 0 and is blocked (the header's choice). Radiance = rho (1 - sin a0) / 2. Had the rays through the
    // bottom seen the sky, the lower half of the hemisphere (1/2) would add 0.5 rho.
    const double rho = 0.8;
    const SolidMesh solid = wall();
    Camera camera;
    camera.eye = {0.95, 0.5, 1.2};
    camera.target = {kWallEnd, 0.5, kHeight / 2};
    camera.fovYDegrees = 30.0;
    const int samples = 256;
    const GdmPathTraceImages images = trace(solid, gray(rho), constantSky(1.0), camera, samples, 0);
    const GdmSceneImages reference = renderGdmReference(solid, camera, camera.eye, kSize, kSize);
    int checked = 0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            ASSERT_EQ(images.mask.at(i, j), reference.mask.at(i, j));
            if (reference.mask.at(i, j) == 0.0f) continue;
            // The wall's side (x = 0.2, below its top): the cut faces and the wall's top are left out.
            const double u = reference.uvw.at(i, j, 0), w = reference.uvw.at(i, j, 2);
            if (std::abs(u - kWallEnd) > 1e-5 || w > 0.99) continue;
            const double above = kHeight - w * kHeight;
            const double f = 0.5 * (1.0 - above / std::hypot(kSlotWidth, above));
            // Bernoulli paths of mean f, weight rho: sigma = rho sqrt(f (1 - f) / N). 5 sigma per pixel.
            const double sigma = rho * std::sqrt(f * (1.0 - f) / samples);
            EXPECT_NEAR(images.radiance.at(i, j, 1), rho * f, 5.0 * sigma) << i << ", " << j;
            ++checked;
        }
    EXPECT_GT(checked, kSize * kSize / 4);
}

TEST(GdmPathTrace, BouncesAddLightUpToTheFurnaceBound) {
    const SolidMesh solid = slot();
    const Camera camera = downCamera(0.6, 0.15);
    const int samples = 64;
    // Gray: each bounce repeats the paths of the one before and only adds (the header), so the radiance
    // grows monotonically, exactly. It never exceeds rho L: a path adds rho^(k+1) L <= rho L at most once.
    const double rho = 0.5;
    std::vector<GdmPathTraceImages> byBounces;
    for (int bounces = 0; bounces <= 2; ++bounces)
        byBounces.push_back(trace(solid, gray(rho), constantSky(1.0), camera, samples, bounces));
    double gain = 0.0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            const float b0 = byBounces[0].radiance.at(i, j), b1 = byBounces[1].radiance.at(i, j),
                        b2 = byBounces[2].radiance.at(i, j);
            EXPECT_LE(b0, b1);
            EXPECT_LE(b1, b2);
            EXPECT_LE(b2, rho * (1.0 + 1e-6));  // 1e-6: float storage
            gain += double(b2 - b0);
        }
    // The floor sees the walls over 1 - f >= 0.29 of its hemisphere (floorSkyFraction <= 1 / sqrt(2)), and a
    // wall sees the sky over >= 0.276 of its own: the second order adds >= rho^2 0.29 0.276 = 0.02 on
    // average. Half of it, for the noise (sigma of the mean gain < 0.002).
    EXPECT_GT(gain / (kSize * kSize), 0.01);

    // The white furnace: rho = 1, L = 1. A path escapes to the sky unless each of its 17 rays (16 bounces)
    // is blocked; every point of the slot sees the sky over at least F_min = (1 - 0.4 / sqrt(0.8)) / 2 =
    // 0.276 of its hemisphere (the foot of a wall), so the expected radiance is >= 1 - 0.724^17 = 0.996.
    // Every pixel is <= 1 (a path adds 1 at most once). Bound 0.99: 0.006 below the expectation, and the
    // image mean's sigma is <= sqrt(0.004 / 9216) = 0.0007.
    const GdmPathTraceImages white = trace(solid, gray(1.0), constantSky(1.0), camera, samples, 16);
    double mean = 0.0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            EXPECT_LE(white.radiance.at(i, j), 1.0f + 1e-6f);  // float storage
            mean += double(white.radiance.at(i, j));
        }
    EXPECT_GT(mean / (kSize * kSize), 0.99);
}

TEST(GdmPathTrace, SameSeedSameImageBitForBit) {
    const SolidMesh solid = slot();
    const Camera camera = downCamera(0.6, 0.3);
    const EnvironmentRadiance sky = [](const glm::dvec3& d) {
        return glm::dvec3(0.2, 0.5, 1.0) * (1.0 + d.x);
    };
    const auto a = trace(solid, gray(0.7), sky, camera, 16, 2, 42);
    const auto b = trace(solid, gray(0.7), sky, camera, 16, 2, 42);
    const auto c = trace(solid, gray(0.7), sky, camera, 16, 2, 43);
    const std::size_t bytes = sizeof(float) * 3 * kSize * kSize;
    EXPECT_EQ(std::memcmp(a.radiance.row(0), b.radiance.row(0), bytes), 0);
    EXPECT_NE(std::memcmp(a.radiance.row(0), c.radiance.row(0), bytes), 0);
}

TEST(GdmPathTrace, MaskIsTheReferenceMaskAndAlbedoComesFromTheTexturePoint) {
    // A sphere seen obliquely (cut faces, misses and hits), albedo red = u: 0 bounces, L = 1. The mask is the
    // reference's; on the top of a slab (open to the sky) the radiance is the albedo at its texture point.
    const SolidMesh sphere = icosphere({0.5, 0.5, 0.2}, 0.3, 2, kHeight);
    Camera camera;
    camera.eye = {0.5, -0.8, 1.1};
    camera.target = {0.5, 0.5, 0.1};
    const GdmAlbedo albedo = [](const glm::dvec3& p) { return glm::dvec3(p.x, p.y, p.z); };
    const auto images = trace(sphere, albedo, constantSky(1.0), camera, 4, 1);
    const auto reference = renderGdmReference(sphere, camera, camera.eye, kSize, kSize);
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) EXPECT_EQ(images.mask.at(i, j), reference.mask.at(i, j));

    const auto top = trace(halfSlab(), albedo, constantSky(1.0), downCamera(0.5, 0.3), 2, 0);
    const auto topReference =
        renderGdmReference(halfSlab(), downCamera(0.5, 0.3), {0.5, 0.5, 3.0}, kSize, kSize);
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i)
            for (int c = 0; c < 3; ++c)  // 1e-6: float storage of both
                EXPECT_NEAR(top.radiance.at(i, j, c), topReference.uvw.at(i, j, c), 1e-6);
}

TEST(GdmPathTrace, VolumeAlbedoIsTrilinearInLinearValues) {
    // 2 x 1 x 1 voxels: u = 0.25 is voxel 0's centre, u = 0.75 voxel 1's, u = 0.5 halfway (and u = 0 halfway
    // too, wrapping). sRGB 255 -> 1, 0 -> 0, 188 -> srgbToLinear(188 / 255).
    const GdmAlbedo albedo = gdmVolumeAlbedo({255, 0, 188, 0, 0, 0}, 2, 1, 1);
    const double blue = srgbToLinear(188.0 / 255.0);
    // 1e-12: a few double roundings of values ~1.
    EXPECT_NEAR(albedo({0.25, 0.5, 0.5}).x, 1.0, 1e-12);
    EXPECT_NEAR(albedo({0.25, 0.5, 0.0}).z, blue, 1e-12);
    EXPECT_NEAR(albedo({0.75, 0.9, 1.0}).x, 0.0, 1e-12);
    EXPECT_NEAR(albedo({0.5, 0.5, 0.5}).x, 0.5, 1e-12);
    EXPECT_NEAR(albedo({0.0, 0.5, 0.5}).z, 0.5 * blue, 1e-12);

    const Mesostructure weave = makeMesostructure("weave");
    const glm::dvec3 p(0.3, 0.6, 0.5);
    const glm::dvec3 srgb = weave.sample({p.x, p.y, p.z * weave.height()}).albedo;
    EXPECT_NEAR(mesostructureLinearAlbedo(weave)(p).y, srgbToLinear(srgb.y), 1e-15);  // the same formula
}

TEST(GdmPathTrace, RefusesBadInput) {
    const SolidMesh solid = halfSlab();
    const Camera camera = downCamera(0.5, 0.3);
    GdmPathTraceOptions options;
    const auto throwsInvalid = [&](auto call) {
        try {
            call();
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput) << e.what();
            return;
        }
        ADD_FAILURE() << "no Error";
    };
    throwsInvalid([&] { pathTraceGdm(solid, gray(1), constantSky(1), camera, 0, 4, options); });
    throwsInvalid([&] { pathTraceGdm(solid, {}, constantSky(1), camera, 4, 4, options); });
    throwsInvalid([&] { pathTraceGdm(solid, gray(1), {}, camera, 4, 4, options); });
    Camera same = camera;
    same.target = same.eye;
    throwsInvalid([&] { pathTraceGdm(solid, gray(1), constantSky(1), same, 4, 4, options); });
    SolidMesh flat = solid;
    flat.height = 0.0;
    throwsInvalid([&] { pathTraceGdm(flat, gray(1), constantSky(1), camera, 4, 4, options); });
    options.samplesPerPixel = 0;
    throwsInvalid([&] { pathTraceGdm(solid, gray(1), constantSky(1), camera, 4, 4, options); });
    options.samplesPerPixel = 1;
    options.bounces = -1;
    throwsInvalid([&] { pathTraceGdm(solid, gray(1), constantSky(1), camera, 4, 4, options); });
    options.bounces = GdmPathTraceOptions::kMaxBounces + 1;
    throwsInvalid([&] { pathTraceGdm(solid, gray(1), constantSky(1), camera, 4, 4, options); });
    throwsInvalid([] { gdmVolumeAlbedo({1, 2, 3}, 2, 1, 1); });
    throwsInvalid([] { gdmVolumeAlbedo({}, 0, 1, 1); });
}

}  // namespace
}  // namespace strata
