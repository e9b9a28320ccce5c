// The verification-scene reference renderer against analytic scenes: a flat relief (plane intersection), a
// top-down view (pixel footprint), rays that never see the relief, a ridge with an analytic shadow boundary,
// and a sphere against ray/sphere distances.
#include "strata/core/error.h"
#include "strata/image/image.h"
#include "strata/scene/camera.h"
#include "strata/trace/heightfield_tracer.h"
#include "strata/trace/quad_reference.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace strata {
namespace {

constexpr int kSize = 64;  // pictures are 64 x 64: enough pixels for every case, fast

// Distance between two values modulo 1 (u = 0.999999 and u = 0 are neighbours).
double wrappedDistance(double a, double b) {
    const double d = std::abs(a - b) - std::floor(std::abs(a - b));
    return std::min(d, 1.0 - d);
}

glm::dvec3 rayOf(const Camera& camera, int x, int y) {
    return pixelRayDirection(camera, kSize, kSize, x + 0.5, y + 0.5);
}

// Does the ray enter the quad's top face (cross z = 0 going down inside [0, 1]^2)? A crossing within
// kMargin of the quad's edges is `ambiguous` (the tests skip those pixels: there, whether the ray enters
// depends on the last bit).
struct Entry {
    bool inside = false;
    bool ambiguous = false;
};
Entry quadEntry(const glm::dvec3& eye, const glm::dvec3& direction) {
    constexpr double kMargin = 1e-9;  // 1e6 times the rounding of the crossing point (~1e-15)
    if (!(eye.z > 0.0 && direction.z < 0.0)) return {};
    const double t = -eye.z / direction.z;
    const double x = eye.x + t * direction.x;
    const double y = eye.y + t * direction.y;
    const auto near = [&](double c) { return std::abs(c) < kMargin || std::abs(c - 1.0) < kMargin; };
    if (near(x) || near(y)) return {false, true};
    return {x > 0.0 && x < 1.0 && y > 0.0 && y < 1.0, false};
}

// Every image value of every pixel is the float of the per-ray sample (the images are the samples stored).
void expectImagesAreTheSamples(const QuadReferenceImages& images, const HeightFieldTracer& tracer,
                               const Camera& camera, const QuadReferenceOptions& options) {
    ASSERT_EQ(images.uv.width(), kSize);
    ASSERT_EQ(images.uv.channels(), 3);
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const QuadReferenceSample s =
                traceQuadReference(tracer, camera.eye, rayOf(camera, x, y), options);
            const bool relief = s.object == QuadReferenceObject::Relief;
            // Floats of the same doubles (up to the 1-ulp renormalisation of the direction in
            // traceQuadReference): 4 float ulps (EXPECT_FLOAT_EQ) absorbs that and the clamp below 1.
            EXPECT_FLOAT_EQ(images.object.at(x, y), static_cast<float>(static_cast<int>(s.object)));
            EXPECT_FLOAT_EQ(images.distance.at(x, y), static_cast<float>(s.distance));
            EXPECT_FLOAT_EQ(images.uv.at(x, y, 0), static_cast<float>(relief ? s.u : 0.0));
            EXPECT_FLOAT_EQ(images.uv.at(x, y, 1), static_cast<float>(relief ? s.v : 0.0));
            EXPECT_EQ(images.uv.at(x, y, 2), relief ? 1.0f : 0.0f);
            EXPECT_FLOAT_EQ(images.depth.at(x, y), static_cast<float>(relief ? s.depth : 0.0));
            EXPECT_EQ(images.shadow.at(x, y), relief && s.lit ? 1.0f : 0.0f);
            EXPECT_LT(images.uv.at(x, y, 0), 1.0f);
            EXPECT_LT(images.uv.at(x, y, 1), 1.0f);
        }
    }
}

