// HeightFieldTracer against analytic intersections (flat, piecewise-linear, bilinear, spike, pit, ridge)
// and against a dense brute-force march on random maps.
#include "strata/core/error.h"
#include "strata/image/image.h"
#include "strata/trace/heightfield_tracer.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <optional>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

Image mapOf(int width, int height, const std::function<double(int, int)>& depthOf) {
    Image image(width, height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) image.at(x, y) = static_cast<float>(depthOf(x, y));
    return image;
}

class Random {
public:
    explicit Random(std::uint64_t seed) : mState(seed * 0x9E3779B97F4A7C15ull + 1) {}
    double uniform() {  // [0, 1)
        mState = mState * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(mState >> 11) * 0x1.0p-53;
    }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

private:
    std::uint64_t mState;
};

Image randomMap(int width, int height, std::uint64_t seed) {
    Random random(seed);
    return mapOf(width, height, [&](int, int) { return random.uniform(); });
}

// A unit direction from azimuth (from +u towards +v) and elevation (above the plane), in radians.
glm::dvec3 directionOf(double azimuth, double elevation) {
    return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
            std::sin(elevation)};
}

// Distance between two values modulo 1 (u = 0.999999 and u = 0 are neighbours).
double wrappedDistance(double a, double b) {
    const double d = std::abs(a - b);
    return std::min(d, 1.0 - d);
}

// The bilinear, wrap-around reconstruction written out independently of the tracer (in double), for the
// brute-force reference.
double referenceDepth(const Image& map, double u, double v) {
    const double x = u * map.width() - 0.5;
    const double y = (1.0 - v) * map.height() - 0.5;
    const double fx = std::floor(x);
    const double fy = std::floor(y);
    const auto i = static_cast<int>(fx);
    const auto j = static_cast<int>(fy);
    const double a = x - fx;
    const double b = y - fy;
    auto at = [&](int xi, int yi) { return static_cast<double>(map.atWrapped(xi, yi)); };
    return (1 - a) * (1 - b) * at(i, j) + a * (1 - b) * at(i + 1, j) + (1 - a) * b * at(i, j + 1) +
           a * b * at(i + 1, j + 1);
}

// First t in [0, tMax] with the ray on or below the surface, by marching at `step` (tile units of travel)
// and bisecting the first bracket to machine precision. nullopt: no sample at or below the surface.
std::optional<double> bruteForceHit(const Image& map, double scale, const glm::dvec3& origin,
                                    const glm::dvec3& direction, double tMax, double step) {
    auto f = [&](double t) {
        const glm::dvec3 p = origin + t * direction;
        return p.z + scale * referenceDepth(map, p.x, p.y);
    };
    if (f(0.0) <= 0.0) return 0.0;
    double previous = 0.0;
    const auto count = static_cast<long>(std::ceil(tMax / step));
    for (long k = 1; k <= count; ++k) {
        const double t = std::min(tMax, static_cast<double>(k) * step);
        if (f(t) <= 0.0) {
            double lo = previous;
            double hi = t;
            for (int iteration = 0; iteration < 200 && hi - lo > 1e-15; ++iteration) {
                const double mid = 0.5 * (lo + hi);
                (f(mid) <= 0.0 ? hi : lo) = mid;
            }
            return hi;
        }
        previous = t;
    }
    return std::nullopt;
}

TEST(HeightFieldTracer, RejectsBadInput) {
    EXPECT_THROW(HeightFieldTracer(Image(), 0.1), Error);
    EXPECT_THROW(HeightFieldTracer(Image(4, 4, 3, 0.5f), 0.1), Error);
    EXPECT_THROW(HeightFieldTracer(Image(4, 4, 1, 0.5f), 0.0), Error);
    EXPECT_THROW(HeightFieldTracer(Image(4, 4, 1, 0.5f), -1.0), Error);
    EXPECT_THROW(HeightFieldTracer(Image(4, 4, 1, 0.5f), std::nan("")), Error);
    Image withNan(4, 4, 1, 0.5f);
    withNan.at(2, 1) = std::nanf("");
    EXPECT_THROW(HeightFieldTracer(withNan, 0.1), Error);
}

