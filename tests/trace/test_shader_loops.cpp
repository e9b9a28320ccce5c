// The shaders' own search loops (shaders/shared/relief_search.h, maxmip.h, cone.h), compiled as C++ with the
// fetches of strata/trace/shader_loops.h, against the exact tracer on a small literal map: maxmip and cone
// find the exact first hit, the relief search brackets a crossing of the surface within its final window,
// and the light-ray search never shadows a point the exact tracer sees lit.
#include "strata/image/image.h"
#include "strata/relief/cone_map.h"
#include "strata/relief/max_mip.h"
#include "strata/trace/heightfield_tracer.h"
#include "strata/trace/shader_loops.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <vector>

namespace strata {
namespace {

// 8 x 8 texels (rows top first, as Image stores them): a spike at the top (0), a pit at the bottom (1), a
// ridge, a slope and a plateau, so that rays cross every kind of cell and every level of the maximum mipmap.
// Values are multiples of 1/8, exact in 16 bits as the textures hold them.
constexpr float kMap[8][8] = {
    {0.500f, 0.500f, 0.625f, 0.750f, 0.875f, 1.000f, 0.875f, 0.750f},
    {0.500f, 0.000f, 0.500f, 0.750f, 0.875f, 0.875f, 0.750f, 0.625f},
    {0.500f, 0.500f, 0.500f, 0.250f, 0.250f, 0.250f, 0.250f, 0.500f},
    {0.750f, 0.750f, 0.750f, 0.250f, 0.125f, 0.125f, 0.250f, 0.500f},
    {1.000f, 0.875f, 0.750f, 0.250f, 0.125f, 0.125f, 0.250f, 0.500f},
    {0.875f, 0.750f, 0.625f, 0.500f, 0.375f, 0.250f, 0.250f, 0.500f},
    {0.750f, 0.625f, 0.500f, 0.375f, 1.000f, 0.125f, 0.125f, 0.375f},
    {0.625f, 0.500f, 0.375f, 0.250f, 0.125f, 0.000f, 0.000f, 0.250f},
};
// Tile widths per unit of depth: large, so that a grazing ray crosses the tile several times.
constexpr double kDepthScale = 0.5;

Image literalMap() {
    Image image(8, 8, 1);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) image.at(x, y) = kMap[y][x];
    return image;
}

// A ray of the shaders (entry dp at depth 0, (u, v) travel ds from depth 0 to 1).
struct Ray {
    shared::vec2 dp;
    shared::vec2 ds;
    float cosTheta;  // from the normal, for the relief search's step count