TEST(QuadReference, FlatMapHitsTheAnalyticPlane) {
    constexpr double kDepth = 0.25;  // exact in float and double
    constexpr double kScale = 0.2;
    const double planeZ = -kScale * kDepth;
    const HeightFieldTracer tracer(Image(4, 4, 1, static_cast<float>(kDepth)), kScale);
    Camera camera;
    camera.eye = {0.3, -0.4, 0.9};
    camera.target = {0.5, 0.5, 0.0};
    camera.fovYDegrees = 60.0;  // wide enough to see past the quad's edges
    QuadReferenceOptions options;
    options.light = glm::dvec3(0.5, 0.5, 0.5);

    const QuadReferenceImages images = renderQuadReference(tracer, camera, kSize, kSize, options);
    expectImagesAreTheSamples(images, tracer, camera, options);

    int hits = 0;
    int misses = 0;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec3 direction = rayOf(camera, x, y);
            const Entry entry = quadEntry(camera.eye, direction);
            if (entry.ambiguous) continue;
            const QuadReferenceSample s = traceQuadReference(tracer, camera.eye, direction, options);
            if (!entry.inside) {
                EXPECT_EQ(s.object, QuadReferenceObject::Nothing) << x << ", " << y;
                ++misses;
                continue;
            }
            ++hits;
            ASSERT_EQ(s.object, QuadReferenceObject::Relief) << x << ", " << y;
            const double t = (planeZ - camera.eye.z) / direction.z;
            const glm::dvec3 p = camera.eye + t * direction;
            // Double-precision plane intersection; the tracer solves the same linear equation: 1e-9 is
            // a million times the rounding of either (~1e-15 at distances ~2).
            EXPECT_NEAR(s.distance, t, 1e-9);
            EXPECT_LT(wrappedDistance(s.u, p.x), 1e-9);
            EXPECT_LT(wrappedDistance(s.v, p.y), 1e-9);
            EXPECT_NEAR(s.point.z, planeZ, 1e-9);
            // Bilinear reconstruction of equal texels is that value up to a rounding (1e-15).
            EXPECT_NEAR(s.depth, kDepth, 1e-12);
            // The light is above the plane: nothing of a flat relief is between a hit and it.
            EXPECT_TRUE(s.lit);
        }
    }
    // The 60-degree view sees both the quad and the plane beyond it.
    EXPECT_GT(hits, 1000) << hits << " " << misses;
    EXPECT_GT(misses, 100);

    // Light below the plane (inside the solid): every hit is shadowed.
    options.light = glm::dvec3(0.5, 0.5, planeZ - 0.05);
    const QuadReferenceImages below = renderQuadReference(tracer, camera, kSize, kSize, options);
    // Light a hair above the (zero-thickness) slab of a flat map: every hit is lit.
    options.light = glm::dvec3(0.5, 0.5, planeZ + 1e-3);
    const QuadReferenceImages justAbove = renderQuadReference(tracer, camera, kSize, kSize, options);
    // No light: shadow is 0 everywhere.
    const QuadReferenceImages unlit = renderQuadReference(tracer, camera, kSize, kSize);
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            EXPECT_EQ(below.shadow.at(x, y), 0.0f);
            EXPECT_EQ(justAbove.shadow.at(x, y), images.uv.at(x, y, 2));
            EXPECT_EQ(unlit.shadow.at(x, y), 0.0f);
            EXPECT_EQ(unlit.uv.at(x, y, 2), images.uv.at(x, y, 2));
        }
    }
}

TEST(QuadReference, TopDownViewSeesThePixelFootprint) {
    constexpr double kScale = 0.2;
    constexpr double kEyeHeight = 2.0;
    for (const double depth : {0.0, 0.5}) {  // 0: the relief touches the quad; 0.5: a plane below it
        const HeightFieldTracer tracer(Image(3, 5, 1, static_cast<float>(depth)), kScale);
        // The field of view that makes the plane z = -S d fill the picture exactly.
        const double distance = kEyeHeight + kScale * depth;
        Camera camera;
        camera.eye = {0.5, 0.5, kEyeHeight};
        camera.target = {0.5, 0.5,
                         -1.0};  // straight down: the camera keeps +x right and +y up in the picture
        camera.fovYDegrees = 2.0 * std::atan(0.5 / distance) * 180.0 / std::numbers::pi;

        const QuadReferenceImages images = renderQuadReference(tracer, camera, kSize, kSize);
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                // Pixel (x, y) sees the centre of texel (x, y) of a 64 x 64 map (CONVENTIONS §1), a dyadic
                // number: the double result is within ~1e-15 of it and rounds onto it as a float, so 1e-9
                // only allows for that.
                EXPECT_NEAR(images.uv.at(x, y, 0), (x + 0.5) / kSize, 1e-9)
                    << depth << ": " << x << ", " << y;
                EXPECT_NEAR(images.uv.at(x, y, 1), 1.0 - (y + 0.5) / kSize, 1e-9) << x << ", " << y;
                EXPECT_EQ(images.uv.at(x, y, 2), 1.0f);
                EXPECT_EQ(images.depth.at(x, y), static_cast<float>(depth));
                EXPECT_EQ(images.object.at(x, y), 1.0f);
            }
        }
    }
}