TEST(HeightFieldTracer, DepthAtMatchesImageSample) {
    const Image map = randomMap(7, 5, 3);
    const HeightFieldTracer tracer(map, 0.2);
    EXPECT_DOUBLE_EQ(tracer.minDepth(),
                     static_cast<double>(*std::min_element(map.pixels().begin(), map.pixels().end())));
    Random random(11);
    for (int k = 0; k < 1000; ++k) {
        const double u = random.uniform(-3.0, 3.0);
        const double v = random.uniform(-3.0, 3.0);
        // Image::sample weights in float: ~1e-7 relative, so 1e-6 absolute on values in [0, 1].
        EXPECT_NEAR(tracer.depthAt(u, v), static_cast<double>(map.sample(u, v)), 1e-6);
        // The independent double reconstruction: only rounding differs (1e-12).
        EXPECT_NEAR(tracer.depthAt(u, v), referenceDepth(map, u - std::floor(u), v - std::floor(v)), 1e-12);
        EXPECT_DOUBLE_EQ(tracer.surfaceZ(u, v), -0.2 * tracer.depthAt(u, v));
    }
    // At a texel centre: the texel itself.
    EXPECT_EQ(tracer.depthAt(map.texelU(3), map.texelV(2)), static_cast<double>(map.at(3, 2)));
}

TEST(HeightFieldTracer, FlatMapHitsThePlane) {
    for (const double scale : {0.05, 0.1, 0.7}) {
        const HeightFieldTracer tracer(Image(16, 8, 1, 0.5f), scale);
        const glm::dvec3 origin(0.3, 0.4, 1.0);
        for (int a = 0; a < 16; ++a) {
            for (const double elevationDegrees : {-90.0, -60.0, -30.0, -10.0, -2.0, -0.5}) {
                const glm::dvec3 direction =
                    directionOf(2.0 * kPi * a / 16.0, elevationDegrees * kPi / 180.0);
                const auto hit = tracer.firstHit(origin, direction);
                ASSERT_TRUE(hit.has_value()) << a << " " << elevationDegrees;
                const double t = (1.0 + 0.5 * scale) / -direction.z;
                const glm::dvec3 expected = origin + t * direction;
                // Plane at z = -0.5 S: only rounding of t * direction (|t| up to ~120): 1e-12 relative to
                // that.
                EXPECT_NEAR(hit->point.z, -0.5 * scale, 1e-12);
                EXPECT_NEAR(hit->t, t, 1e-12 * t);
                EXPECT_NEAR(wrappedDistance(hit->u, expected.x - std::floor(expected.x)), 0.0, 1e-12 * t);
                EXPECT_NEAR(wrappedDistance(hit->v, expected.y - std::floor(expected.y)), 0.0, 1e-12 * t);
                EXPECT_GE(hit->u, 0.0);
                EXPECT_LT(hit->u, 1.0);
                EXPECT_GE(hit->v, 0.0);
                EXPECT_LT(hit->v, 1.0);
                EXPECT_NEAR(hit->depth, 0.5, 1e-12);
            }
            // Going up, or parallel to the plane above it: never.
            EXPECT_FALSE(tracer.firstHit(origin, directionOf(2.0 * kPi * a / 16.0, 0.3)).has_value());
            EXPECT_FALSE(tracer.firstHit({0.3, 0.4, -0.49 * scale}, directionOf(2.0 * kPi * a / 16.0, 0.0))
                             .has_value());
        }
        // tMax before the plane: no hit; tMin past the origin still finds it.
        EXPECT_FALSE(tracer.firstHit(origin, {0, 0, -1}, 0.0, 1.0).has_value());
        EXPECT_NEAR(tracer.firstHit(origin, {0, 0, -1}, 0.5)->t, 1.0 + 0.5 * scale, 1e-12);
    }
}

