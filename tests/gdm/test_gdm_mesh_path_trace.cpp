// The path tracer on curved bases (gdm_mesh_path_trace.h): its mask is the curved reference's; on the quad
// it is the flat path tracer (path for path, where the two scenes are the same); a thin slab under a
// constant sky in closed form; the macro occlusion of a torus; bounces, determinism and bad input.
#include "strata/core/error.h"
#include "strata/gdm/gdm_mesh_path_trace.h"
#include "strata/gdm/gdm_mesh_reference.h"
#include "strata/gdm/gdm_path_trace.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/mesostructure.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gdm/prism_shell.h"
#include "strata/mesh/builtin_meshes.h"

#include "test_solids.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace strata {
namespace {

GdmAlbedo gray(double rho) {
    return [rho](const glm::dvec3&) { return glm::dvec3(rho); };
}

// A coloured sky, brighter towards the zenith, black below the horizon (the flat scene's base blocks every
// ray heading down; the quad's base blocks only those that meet it).
glm::dvec3 sky(const glm::dvec3& d) {
    return d.z > 0.0 ? glm::dvec3(0.4 + 0.8 * d.z, 0.5 + 0.6 * d.z, 0.7 + 0.3 * d.z) : glm::dvec3(0.0);
}

// The torus of the curved reference's tests, seen from above its outer rim: its inner side faces the hole.
Camera torusCamera() {
    Camera camera;
    camera.eye = {0.3, -1.6, 0.9};
    camera.target = {0.0, 0.0, 0.0};
    camera.fovYDegrees = 40.0;
    return camera;
}

GdmMeshPathTraceOptions paths(int samples, int bounces, bool macroOcclusion = true) {
    GdmMeshPathTraceOptions options;
    options.samplesPerPixel = samples;
    options.bounces = bounces;
    options.seed = 11;
    options.macroOcclusion = macroOcclusion;
    return options;
}

TEST(GdmMeshPathTrace, MaskIsTheCurvedReferencesMask) {
    constexpr int kSize = 64;
    const SolidMesh chain = meshMesostructure(makeMesostructure("chain"), 32);
    PrismShellOptions torusShell;
    torusShell.tiling = {4.0, 2.0};
    PrismShellOptions quadShell;
    quadShell.thickness = chain.height;
    struct Case {
        Mesh mesh;
        PrismShellOptions shell;
        Camera camera;
    };
    const Case cases[] = {{makeBuiltinMesh("torus", {1}), torusShell, torusCamera()},
                          {makeBuiltinMesh("quad"), quadShell, gdmSceneView(60.0)}};
    for (const Case& c : cases) {
        const GdmSceneImages reference =
            renderGdmMeshReference(chain, c.mesh, c.shell, c.camera, {1.0, -1.0, 2.0}, kSize, kSize);
        const GdmPathTraceImages traced =
            pathTraceGdmMesh(chain, c.mesh, c.shell, gray(0.5), sky, c.camera, kSize, kSize, paths(1, 0));
        int hits = 0, differ = 0;
        for (int j = 0; j < kSize; ++j)
            for (int i = 0; i < kSize; ++i) {
                hits += reference.mask.at(i, j) > 0.5f;
                differ += reference.mask.at(i, j) != traced.mask.at(i, j);
                // Nothing outside the mask.
                if (traced.mask.at(i, j) == 0.0f) {
                    EXPECT_EQ(traced.radiance.at(i, j, 0), 0.0f);
                }
            }
        EXPECT_EQ(differ, 0) << c.mesh.name;
        EXPECT_GT(hits, kSize * kSize / 10) << c.mesh.name;
    }
}

TEST(GdmMeshPathTrace, ThinSlabOnTheQuadIsAlbedoTimesSky) {
    // The slab 0 <= z <= 0.05 on the quad under a constant sky L: its top and its rim sides see nothing of
    // the solid, and the quad's base lies behind them (the sides' rays that head down pass beside the
    // quad), so every path escapes at once: albedo L exactly, with zero variance, at any bounce count and
    // with or without macro occlusion.
    constexpr int kSize = 48;
    constexpr double kHeight = 0.25, kRho = 0.6, kL = 0.8;
    const SolidMesh slab = boxMesh({-0.25f, -0.25f, 0.0f}, {1.25f, 1.25f, 0.05f}, kHeight);
    PrismShellOptions shell;
    shell.thickness = kHeight;
    const EnvironmentRadiance constant = [](const glm::dvec3&) { return glm::dvec3(kL); };
    for (const bool macro : {true, false})
        for (const int bounces : {0, 2}) {
            const GdmPathTraceImages traced =
                pathTraceGdmMesh(slab, makeBuiltinMesh("quad"), shell, gray(kRho), constant,
                                 gdmSceneView(50.0), kSize, kSize, paths(4, bounces, macro));
            int hits = 0;
            double worst = 0.0;
            for (int j = 0; j < kSize; ++j)
                for (int i = 0; i < kSize; ++i) {
                    if (traced.mask.at(i, j) == 0.0f) continue;
                    ++hits;
                    for (int c = 0; c < 3; ++c)
                        worst = std::max(worst, std::abs(double(traced.radiance.at(i, j, c)) - kRho * kL));
                }
            EXPECT_GT(hits, kSize * kSize / 4);
            // Float rounding of the stored radiance (measured 0).
            EXPECT_LT(worst, 1e-6) << "macro " << macro << ", bounces " << bounces;
        }
}

// The quad's pixels whose flat-scene camera ray runs through the box [0, 1]^2 x [0, H] from its top to its
// bottom inside [lo, 1 - lo]^2: there both scenes' first hits are the same (the flat reference looks only
// inside the box, and the box's sides are cut faces of the flat scene's infinite slab, open rims on the
// quad at tiling 1).
bool crossesBoxInside(const Camera& camera, int size, int i, int j, double height, double lo) {
    const glm::dvec3 d = pixelRayDirection(camera, size, size, i + 0.5, j + 0.5);
    if (d.z >= 0.0) return false;
    const auto inside = [&](double z) {
        const glm::dvec3 p = camera.eye + ((z - camera.eye.z) / d.z) * d;
        return p.x >= lo && p.x <= 1.0 - lo && p.y >= lo && p.y <= 1.0 - lo;
    };
    return inside(height) && inside(0.0);
}

TEST(GdmMeshPathTrace, OnTheQuadItIsTheFlatPathTracer) {
    // Both tracers draw the same random numbers per (seed, pixel, sample), so where the two scenes agree
    // the paths are the same and the pixels agree to the float rounding of Embree's hits, far below the
    // Monte Carlo error. The scenes differ outside the tile: the flat scene repeats the solid in an
    // infinite slab, the quad at tiling 1 has one tile, with open rims.
    constexpr int kSize = 64;
    const Mesostructure weave = makeMesostructure("weave");
    const SolidMesh solid = meshMesostructure(weave, 32);
    const GdmAlbedo albedo = mesostructureLinearAlbedo(weave);
    const double H = solid.height;
    const Mesh quad = makeBuiltinMesh("quad");

    // (a) Tiling 1, T = H, direct light from a sky that is black below 60 degrees of elevation: a ray from
    // a point at least 0.3 tile widths from the sides that leaves the tile through a side, below z = H,
    // rises less than atan(H / 0.3) (< 60 degrees for H <= 0.5); in the flat scene it meets a neighbour or
    // leaves through the top at that elevation, on the quad it escapes at it: black either way.
    ASSERT_LE(H, 0.5);
    const EnvironmentRadiance highSky = [](const glm::dvec3& d) {
        return d.z > std::sin(60.0 * 3.14159265358979 / 180.0) ? sky(d) : glm::dvec3(0.0);
    };
    // (b) Tiling 5 (T = H / 5, the quad's tile length), the camera scaled by 1/5 about the origin and
    // moved to the middle tile, [0.4, 0.6]^2: the same scene, 1/5 the size, with two tiles of the flat
    // scene's slab on every side of the middle one. Two bounces under the whole sky: only paths that run
    // two tiles sideways inside the slab differ.
    PrismShellOptions one;
    one.thickness = H;
    PrismShellOptions five;
    five.tiling = {5.0, 5.0};
    five.thickness = H / 5.0;
    struct Case {
        const char* name;
        const PrismShellOptions& shell;
        const EnvironmentRadiance& environment;
        int bounces;
        double lo;
        double degrees;    // the camera's angle from the normal
        double tolerance;  // of the mean's relative difference
    };
    const EnvironmentRadiance wholeSky = sky;
    const Case cases[] = {{"tiling 1, 0 bounces", one, highSky, 0, 0.3, 15.0, 1e-4},
                          {"tiling 5, 2 bounces", five, wholeSky, 2, 0.0, 35.0, 1e-4}};
    for (const Case& c : cases) {
        const Camera flatCamera = gdmSceneView(c.degrees);
        Camera camera = flatCamera;
        if (c.shell.tiling.x != 1.0) {
            const glm::dvec3 shift(0.4, 0.4, 0.0);
            camera.eye = shift + 0.2 * flatCamera.eye;
            camera.target = shift + 0.2 * flatCamera.target;
        }
        GdmPathTraceOptions flatOptions;
        flatOptions.samplesPerPixel = 16;
        flatOptions.bounces = c.bounces;
        flatOptions.seed = 11;
        const GdmPathTraceImages flat =
            pathTraceGdm(solid, albedo, c.environment, flatCamera, kSize, kSize, flatOptions);
        const GdmPathTraceImages curved = pathTraceGdmMesh(solid, quad, c.shell, albedo, c.environment,
                                                           camera, kSize, kSize, paths(16, c.bounces));
        int compared = 0, differ = 0;
        double flatSum = 0.0, curvedSum = 0.0;
        for (int j = 0; j < kSize; ++j)
            for (int i = 0; i < kSize; ++i) {
                if (!crossesBoxInside(flatCamera, kSize, i, j, H, c.lo)) continue;
                // The same first hit: through the weave's gaps both rays may reach the base and miss.
                ASSERT_EQ(flat.mask.at(i, j), curved.mask.at(i, j)) << c.name << " at " << i << ", " << j;
                if (flat.mask.at(i, j) == 0.0f) continue;
                ++compared;
                double a = 0.0, b = 0.0;
                for (int ch = 0; ch < 3; ++ch) {
                    a += double(flat.radiance.at(i, j, ch));
                    b += double(curved.radiance.at(i, j, ch));
                }
                flatSum += a;
                curvedSum += b;
                differ += std::abs(a - b) > 1e-4 * std::max(a, 1.0);
            }
        EXPECT_GT(compared, kSize * kSize / 16) << c.name;
        EXPECT_GT(flatSum, 0.0) << c.name;
        const double relative = std::abs(curvedSum - flatSum) / flatSum;
        EXPECT_LT(relative, c.tolerance) << c.name;
        // A pixel differs where one of its 16 paths met an edge where float rounding goes the other way,
        // or (b) ran two tiles sideways. Measured: mean relative differences 1.4e-10 (a) and 1.5e-6 (b), far
        // below the 16-path Monte Carlo error (percents); 0 of 294 and 1 of 1715 pixels differ by > 1e-4.
        EXPECT_LE(differ, compared / 50) << c.name;
        std::printf("[ measured ] %s: %d pixels, mean relative difference %.2e, %d pixels differ\n", c.name,
                    compared, relative, differ);
    }
}

TEST(GdmMeshPathTrace, MacroOcclusionDarkensTheTorus) {
    // The torus's own tube hides part of the sky from its inner side, and the base under the chain's gaps
    // hides the lower half of the sky from the links' sides (a slab would hide the base itself: no ray
    // could reach the mesh without meeting the slab first). With the base mesh opaque every path is the
    // one without it or is cut short, so no pixel is brighter, and the picture is darker.
    constexpr int kSize = 48;
    const SolidMesh chain = meshMesostructure(makeMesostructure("chain"), 32);
    PrismShellOptions shell;
    shell.tiling = {4.0, 2.0};
    const Mesh torus = makeBuiltinMesh("torus", {1});
    const EnvironmentRadiance constant = [](const glm::dvec3&) { return glm::dvec3(1.0); };
    const GdmPathTraceImages occluded = pathTraceGdmMesh(chain, torus, shell, gray(0.5), constant,
                                                         torusCamera(), kSize, kSize, paths(8, 1, true));
    const GdmPathTraceImages open = pathTraceGdmMesh(chain, torus, shell, gray(0.5), constant, torusCamera(),
                                                     kSize, kSize, paths(8, 1, false));
    double occludedSum = 0.0, openSum = 0.0;
    int brighter = 0, darker = 0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            ASSERT_EQ(occluded.mask.at(i, j), open.mask.at(i, j));
            const double a = double(occluded.radiance.at(i, j, 0)), b = double(open.radiance.at(i, j, 0));
            occludedSum += a;
            openSum += b;
            brighter += a > b;
            darker += a < b;
        }
    EXPECT_EQ(brighter, 0);
    EXPECT_GT(darker, 100);
    // Without the mesh, a link's side sees the sky below it through the torus. Measured: 262 pixels darker,
    // the picture's radiance 0.800 of the open one's.
    EXPECT_LT(occludedSum, 0.9 * openSum);
    EXPECT_GT(occludedSum, 0.3 * openSum);
    std::printf("[ measured ] torus: %d pixels darker, radiance with / without macro occlusion %.3f\n",
                darker, occludedSum / openSum);
}