TEST(QuadReference, RaysThatDoNotEnterTheTopFaceSeeNothing) {
    constexpr double kScale = 0.2;
    const HeightFieldTracer tracer(Image(4, 4, 1, 0.5f), kScale);  // the plane z = -0.1 everywhere
    const auto expectNothing = [&](const Camera& camera, const char* what) {
        const QuadReferenceImages images = renderQuadReference(tracer, camera, kSize, kSize);
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                EXPECT_EQ(images.object.at(x, y), 0.0f) << what << ": " << x << ", " << y;
                EXPECT_EQ(images.uv.at(x, y, 2), 0.0f) << what;
                EXPECT_EQ(images.distance.at(x, y), 0.0f) << what;
            }
        }
    };
    Camera camera;
    // Looking down at z = 0 around (3, 3): the footprint (half-width tan 15 deg ~ 0.27) is outside the
    // quad, though the repeating relief lies under it.
    camera.eye = {3.0, 3.0, 1.0};
    camera.target = {3.0, 3.0, 0.0};
    camera.fovYDegrees = 30.0;
    expectNothing(camera, "outside the quad");
    // From below, looking up at the quad.
    camera.eye = {0.5, 0.5, -0.5};
    camera.target = {0.5, 0.5, 0.0};
    expectNothing(camera, "from below");
    // From inside the slab, above the relief, looking down at it: the ray never crosses the top face.
    camera.eye = {0.5, 0.5, -0.05};
    camera.target = {0.5, 0.5, -1.0};
    expectNothing(camera, "inside the slab");
    // An eye exactly on the quad does not enter it from above.
    EXPECT_EQ(traceQuadReference(tracer, {0.5, 0.5, 0.0}, {0.0, 0.0, -1.0}).object,
              QuadReferenceObject::Nothing);
    // Parallel to the quad, above it: never crosses z = 0.
    EXPECT_EQ(traceQuadReference(tracer, {0.5, -1.0, 0.3}, {0.0, 1.0, 0.0}).object,
              QuadReferenceObject::Nothing);
}

TEST(QuadReference, HorizonRowIsParallelToTheQuad) {
    const HeightFieldTracer tracer(Image(4, 4, 1, 0.5f), 0.2);
    Camera camera;
    camera.eye = {0.5, -1.0, 0.3};
    camera.target = {0.5, 2.0, 0.3};  // level: the middle of an odd-height picture is the horizon
    camera.fovYDegrees = 60.0;
    constexpr int kHeight = 63;
    const QuadReferenceImages images = renderQuadReference(tracer, camera, kSize, kHeight);
    constexpr int kHorizon = kHeight / 2;  // pixel centre 31.5 = H / 2: NDC y is exactly 0
    int below = 0;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec3 direction = pixelRayDirection(camera, kSize, kHeight, x + 0.5, y + 0.5);
            if (y == kHorizon) {
                ASSERT_EQ(direction.z, 0.0);
            }
            const bool hit = images.object.at(x, y) == 1.0f;
            if (y <= kHorizon) {
                EXPECT_FALSE(hit) << x << ", " << y;  // level or going up
            }
            below += hit;
        }
    }
    EXPECT_GT(below, 100);  // the rows below the horizon do see the quad
}