    // The same ray in double, for the exact side.
    glm::dvec2 entry() const { return {static_cast<double>(dp.x), static_cast<double>(dp.y)}; }
    glm::dvec2 travel() const { return {static_cast<double>(ds.x), static_cast<double>(ds.y)}; }
};

// Entries on a 7 x 7 grid (off the texel centres and cell borders), 8 azimuths, 4 angles from the normal up
// to 85 degrees: 1568 rays.
std::vector<Ray> rays() {
    std::vector<Ray> result;
    for (const double angle : {10.0, 45.0, 70.0, 85.0}) {
        const double theta = angle * std::numbers::pi / 180.0;
        for (int a = 0; a < 8; ++a) {
            const double azimuth = (a + 0.3) * std::numbers::pi / 4.0;
            const double travel = std::tan(theta) * kDepthScale;
            for (int i = 0; i < 7; ++i) {
                for (int j = 0; j < 7; ++j) {
                    Ray ray;
                    ray.dp = {static_cast<float>((i + 0.37) / 7.0), static_cast<float>((j + 0.71) / 7.0)};
                    ray.ds = {static_cast<float>(travel * std::cos(azimuth)),
                              static_cast<float>(travel * std::sin(azimuth))};
                    ray.cosTheta = static_cast<float>(std::cos(theta));
                    result.push_back(ray);
                }
            }
        }
    }
    return result;
}

// The exact first hit's depth along the ray, the tracer's t for the direction (ds, -S).
double exactDepth(const HeightFieldTracer& tracer, const Ray& ray) {
    const glm::dvec3 origin(ray.entry(), 0.0);
    const glm::dvec3 direction(ray.travel(), -kDepthScale);
    const std::optional<HeightFieldTracer::Hit> hit = tracer.firstHit(origin, direction);
    EXPECT_TRUE(hit.has_value());  // d <= 1 everywhere: every ray entering the top face hits by depth 1
    return hit ? hit->t : 1.0;
}

// The exact techniques: |t - t_exact| in units of depth, and that times the ray's travel in texels per unit
// of depth (the uv error in texels, what the renderer's tests bound).
struct Agreement {
    double depth = 0.0;
    double texels = 0.0;
};

template <class Intersect>
Agreement agreement(const HeightFieldTracer& tracer, const Intersect& intersect) {
    Agreement worst;
    for (const Ray& ray : rays()) {
        const double t = static_cast<double>(intersect(ray));
        const double error = std::abs(t - exactDepth(tracer, ray));
        const double texelsPerDepth = glm::length(ray.travel()) * 8.0;
        worst.depth = std::max(worst.depth, error);
        worst.texels = std::max(worst.texels, error * texelsPerDepth);
    }
    return worst;
}

TEST(ShaderLoops, MaxMipFindsTheExactFirstHit) {
    const Image depth = literalMap();
    const HeightFieldTracer tracer(depth, kDepthScale);
    const std::vector<Image> levels = maxMipPyramid(depth);
    CpuMaxMipTraversal maxMip(levels, depth);
    const Agreement worst =
        agreement(tracer, [&](const Ray& ray) { return maxMip.maxMipIntersect(ray.dp, ray.ds); });
    std::printf("maxmip: max |t - t_exact| %.3g, in texels %.3g\n", worst.depth, worst.texels);
    // The shader's loop runs in float: positions carry a relative error of a few 1e-7 of coordinates up to
    // ~50 cells, and the closed-form root of a cell about as much (here at most 3e-7 of the depth range and
    // 3e-6 texel). 1e-5 and 1e-4 texel leave room for that on other compilers, and none for a skipped
    // feature, which costs at least a good part of a cell (the renderer's tests allow 0.25 texel at the 99th
    // percentile, for the GPU's 8-bit filtering weights and texture coordinates).
    EXPECT_LE(worst.depth, 1e-5);
    EXPECT_LE(worst.texels, 1e-4);
}

TEST(ShaderLoops, ConeFindsTheExactFirstHit) {
    const Image depth = literalMap();
    const HeightFieldTracer tracer(depth, kDepthScale);
    const PackedConeMap packed = packConeMap(depth);
    CpuConeStepping cone(packed.texels, packed.maxRatio, depth);
    const Agreement worst =
        agreement(tracer, [&](const Ray& ray) { return cone.coneIntersect(ray.dp, ray.ds); });
    std::printf("cone: max |t - t_exact| %.3g, in texels %.3g\n", worst.depth, worst.texels);
    // As maxmip (the same leaf in float); the cones only ever skip relief-free space.
    EXPECT_LE(worst.depth, 1e-5);
    EXPECT_LE(worst.texels, 1e-4);
}

// reliefIntersect's result t is a point inside the relief (t >= d), and the point a final window above it
// is outside (or above depth 0): the surface is crossed within [t - bracket, t]. It need not be the first
// crossing: a feature thinner than a linear step can be stepped over (the paper's Sec. 5).
TEST(ShaderLoops, ReliefSearchBracketsACrossing) {
    const Image depth = literalMap();
    const HeightFieldTracer tracer(depth, kDepthScale);
    CpuReliefSearch search(tracer);
    // The float positions of the loop differ from the double ones here by a few 1e-7 of uv; times the
    // steepest slope of the map (1 in depth per texel, 8 per unit of uv) that is ~1e-5 in depth: 1e-4 is
    // that with margin, and far below the window (1/512 at the most steps used here).
    const double tolerance = 1e-4;
    int rayCount = 0, firstHits = 0;
    for (const Ray& ray : rays()) {
        for (const int binary : {0, 1, 5}) {
            const int n = std::clamp(shared::reliefLinearSteps(16, ray.cosTheta), 1, 64);
            const double t = static_cast<double>(search.reliefIntersect(ray.dp, ray.ds, n, binary));
            const double bracket = 1.0 / (n * std::exp2(std::max(binary - 1, 0)));
            const auto depthAt = [&](double depthAlong) {
                const glm::dvec2 uv = ray.entry() + ray.travel() * depthAlong;
                return tracer.depthAt(uv.x, uv.y);
            };
            EXPECT_GE(t, depthAt(t) - tolerance) << "t " << t;
            const double above = t - bracket;
            if (above > tolerance) {
                EXPECT_LT(above, depthAt(above) + tolerance) << "t " << t;
            }
            ++rayCount;
            firstHits += std::abs(t - exactDepth(tracer, ray)) <= bracket + tolerance;
        }
    }
    std::printf("relief: %d of %d searches found the first crossing\n", firstHits, rayCount);
}

// reliefLit only reports a shadow where a point of the light ray lies strictly inside the relief, so a point
// it shadows is occluded for the exact tracer too (it may miss thin occluders: a linear search only).
TEST(ShaderLoops, LightRaySearchNeverShadowsALitPoint) {
    const Image depth = literalMap();
    const HeightFieldTracer tracer(depth, kDepthScale);
    CpuReliefSearch search(tracer);
    int shadowed = 0, lit = 0;
    for (const Ray& ray : rays()) {
        const double t = exactDepth(tracer, ray);
        const glm::dvec2 uv = ray.entry() + ray.travel() * t;
        // Lights in the four diagonal directions, 30 degrees above the plane (tile units, z up).
        for (int a = 0; a < 4; ++a) {
            const double azimuth = (a + 0.5) * std::numbers::pi / 2.0;
            const glm::dvec3 toLight(std::cos(azimuth), std::sin(azimuth), std::tan(std::numbers::pi / 6.0));
            // A bias of 0.01 of the depth range keeps the search off the hit itself, where the float hit
            // lies within rounding of the surface either way.
            const bool searchLit =
                search.reliefLit(shared::vec2(uv), static_cast<float>(t), 0.0f, shared::vec3(toLight),
                                 static_cast<float>(kDepthScale), 32, 0.01f);
            const bool exactLit =
                !tracer.occludedFromSurface(uv.x, uv.y, toLight, HeightFieldTracer::kInfinity);
            if (!searchLit) {
                EXPECT_FALSE(exactLit) << "uv " << uv.x << ", " << uv.y << " light " << a;
            }
            (searchLit ? lit : shadowed) += 1;
        }
    }
    std::printf("light-ray search: %d shadowed, %d lit\n", shadowed, lit);
    EXPECT_GT(shadowed, 0);  // the rays and lights do test occlusion
}

// Fetches, counted: a flat map at d = 1/2 with 8 linear steps finds the surface at the 4th step (1/2 >= 1/2),
// then the binary search reads once per step: 4 + 4.
TEST(ShaderLoops, CountTheirFetches) {
    const Image depth(8, 8, 1, 0.5f);
    const HeightFieldTracer tracer(depth, kDepthScale);
    CpuReliefSearch search(tracer);
    EXPECT_EQ(search.reliefIntersect({0.3f, 0.6f}, {0.2f, 0.1f}, 8, 4), 0.5f);
    EXPECT_EQ(search.fetches(), 8);
    search.resetFetches();
    EXPECT_EQ(search.fetches(), 0);
    // maxmip straight down: it starts at the level whose nodes are as wide as the ray's travel (none: level
    // 0), so one cell solve (one textureGather) finds the hit.
    const std::vector<Image> levels = maxMipPyramid(depth);
    CpuMaxMipTraversal maxMip(levels, depth);
    EXPECT_NEAR(maxMip.maxMipIntersect({0.3f, 0.6f}, {0.0f, 0.0f}), 0.5f, 1e-6f);  // float root of d = 1/2
    EXPECT_EQ(maxMip.fetches(), 1);
}

}  // namespace
}  // namespace strata