// A periodic triangle wave along u, d_i = |(i mod 8) - 4| / 4 at the texel centres: bilinear reconstruction
// is exactly the piecewise-linear d(x) = |(x mod 8) - 4| / 4 in texel units x = 8u - 0.5, constant in v.
TEST(HeightFieldTracer, TriangleWaveHasAnalyticHits) {
    const int width = 8;
    const double scale = 0.3;
    const HeightFieldTracer tracer(mapOf(width, 3, [](int x, int) { return std::abs(x - 4) / 4.0; }), scale);
    auto depthOfX = [](double x) {
        const double m = x - 8.0 * std::floor(x / 8.0);
        return std::abs(m - 4.0) / 4.0;
    };
    // The analytic first hit: d is linear on each [k, k + 1] in x, so each piece is one linear equation.
    auto analytic = [&](const glm::dvec3& origin, const glm::dvec3& direction) {
        const double x0 = origin.x * width - 0.5;
        const double qx = direction.x * width;
        for (int step = 0; step < 4000; ++step) {
            const double k = std::floor(x0) + (qx >= 0 ? step : -step);
            const double ta = qx != 0 ? std::max(0.0, std::min((k - x0) / qx, (k + 1 - x0) / qx)) : 0.0;
            const double tb = qx != 0 ? std::max((k - x0) / qx, (k + 1 - x0) / qx) : 1e9;
            const double slope = depthOfX(k + 1) - depthOfX(k);  // d = depthOfX(k) + slope (x - k)
            // origin.z + dz t + S (d(k) + slope (x0 + qx t - k)) = 0
            const double a = direction.z + scale * slope * qx;
            const double b = origin.z + scale * (depthOfX(k) + slope * (x0 - k));
            if (a < 0) {
                const double t = -b / a;
                if (t >= ta - 1e-15 && t <= tb) return t;
            }
        }
        return -1.0;
    };
    Random random(5);
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 origin(random.uniform(-2.0, 2.0), random.uniform(-2.0, 2.0),
                                random.uniform(0.0, 0.5));
        const glm::dvec3 direction =
            directionOf(random.uniform(0.0, 2.0 * kPi), -random.uniform(0.01, 0.5 * kPi));
        const auto hit = tracer.firstHit(origin, direction);
        const double expected = analytic(origin, direction);
        ASSERT_TRUE(hit.has_value());
        // Closed forms on both sides; t up to ~30 at the lowest elevations: 1e-9.
        EXPECT_NEAR(hit->t, expected, 1e-9) << k;
        EXPECT_NEAR(hit->depth, depthOfX(hit->u * width - 0.5), 1e-9);
    }
}

// One bilinear cell with a twist (e3 != 0): pick the hit point on the surface, shoot at it steeply from
// above (the surface's slope is below the ray's, so nothing earlier is hit), expect that exact point.
TEST(HeightFieldTracer, BilinearCellHitsTheChosenPoint) {
    // 2 x 2 map: cell [0, 1]^2 in texel units has corners d00 = 0.125, d10 = 0.5, d01 = 0.3125, d11 = 0.875
    // (exact in float), so d = 0.125 + 0.375 fx + 0.1875 fy + 0.1875 fx fy.
    const Image map = mapOf(2, 2, [](int x, int y) {
        return (x == 0 ? 0.125 : 0.5) + (y == 0 ? 0.0 : 0.1875) + (x == 1 && y == 1 ? 0.1875 : 0.0);
    });
    const double scale = 0.05;
    const HeightFieldTracer tracer(map, scale);
    Random random(9);
    for (int k = 0; k < 1000; ++k) {
        const double fx = random.uniform(0.01, 0.99);
        const double fy = random.uniform(0.01, 0.99);
        const double d = 0.125 + 0.375 * fx + 0.1875 * fy + 0.1875 * fx * fy;
        const glm::dvec3 target((fx + 0.5) / 2.0, 1.0 - (fy + 0.5) / 2.0, -scale * d);
        // The surface's slope is at most S * 0.75 per texel = 0.075 in z per tile (2 texels a tile): rays
        // steeper than 20 degrees descend far faster, so the ray is above the surface before the target.
        const glm::dvec3 direction =
            directionOf(random.uniform(0.0, 2.0 * kPi), -random.uniform(20.0, 90.0) * kPi / 180.0);
        const double tau = random.uniform(0.1, 3.0);
        const auto hit = tracer.firstHit(target - tau * direction, direction);
        ASSERT_TRUE(hit.has_value());
        // The quadratic root is exact up to rounding of the coefficients (~1e-16 S): 1e-9.
        EXPECT_NEAR(hit->t, tau, 1e-9);
        EXPECT_NEAR(hit->u, target.x, 1e-9);
        EXPECT_NEAR(hit->v, target.y, 1e-9);
        EXPECT_NEAR(hit->depth, d, 1e-9);
    }
}