// A ridge along v: the 8 x 2 map is 1 everywhere except column 3 (d = 0). Bilinearly, a tent with its
// peak at u = 3.5 / 8 (z = 0), feet at u = 2.5 / 8 and 4.5 / 8 (z = -S), flanks of slope 8 S = 0.8, and a
// flat floor z = -S elsewhere; it does not depend on v. The light P is at u = 0.5 / 8, above the peaks.
class RidgeShadow : public ::testing::Test {
protected:
    static constexpr double kScale = 0.1;
    static constexpr double kPeak = 3.5 / 8.0;
    static constexpr double kLeftFoot = 2.5 / 8.0;
    static constexpr double kRightFoot = 4.5 / 8.0;
    static inline const glm::dvec3 kLight{0.5 / 8.0, 0.5, 0.075};

    static Image ridgeMap() {
        Image map(8, 2, 1, 1.0f);
        map.at(3, 0) = 0.0f;
        map.at(3, 1) = 0.0f;
        return map;
    }

    // Expected shadow of a relief point q (world, unwrapped) away from the tent's kinks; nullopt within
    // 1e-6 of a kink or of the shadow boundary (not judged there).
    static std::optional<bool> expectedLit(const glm::dvec3& q) {
        constexpr double kMargin = 1e-6;  // far above the hit's rounding (1e-15), far below a pixel (1e-2)
        const double f = q.x - std::floor(q.x);
        for (const double kink : {kLeftFoot, kPeak, kRightFoot})
            if (std::abs(f - kink) < kMargin) return std::nullopt;
        const bool lightOnLeft = kLight.x < q.x;
        if (f > kLeftFoot && f < kPeak) {
            // Left flank: faces -u. P lies above its tangent plane iff P is to the left (the segment to P
            // then climbs at most 0.175 / 0.375 < 0.8 and clears the flank); otherwise the ray to P goes
            // into the solid at once.
            if (!lightOnLeft) return false;
        } else if (f > kPeak && f < kRightFoot) {
            if (lightOnLeft) return false;
        }
        // The segment from q to P is shallower than the flanks (|slope| <= 0.175 / 0.5 < 0.8 whenever a peak
        // lies between them), so it is blocked iff it passes below the nearest peak between q and P.
        const double step = lightOnLeft ? -1.0 : 1.0;
        double peak = std::floor(q.x) + kPeak;
        while ((peak - q.x) * step <= 0.0) peak += step;
        if ((peak - kLight.x) * step >= 0.0) return true;  // no peak strictly between
        const double zAtPeak = q.z + (kLight.z - q.z) * (peak - q.x) / (kLight.x - q.x);
        if (std::abs(zAtPeak) < kMargin) return std::nullopt;
        return zAtPeak > 0.0;
    }
};

TEST_F(RidgeShadow, ShadowMatchesTheAnalyticBoundary) {
    const HeightFieldTracer tracer(ridgeMap(), kScale);
    QuadReferenceOptions options;
    options.light = kLight;
    Camera camera;
    camera.eye = {0.5, -0.3, 0.6};
    camera.target = {0.5, 0.5, -0.05};
    camera.fovYDegrees = 60.0;
    const QuadReferenceImages images = renderQuadReference(tracer, camera, kSize, kSize, options);
    expectImagesAreTheSamples(images, tracer, camera, options);

    int litFloor = 0, shadowedFloor = 0, litFlank = 0, shadowedFlank = 0;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const QuadReferenceSample s =
                traceQuadReference(tracer, camera.eye, rayOf(camera, x, y), options);
            if (s.object != QuadReferenceObject::Relief) continue;
            const std::optional<bool> lit = expectedLit(s.point);
            if (!lit) continue;
            EXPECT_EQ(s.lit, *lit) << x << ", " << y << " hit at u = " << s.point.x;
            const bool onFloor = s.depth > 1.0 - 1e-12;  // the floor is d = 1 up to rounding
            (onFloor ? (*lit ? litFloor : shadowedFloor) : (*lit ? litFlank : shadowedFlank))++;
        }
    }
    // Every kind of point occurs in the picture.
    EXPECT_GT(litFloor, 50);
    EXPECT_GT(shadowedFloor, 50);
    EXPECT_GT(litFlank, 10);
    EXPECT_GT(shadowedFlank, 10);

    // The boundary on the floor: the line from P over the peak (0.4375, 0) meets z = -0.1 at u = 0.9375.
    // Vertical rays 1e-9 either side (the line's height at the peak changes by 0.086 per unit of u: 1e-9
    // moves it 8.6e-11, above the tracer's tolerance of 1e-12 S and the rounding of 1e-16).
    const auto litAt = [&](double u) {
        return traceQuadReference(tracer, {u, 0.5, 1.0}, {0.0, 0.0, -1.0}, options).lit;
    };
    EXPECT_FALSE(litAt(0.9375 - 1e-9));
    EXPECT_TRUE(litAt(0.9375 + 1e-9));
    EXPECT_TRUE(litAt(0.2));    // between P and the left foot: nothing in the way
    EXPECT_FALSE(litAt(0.5));   // right flank, facing away from P
    EXPECT_TRUE(litAt(0.375));  // left flank, facing P
    EXPECT_FALSE(litAt(0.6));   // floor just behind the ridge
}