TEST(GdmMeshPathTrace, BouncesAddLightAndTheImageIsDeterministic) {
    constexpr int kSize = 32;
    const SolidMesh chain = meshMesostructure(makeMesostructure("chain"), 32);
    PrismShellOptions shell;
    shell.tiling = {4.0, 2.0};
    const Mesh torus = makeBuiltinMesh("torus", {1});
    const GdmPathTraceImages once =
        pathTraceGdmMesh(chain, torus, shell, gray(0.7), sky, torusCamera(), kSize, kSize, paths(4, 0));
    const GdmPathTraceImages again =
        pathTraceGdmMesh(chain, torus, shell, gray(0.7), sky, torusCamera(), kSize, kSize, paths(4, 0));
    const GdmPathTraceImages bounced =
        pathTraceGdmMesh(chain, torus, shell, gray(0.7), sky, torusCamera(), kSize, kSize, paths(4, 1));
    int lower = 0, higher = 0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i)
            for (int c = 0; c < 3; ++c) {
                const float a = once.radiance.at(i, j, c), b = again.radiance.at(i, j, c);
                EXPECT_EQ(std::memcmp(&a, &b, sizeof(float)), 0);
                lower += bounced.radiance.at(i, j, c) < once.radiance.at(i, j, c);
                higher += bounced.radiance.at(i, j, c) > once.radiance.at(i, j, c);
            }
    EXPECT_EQ(lower, 0);
    EXPECT_GT(higher, 0);
}