// One spike: texel (3, 4) of an 8 x 8 map at d = 0, every other texel at d = 1. Around its centre each cell
// is d = 1 - (1 - |fx|)(1 - |fy|), a bilinear "pyramid".
TEST(HeightFieldTracer, SpikeIsHitAtTheApexAndMissedBeside) {
    const double scale = 0.25;
    const Image map = mapOf(8, 8, [](int x, int y) { return x == 3 && y == 4 ? 0.0 : 1.0; });
    const HeightFieldTracer tracer(map, scale);
    const glm::dvec3 apex(map.texelU(3), map.texelV(4), 0.0);
    Random random(2);
    for (int k = 0; k < 500; ++k) {
        // Before the apex the ray is above z = 0, the top of the relief. Near the apex the flanks fall at
        // S W (|cos a| + |sin a|) <= 2 sqrt(2) = tan(70.5 deg) per tile: a ray steeper than 75 degrees goes
        // into the solid at the apex (a shallower one only touches it at one point, a rounding-decided
        // contact).
        const double azimuth = random.uniform(0.0, 2.0 * kPi);
        const glm::dvec3 steep = directionOf(azimuth, -random.uniform(75.0, 90.0) * kPi / 180.0);
        const double tau = random.uniform(0.01, 2.0);
        const auto hit = tracer.firstHit(apex - tau * steep, steep);
        ASSERT_TRUE(hit.has_value());
        // Exact apex up to rounding of the origin (|origin| ~ 2): 1e-12.
        EXPECT_NEAR(hit->t, tau, 1e-12);
        EXPECT_NEAR(hit->point.z, 0.0, 1e-12);
        // A shallow ray aimed 1e-9 above the apex passes over it (and lands beyond it, or never).
        const glm::dvec3 shallow = directionOf(azimuth, -random.uniform(1.0, 60.0) * kPi / 180.0);
        const auto over = tracer.firstHit(apex + glm::dvec3(0, 0, 1e-9) - tau * shallow, shallow);
        if (over) {
            EXPECT_GT(over->t, tau + 1e-3);
        }
    }
    // Horizontal rays along +u at texel row 4 + delta and depth h: the line's shallowest point is d = delta
    // (at fx = 0), so it hits iff h >= delta, at x = 3 - a with 1 - (1 - a)(1 - delta) = h on the near side.
    for (const double delta : {0.0, 0.1, 0.37, 0.8}) {
        const double v = 1.0 - (4.0 + delta + 0.5) / 8.0;
        const double x0 = 0.25;  // texel x = 0.25 * 8 - 0.5 = 1.5, left of the spike
        for (const double offset : {1e-9, 1e-6, 0.05}) {
            // Beside: h = delta - offset misses, for every tile along the 64-tile walk.
            if (delta - offset > 0) {
                EXPECT_FALSE(tracer.firstHit({x0, v, -scale * (delta - offset)}, {1, 0, 0}).has_value());
                EXPECT_FALSE(tracer.firstHit({x0, v, -scale * (delta - offset)}, {-1, 0, 0}).has_value());
            }
            const double h = delta + offset;
            const auto hit = tracer.firstHit({x0, v, -scale * h}, {1, 0, 0});
            ASSERT_TRUE(hit.has_value()) << delta << " " << offset;
            const double a = 1.0 - (1.0 - h) / (1.0 - delta);
            // Linear root on a face whose slope along the ray is (1 - delta) / texel: 1e-12.
            EXPECT_NEAR(hit->u * 8.0 - 0.5, 3.0 - a, 1e-12) << delta << " " << offset;
        }
    }
}