// Naive ray/sphere distance (unit direction), independent of raySphereDistance's stable form.
std::optional<double> naiveSphereDistance(const glm::dvec3& eye, const glm::dvec3& direction,
                                          const ReferenceSphere& sphere) {
    const glm::dvec3 e = eye - sphere.centre;
    const double b = glm::dot(e, direction);
    const double disc = b * b - (glm::dot(e, e) - sphere.radius * sphere.radius);
    if (disc < 0.0) return std::nullopt;
    const double t = -b - std::sqrt(disc);
    return t > 0.0 ? std::optional<double>(t) : std::nullopt;
}

TEST(QuadReference, SphereIsVisibleWhereNearest) {
    constexpr double kScale = 0.2;
    const double planeZ = -kScale * 0.5;  // flat relief at z = -0.1
    const HeightFieldTracer tracer(Image(4, 4, 1, 0.5f), kScale);
    // Straddles the quad's right edge and reaches below the relief: part of it stands outside the quad
    // (visible on its own), part pokes up through the quad, part is buried under the relief.
    const ReferenceSphere sphere{{1.0, 0.5, -0.05}, 0.25};
    QuadReferenceOptions options;
    options.sphere = sphere;
    options.light = glm::dvec3(0.5, 0.5, 1.0);
    Camera camera;
    camera.eye = {0.5, -0.8, 0.5};
    camera.target = {0.8, 0.5, -0.1};
    camera.fovYDegrees = 60.0;
    const QuadReferenceImages images = renderQuadReference(tracer, camera, kSize, kSize, options);
    expectImagesAreTheSamples(images, tracer, camera, options);

    constexpr double kNone = std::numeric_limits<double>::infinity();
    int sphereAlone = 0, sphereNearer = 0, sphereFarther = 0, reliefAlone = 0, nothing = 0;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec3 direction = rayOf(camera, x, y);
            const Entry entry = quadEntry(camera.eye, direction);
            if (entry.ambiguous) continue;
            // Infinity: not hit.
            const double tSphere = naiveSphereDistance(camera.eye, direction, sphere).value_or(kNone);
            const double tRelief = entry.inside ? (planeZ - camera.eye.z) / direction.z : kNone;
            const bool sphereHit = tSphere < kNone;
            const bool reliefHit = tRelief < kNone;
            // A tie within 1e-9 (1e6 times the rounding) is not judged.
            if (sphereHit && reliefHit && std::abs(tSphere - tRelief) < 1e-9) continue;
            const QuadReferenceSample s = traceQuadReference(tracer, camera.eye, direction, options);
            if (sphereHit && tSphere < tRelief) {
                ASSERT_EQ(s.object, QuadReferenceObject::Sphere) << x << ", " << y;
                // The naive root loses at most ~1e-15 relative at these distances (rays are not grazing
                // enough to cancel more than a few digits): 1e-9.
                EXPECT_NEAR(s.distance, tSphere, 1e-9);
                EXPECT_NEAR(glm::length(s.point - sphere.centre), sphere.radius, 1e-9);
                EXPECT_EQ(images.uv.at(x, y, 2), 0.0f);
                EXPECT_EQ(images.shadow.at(x, y), 0.0f);
                EXPECT_EQ(images.depth.at(x, y), 0.0f);
                (reliefHit ? sphereNearer : sphereAlone)++;
            } else if (reliefHit) {
                ASSERT_EQ(s.object, QuadReferenceObject::Relief) << x << ", " << y;
                EXPECT_NEAR(s.distance, tRelief, 1e-9);  // as in FlatMapHitsTheAnalyticPlane
                EXPECT_TRUE(s.lit);                      // the sphere casts no shadow (documented)
                (sphereHit ? sphereFarther : reliefAlone)++;
            } else {
                EXPECT_EQ(s.object, QuadReferenceObject::Nothing) << x << ", " << y;
                ++nothing;
            }
        }
    }
    // Every case occurs in the picture.
    EXPECT_GT(sphereAlone, 10) << sphereAlone << " " << sphereNearer << " " << sphereFarther << " "
                               << reliefAlone << " " << nothing;
    EXPECT_GT(sphereNearer, 10);
    EXPECT_GT(sphereFarther, 10) << sphereAlone << " " << sphereNearer << " " << sphereFarther << " "
                                 << reliefAlone << " " << nothing;
    EXPECT_GT(reliefAlone, 100);
    EXPECT_GT(nothing, 10);
}