TEST(GdmMeshPathTrace, RefusesBadInput) {
    const SolidMesh slab = boxMesh({0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.1f}, 0.25);
    const Mesh quad = makeBuiltinMesh("quad");
    const Camera camera = gdmSceneView(45.0);
    const auto trace = [&](const SolidMesh& solid, const Mesh& mesh, const GdmAlbedo& albedo,
                           const EnvironmentRadiance& environment, int width,
                           const GdmMeshPathTraceOptions& options) {
        return pathTraceGdmMesh(solid, mesh, {}, albedo, environment, camera, width, 4, options);
    };
    EXPECT_NO_THROW(trace(slab, quad, gray(0.5), sky, 4, paths(1, 0)));
    EXPECT_THROW(trace(slab, quad, gray(0.5), sky, 0, paths(1, 0)), Error);
    EXPECT_THROW(trace(slab, Mesh{}, gray(0.5), sky, 4, paths(1, 0)), Error);
    EXPECT_THROW(trace(slab, quad, GdmAlbedo{}, sky, 4, paths(1, 0)), Error);
    EXPECT_THROW(trace(slab, quad, gray(0.5), EnvironmentRadiance{}, 4, paths(1, 0)), Error);
    SolidMesh flat = slab;
    flat.height = 0.0;
    EXPECT_THROW(trace(flat, quad, gray(0.5), sky, 4, paths(1, 0)), Error);
    const auto message = [&](const GdmMeshPathTraceOptions& options) {
        try {
            trace(slab, quad, gray(0.5), sky, 4, options);
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message(paths(0, 0)).find("samplesPerPixel 0"), std::string::npos);
    EXPECT_NE(message(paths(1, -1)).find("bounces -1"), std::string::npos);
    GdmMeshPathTraceOptions tolerance = paths(1, 0);
    tolerance.chordTolerance = 0.0;
    EXPECT_NE(message(tolerance).find("chordTolerance"), std::string::npos);
}

}  // namespace
}  // namespace strata