// Brute force (march in 1e-4 texel steps, then bisect) on random maps, including non-square maps,
// grazing rays that start inside the slab and rays that cross many tile borders.
TEST(HeightFieldTracer, AgreesWithBruteForceOnRandomMaps) {
    struct Case {
        int width, height;
        double scale;
        std::uint64_t seed;
    };
    int hits = 0;
    int misses = 0;
    for (const Case& c : {Case{4, 4, 0.2, 1}, Case{5, 3, 0.5, 2}, Case{3, 7, 0.05, 3}}) {
        const Image map = randomMap(c.width, c.height, c.seed);
        const HeightFieldTracer tracer(map, c.scale);
        const int texels = std::max(c.width, c.height);
        Random random(c.seed + 100);
        for (int k = 0; k < 1000; ++k) {
            glm::dvec3 origin;
            glm::dvec3 direction;
            const double u = random.uniform(-3.0, 3.0);
            const double v = random.uniform(-3.0, 3.0);
            if (k % 2 == 0) {  // from above the relief
                origin = {u, v, random.uniform(0.0, 0.3)};
                direction =
                    directionOf(random.uniform(0.0, 2.0 * kPi), -random.uniform(1.0, 90.0) * kPi / 180.0);
            } else {  // grazing, from just above the surface, slightly up or down
                origin = {u, v,
                          -c.scale * referenceDepth(map, u - std::floor(u), v - std::floor(v)) +
                              random.uniform(1e-4, 0.02) * c.scale};
                direction =
                    directionOf(random.uniform(0.0, 2.0 * kPi), random.uniform(-2.0, 2.0) * kPi / 180.0);
            }
            const double tMax = 2.0;  // up to 2 tiles: crosses tile borders
            const auto hit = tracer.firstHit(origin, direction, 0.0, tMax);
            const auto expected = bruteForceHit(map, c.scale, origin, direction, tMax, 1e-4 / texels);
            ASSERT_EQ(hit.has_value(), expected.has_value()) << k;
            if (!hit) {
                ++misses;
                continue;
            }
            ++hits;
            // Bisection to 1e-15 on the exact (independently written) surface; the only other error is the
            // march missing a dip shorter than its step, which would fail has_value above: 1e-6.
            EXPECT_NEAR(hit->t, *expected, 1e-6) << k;
            EXPECT_NEAR(hit->point.z, -c.scale * hit->depth, 1e-9);
        }
    }
    // Both kinds occur in numbers (not a vacuous comparison).
    EXPECT_GT(hits, 1500);
    EXPECT_GT(misses, 100);
}

// The block acceleration (8 x 8 cells) on a 20 x 12 map (partial blocks at the tile border): mostly deep,
// with a few tall random bumps, so that most blocks are skipped; firstHit and occludedFromSurface against
// the brute-force march.
TEST(HeightFieldTracer, BlockSkippingAgreesWithBruteForce) {
    Random bumps(40);
    const Image map = mapOf(20, 12, [&](int, int) {
        const double r = bumps.uniform();
        return r < 0.1 ? bumps.uniform(0.0, 0.5) : bumps.uniform(0.8, 1.0);
    });
    const double scale = 0.08;
    const HeightFieldTracer tracer(map, scale);
    Random random(41);
    int hits = 0;
    for (int k = 0; k < 300; ++k) {
        const glm::dvec3 origin(random.uniform(-1.0, 2.0), random.uniform(-1.0, 2.0),
                                random.uniform(0.0, 0.1));
        const glm::dvec3 direction =
            directionOf(random.uniform(0.0, 2.0 * kPi), -random.uniform(1.0, 30.0) * kPi / 180.0);
        const auto hit = tracer.firstHit(origin, direction, 0.0, 1.5);
        const auto expected = bruteForceHit(map, scale, origin, direction, 1.5, 1e-4 / 20.0);
        ASSERT_EQ(hit.has_value(), expected.has_value()) << k;
        if (hit) {
            ++hits;
            EXPECT_NEAR(hit->t, *expected, 1e-6) << k;  // as in AgreesWithBruteForceOnRandomMaps
        }
        // From the surface at a texel centre, low elevations (long walks over skipped blocks).
        const int x = k % 20;
        const int y = (k / 20) % 12;
        const glm::dvec3 up =
            directionOf(random.uniform(0.0, 2.0 * kPi), random.uniform(0.5, 20.0) * kPi / 180.0);
        const glm::dvec3 start(map.texelU(x), map.texelV(y), -scale * static_cast<double>(map.at(x, y)));
        double minClearance = HeightFieldTracer::kInfinity;
        const double step = 1e-4 / 20.0;
        for (double t = step; t <= 1.0; t += step) {
            const glm::dvec3 p = start + t * up;
            minClearance = std::min(minClearance, p.z + scale * referenceDepth(map, p.x - std::floor(p.x),
                                                                               p.y - std::floor(p.y)));
        }
        // Skip rounding-decided grazing contacts, as in OcclusionAgreesWithBruteForce.
        if (std::abs(minClearance) > 1e-9) {
            EXPECT_EQ(tracer.occludedFromSurface(start.x, start.y, up, 1.0), minClearance < 0.0) << k;
        }
    }
    EXPECT_GT(hits, 100);
}