TEST(QuadReference, RaySphereDistance) {
    const ReferenceSphere unit{{0.0, 0.0, 0.0}, 1.0};
    // Small integers: exact.
    EXPECT_EQ(raySphereDistance({0.0, 0.0, 5.0}, {0.0, 0.0, -1.0}, unit), 4.0);
    EXPECT_EQ(raySphereDistance({1.0, 0.0, 5.0}, {0.0, 0.0, -1.0}, unit), 5.0);  // tangent: a hit
    EXPECT_FALSE(raySphereDistance({0.0, 0.0, 5.0}, {0.0, 0.0, 1.0}, unit));     // sphere behind
    EXPECT_FALSE(raySphereDistance({1.5, 0.0, 5.0}, {0.0, 0.0, -1.0}, unit));    // passes beside
    // Grazing from far away, x = 1 - 1e-8: t = 1e6 - sqrt(1 - x^2) = 1e6 - 1.4142135e-4. The textbook
    // discriminant b^2 - c loses it entirely (both ~1e12); the stable form keeps a few ulps of t, and an
    // ulp at 1e6 is 1.2e-10: 1e-9 is 8 ulps.
    const double x = 1.0 - 1e-8;
    const auto t = raySphereDistance({x, 0.0, 1e6}, {0.0, 0.0, -1.0}, unit);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 1e6 - std::sqrt(1.0 - x * x), 1e-9);
}

TEST(QuadReference, RejectsBadInput) {
    const HeightFieldTracer tracer(Image(4, 4, 1, 0.5f), 0.2);
    const Camera camera;
    EXPECT_THROW(renderQuadReference(tracer, camera, 0, 8), Error);
    EXPECT_THROW(renderQuadReference(tracer, camera, 8, Image::kMaxDimension + 1), Error);
    Camera same;
    same.target = same.eye;
    EXPECT_THROW(renderQuadReference(tracer, same, 8, 8), Error);
    QuadReferenceOptions options;
    options.light = glm::dvec3(0.0, std::nan(""), 1.0);
    EXPECT_THROW(renderQuadReference(tracer, camera, 8, 8, options), Error);
    options.light.reset();
    options.sphere = ReferenceSphere{{0.5, 0.5, 0.0}, 0.0};
    EXPECT_THROW(renderQuadReference(tracer, camera, 8, 8, options), Error);
    options.sphere = ReferenceSphere{camera.eye, 0.1};  // eye inside
    EXPECT_THROW(renderQuadReference(tracer, camera, 8, 8, options), Error);
    options.sphere = ReferenceSphere{{0.5, 0.5, 0.0}, 0.1};
    EXPECT_NO_THROW(renderQuadReference(tracer, camera, 8, 8, options));
    EXPECT_THROW(traceQuadReference(tracer, {0.5, 0.5, 1.0}, {0.0, 0.0, 0.0}), Error);
    EXPECT_THROW(
        traceQuadReference(tracer, {0.5, 0.5, std::numeric_limits<double>::infinity()}, {0.0, 0.0, -1.0}),
        Error);
}

}  // namespace
}  // namespace strata