TEST(HeightFieldTracer, RaysThroughTexelCentresAndAlongAxes) {
    const Image map = randomMap(6, 6, 21);
    const double scale = 0.3;
    const HeightFieldTracer tracer(map, scale);
    // Every texel centre, straight down: the texel's own depth.
    for (int y = 0; y < 6; ++y) {
        for (int x = 0; x < 6; ++x) {
            const auto hit = tracer.firstHit({map.texelU(x), map.texelV(y), 0.5}, {0, 0, -1});
            ASSERT_TRUE(hit.has_value());
            EXPECT_NEAR(hit->depth, static_cast<double>(map.at(x, y)), 1e-12);
            EXPECT_NEAR(hit->point.z, -scale * static_cast<double>(map.at(x, y)), 1e-12);
        }
    }
    // Axis-aligned and diagonal directions through texel centres and cell corners, against brute force.
    for (const glm::dvec3& flat : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0),
                                   glm::dvec3(0, -1, 0), glm::dvec3(1, 1, 0), glm::dvec3(-1, 1, 0)}) {
        for (int x = 0; x < 6; ++x) {
            const glm::dvec3 direction = glm::normalize(flat + glm::dvec3(0, 0, -0.2));
            const glm::dvec3 origin(map.texelU(x), map.texelV(x), 0.05);
            const auto hit = tracer.firstHit(origin, direction);
            const auto expected = bruteForceHit(map, scale, origin, direction, 3.0, 1e-5);
            ASSERT_TRUE(hit.has_value());
            ASSERT_TRUE(expected.has_value());
            EXPECT_NEAR(hit->t, *expected, 1e-6);  // as in AgreesWithBruteForceOnRandomMaps
        }
    }
}

TEST(HeightFieldTracer, ShiftByWholeTilesGivesTheSameHit) {
    const Image map = randomMap(9, 7, 4);
    const HeightFieldTracer tracer(map, 0.15);
    Random random(77);
    for (int k = 0; k < 500; ++k) {
        const glm::dvec3 origin(random.uniform(0.0, 1.0), random.uniform(0.0, 1.0), 0.1);
        const glm::dvec3 direction =
            directionOf(random.uniform(0.0, 2.0 * kPi), -random.uniform(2.0, 80.0) * kPi / 180.0);
        const auto hit = tracer.firstHit(origin, direction);
        ASSERT_TRUE(hit.has_value());
        for (const glm::dvec3& shift : {glm::dvec3(3, 0, 0), glm::dvec3(-5, 2, 0), glm::dvec3(0, -1000, 0)}) {
            const auto shifted = tracer.firstHit(origin + shift, direction);
            ASSERT_TRUE(shifted.has_value());
            // The shift itself is rounded (|origin| up to 1000: 1e-13 absolute), nothing else changes: 1e-11.
            EXPECT_NEAR(shifted->t, hit->t, 1e-11);
            EXPECT_NEAR(wrappedDistance(shifted->u, hit->u), 0.0, 1e-11);
            EXPECT_NEAR(wrappedDistance(shifted->v, hit->v), 0.0, 1e-11);
        }
    }
}

TEST(HeightFieldTracer, FlatMapNeverOccludesUpwardRays) {
    const Image map(16, 16, 1, 0.5f);
    const HeightFieldTracer tracer(map, 0.2);
    Random random(8);
    for (int k = 0; k < 2000; ++k) {
        // Half of the starts on texel centres (cell corners), half anywhere.
        const double u = k % 2 == 0 ? map.texelU(k % 16) : random.uniform(-1.0, 2.0);
        const double v = k % 2 == 0 ? map.texelV((k / 16) % 16) : random.uniform(-1.0, 2.0);
        const double azimuth = k % 4 < 2 ? 0.5 * kPi * (k % 8) / 2.0 : random.uniform(0.0, 2.0 * kPi);
        for (const double elevation : {1e-6, 1e-3, 0.3, 0.5 * kPi}) {
            EXPECT_FALSE(tracer.occludedFromSurface(u, v, directionOf(azimuth, elevation), 1.0));
            EXPECT_FALSE(tracer.occludedFromSurface(u, v, directionOf(azimuth, elevation),
                                                    HeightFieldTracer::kInfinity));
        }
        // Along the tangent plane: touching is not occluding. Into the solid: occluded at once.
        EXPECT_FALSE(tracer.occludedFromSurface(u, v, directionOf(azimuth, 0.0), 1.0));
        EXPECT_TRUE(tracer.occludedFromSurface(u, v, directionOf(azimuth, -1e-6), 1e-9));
        EXPECT_TRUE(tracer.occludedFromSurface(u, v, {0, 0, -1}, 1e-9));
    }
}

// One deep texel (d = 1) in a flat top (d = 0): from the pit's bottom (its texel centre, z = -S) the
// wall along +u is z = -S (1 - fx), slope S W per tile, and along the diagonal the cell is
// d = (1 - a)^2 (a = fx = fy), slope sqrt(2) S W at the start: open iff tan(elevation) >= that slope.
TEST(HeightFieldTracer, PitBottomOpensAtTheWallSlope) {
    const int size = 16;
    const double scale = 0.05;
    const Image map = mapOf(size, size, [](int x, int y) { return x == 5 && y == 9 ? 1.0 : 0.0; });
    const HeightFieldTracer tracer(map, scale);
    const double u = map.texelU(5);
    const double v = map.texelV(9);
    EXPECT_DOUBLE_EQ(tracer.surfaceZ(u, v), -scale);
    struct Direction {
        double azimuth;
        double slope;
    };
    for (const Direction& d :
         {Direction{0.0, scale * size}, Direction{0.5 * kPi, scale * size}, Direction{kPi, scale * size},
          Direction{1.5 * kPi, scale * size}, Direction{0.25 * kPi, std::sqrt(2.0) * scale * size},
          Direction{1.25 * kPi, std::sqrt(2.0) * scale * size}}) {
        const double boundary = std::atan(d.slope);
        // The first-cell test is exact up to rounding of the direction (1e-16): 1e-12 rad either side.
        for (const double below : {1e-12, 1e-6, 0.3}) {
            EXPECT_TRUE(tracer.occludedFromSurface(u, v, directionOf(d.azimuth, boundary - below), 1.0))
                << d.azimuth << " " << below;
        }
        for (const double above : {1e-12, 1e-6, 0.3}) {
            EXPECT_FALSE(tracer.occludedFromSurface(u, v, directionOf(d.azimuth, boundary + above), 1.0))
                << d.azimuth << " " << above;
        }
        EXPECT_TRUE(tracer.occludedFromSurface(u, v, directionOf(d.azimuth, 0.0), 1.0));
        EXPECT_FALSE(tracer.occludedFromSurface(u, v, {0, 0, 1}, 1.0));
    }
}

// A ridge: column 10 of a 32 x 32 map at d = 0, the rest at d = 1. From the floor at column 7, looking
// along +u, the ridge's crest is 3 texels = 3/32 tile away and S above: occluded iff
// tan(elevation) < S / (3/32), and only if maxDistance reaches the crest. This blocker lies cells away
// from the start, so it tests the walk (not the first-cell rule).
TEST(HeightFieldTracer, RidgeOccludesBelowTheCrestAngle) {
    const int size = 32;
    const double scale = 0.1;
    const Image map = mapOf(size, size, [](int x, int) { return x == 10 ? 0.0 : 1.0; });
    const HeightFieldTracer tracer(map, scale);
    const double distance = 3.0 / size;
    const double crest = std::atan(scale / distance);
    for (const int row : {0, 13, 31}) {
        const double u = map.texelU(7);
        const double v = map.texelV(row);
        // kSurfaceTolerance moves the boundary by ~1e-12 S / distance ~ 1e-12 rad: test 1e-10 either side.
        for (const double delta : {1e-10, 1e-5, 0.2}) {
            EXPECT_TRUE(tracer.occludedFromSurface(u, v, directionOf(0.0, crest - delta), 1.0)) << delta;
            EXPECT_FALSE(tracer.occludedFromSurface(u, v, directionOf(0.0, crest + delta), 1.0)) << delta;
        }
        // Not far enough to reach the crest (the wall starts 2 texels away; the ray is above it until the
        // crest at this elevation): open. Far enough: occluded.
        const double reach = distance / std::cos(crest - 1e-5);
        EXPECT_FALSE(tracer.occludedFromSurface(u, v, directionOf(0.0, crest - 1e-5), 0.99 * reach));
        EXPECT_TRUE(tracer.occludedFromSurface(u, v, directionOf(0.0, crest - 1e-5), 1.01 * reach));
        // Looking the other way, the previous tile's ridge is 29 texels away: open at the mirrored angle.
        const double back = std::atan(scale / (29.0 / size));
        EXPECT_FALSE(tracer.occludedFromSurface(u, v, directionOf(kPi, back + 1e-6), 1.0));
        EXPECT_TRUE(tracer.occludedFromSurface(u, v, directionOf(kPi, back - 1e-6), 1.0));
    }
}

// occludedFromSurface against the brute-force march on random maps, from random surface points and from
// texel centres; cases whose brute-force minimum clearance is within 1e-9 of zero (grazing contact,
// decided by rounding) are skipped.
TEST(HeightFieldTracer, OcclusionAgreesWithBruteForce) {
    const Image map = randomMap(6, 5, 31);
    const double scale = 0.1;
    const HeightFieldTracer tracer(map, scale);
    Random random(32);
    int occluded = 0;
    int open = 0;
    for (int k = 0; k < 1500; ++k) {
        const double u = k % 3 == 0 ? map.texelU(k % 6) : random.uniform(0.0, 1.0);
        const double v = k % 3 == 0 ? map.texelV(k % 5) : random.uniform(0.0, 1.0);
        const glm::dvec3 direction =
            directionOf(random.uniform(0.0, 2.0 * kPi), random.uniform(0.5, 60.0) * kPi / 180.0);
        const double maxDistance = random.uniform(0.05, 1.5);
        const glm::dvec3 start(u, v, -scale * referenceDepth(map, u, v));
        double minClearance = HeightFieldTracer::kInfinity;
        const double step = 1e-4 / 6.0;
        for (double t = step; t <= maxDistance; t += step) {
            const glm::dvec3 p = start + t * direction;
            minClearance = std::min(minClearance, p.z + scale * referenceDepth(map, p.x - std::floor(p.x),
                                                                               p.y - std::floor(p.y)));
        }
        if (std::abs(minClearance) < 1e-9) continue;
        const bool expected = minClearance < 0.0;
        EXPECT_EQ(tracer.occludedFromSurface(u, v, direction, maxDistance), expected)
            << k << " " << minClearance;
        (expected ? occluded : open) += 1;
    }
    EXPECT_GT(occluded, 150);
    EXPECT_GT(open, 200);
}

}  // namespace
}  // namespace strata
