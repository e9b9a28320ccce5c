// The exact reference on curved bases (gdm_mesh_reference.h): on the flat quad it is §8's flat reference;
// on a torus, a slab of half the shell is the surface halfway up the shell, in closed form; the silhouette
// measures against closed forms.
#include "strata/core/error.h"
#include "strata/gdm/gdm_mesh_reference.h"
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
#include <limits>

namespace strata {
namespace {

constexpr glm::dvec3 kLight{0.5, -0.6, 1.1};

// Looking at the unit quad's centre from `degrees` off its normal, distance 1.6.
Camera quadCamera(double degrees) {
    return gdmSceneView(degrees);
}

Image disc(int size, double cx, double cy, double radius) {
    Image mask(size, size, 1);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) mask.at(x, y) = std::hypot(x - cx, y - cy) <= radius ? 1.0f : 0.0f;
    return mask;
}

Image rectangle(int size, int x0, int y0, int x1, int y1) {
    Image mask(size, size, 1);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) mask.at(x, y) = 1.0f;
    return mask;
}

TEST(SilhouetteMeasures, SquaresShiftedByFivePixels) {
    // 20 x 20 squares, one 5 pixels right of the other: they share 15 x 20 of 25 x 20 pixels, and the
    // farthest boundary pixel of either (the middle of its outer side) is 5 pixels from the other's.
    const Image a = rectangle(64, 10, 10, 30, 30), b = rectangle(64, 15, 10, 35, 30);
    EXPECT_DOUBLE_EQ(silhouetteIoU(a, b), 300.0 / 500.0);
    EXPECT_DOUBLE_EQ(silhouetteHausdorff(a, b), 5.0);
    EXPECT_DOUBLE_EQ(silhouetteHausdorff(b, a), 5.0);
    EXPECT_DOUBLE_EQ(silhouetteIoU(a, a), 1.0);
    EXPECT_DOUBLE_EQ(silhouetteHausdorff(a, a), 0.0);
}

TEST(SilhouetteMeasures, DiscsOffsetByKPixels) {
    // Digital discs of radius r, centres k pixels apart along x: the boundary of each is the other's moved
    // by k, and the leftmost boundary pixel of the left disc is exactly k from the right one's (every pixel
    // of the right disc lies at least r + k - r from it). IoU: the lens of two circles of radius r at
    // distance k, A = 2 r^2 acos(k / 2r) - (k / 2) sqrt(4 r^2 - k^2), over 2 pi r^2 - A.
    const double r = 40.0;
    for (const int k : {1, 7, 30}) {
        const Image a = disc(128, 44.0, 64.0, r), b = disc(128, 44.0 + k, 64.0, r);
        EXPECT_DOUBLE_EQ(silhouetteHausdorff(a, b), double(k)) << k;
        const double lens = 2.0 * r * r * std::acos(k / (2.0 * r)) - 0.5 * k * std::sqrt(4.0 * r * r - k * k);
        const double iou = lens / (2.0 * 3.14159265358979323846 * r * r - lens);
        // The digital discs differ from the circles by about their perimeter times a pixel: 0.5 % of the
        // union at r = 40 (measured: within 0.14 %).
        EXPECT_NEAR(silhouetteIoU(a, b), iou, 0.005) << k;
    }
}

TEST(SilhouetteMeasures, EmptyMasksAndBadSizes) {
    const Image empty(16, 16, 1), square = rectangle(16, 4, 4, 8, 8);
    EXPECT_DOUBLE_EQ(silhouetteIoU(empty, empty), 1.0);
    EXPECT_DOUBLE_EQ(silhouetteIoU(empty, square), 0.0);
    EXPECT_DOUBLE_EQ(silhouetteHausdorff(empty, empty), 0.0);
    EXPECT_EQ(silhouetteHausdorff(empty, square), std::numeric_limits<double>::infinity());
    // A mask that fills the picture has its boundary at the picture's edge (outside counts as outside).
    const Image full(16, 16, 1, 1.0f);
    EXPECT_DOUBLE_EQ(silhouetteHausdorff(full, rectangle(16, 0, 0, 15, 16)), 1.0);
    EXPECT_THROW(silhouetteIoU(empty, Image(16, 8, 1)), Error);
    EXPECT_THROW(silhouetteHausdorff(empty, Image(16, 16, 3)), Error);
}

// Where the ray leaves the box [0, 1]^2 x [0, H] (or nothing, if it misses it).
bool boxExit(const glm::dvec3& eye, const glm::dvec3& direction, double height, glm::dvec3& exit) {
    double tIn = -1e300, tOut = 1e300;
    const double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {1.0, 1.0, height};
    for (int a = 0; a < 3; ++a) {
        double t0 = (lo[a] - eye[a]) / direction[a], t1 = (hi[a] - eye[a]) / direction[a];
        if (t0 > t1) std::swap(t0, t1);
        tIn = std::max(tIn, t0);
        tOut = std::min(tOut, t1);
    }
    exit = eye + tOut * direction;
    return tIn <= tOut;
}

TEST(GdmMeshReference, OnTheQuadItIsTheFlatReference) {
    // The quad at tiling 1 and T = H is §8's box; the prism maps are the identity. The two references
    // trace different scenes (clipped, per prism, vs the whole periodic solid) and must agree.
    constexpr int kSize = 128;
    const Mesh quad = makeBuiltinMesh("quad");
    for (const char* name : {"weave", "chain", "grid"}) {
        const SolidMesh solid = meshMesostructure(makeMesostructure(name), 32);
        PrismShellOptions options;
        options.thickness = solid.height;
        for (const double degrees : {20.0, 60.0, 80.0}) {
            const Camera camera = quadCamera(degrees);
            const GdmSceneImages flat = renderGdmReference(solid, camera, kLight, kSize, kSize);
            const GdmSceneImages curved =
                renderGdmMeshReference(solid, quad, options, camera, kLight, kSize, kSize);
            int disagree = 0, onSide = 0, shadowCompared = 0, shadowAgree = 0;
            double uvwError = 0.0;
            for (int j = 0; j < kSize; ++j)
                for (int i = 0; i < kSize; ++i) {
                    const bool a = flat.mask.at(i, j) > 0.5f, b = curved.mask.at(i, j) > 0.5f;
                    double error = 0.0;
                    for (int c = 0; c < 3 && a && b; ++c) {
                        double d = double(flat.uvw.at(i, j, c)) - double(curved.uvw.at(i, j, c));
                        if (c < 2) d -= std::round(d);
                        error = std::max(error, std::abs(d));
                    }
                    if (a != b || error > 1e-4) {
                        // The flat reference traces the whole periodic solid from the box's entry to its
                        // exit; where its hit lies on a side of the box, it may be a face of the next
                        // tile's copy lying in that side (meshMesostructure's sections at u = 0 and u = 1
                        // differ a little, docs/gdm.md), met at the segment's very start or end by float
                        // rounding. The mesh reference keeps only faces whose solid is inside the prism.
                        const auto onSidePlane = [](float x) { return std::min(x, 1.0f - x) < 1e-5f; };
                        if (a && (onSidePlane(flat.uvw.at(i, j, 0)) || onSidePlane(flat.uvw.at(i, j, 1)))) {
                            ++onSide;
                            continue;
                        }
                        ++disagree;
                        continue;
                    }
                    uvwError = std::max(uvwError, error);
                    if (!a) continue;
                    // Shadows agree where the segment to the light leaves the box through its top: there the
                    // flat reference's infinite slab and the shell are the same.
                    const glm::dvec3 hit(curved.uvw.at(i, j, 0), curved.uvw.at(i, j, 1),
                                         double(curved.uvw.at(i, j, 2)) * solid.height);
                    glm::dvec3 out;
                    if (boxExit(hit + 1e-9 * (kLight - hit), glm::normalize(kLight - hit), solid.height,
                                out) &&
                        std::abs(out.z - solid.height) < 1e-9) {
                        ++shadowCompared;
                        shadowAgree += (flat.shadow.at(i, j) > 0.5f) == (curved.shadow.at(i, j) > 0.5f);
                    }
                }
            // Measured: no pixel off the sides; on them 0 (grid) to 127 (weave at 80 degrees, 0.78 %).
            EXPECT_LE(disagree, 2) << name << " at " << degrees;
            EXPECT_LE(100.0 * (disagree + onSide) / (kSize * kSize), 1.0) << name << " at " << degrees;
            // The same hit points to the float rounding of Embree's hit (measured <= 7.3e-6).
            EXPECT_LT(uvwError, 1e-4) << name << " at " << degrees;
            // Measured: all agree.
            EXPECT_GE(shadowAgree, shadowCompared - 2) << name << " at " << degrees;
            EXPECT_GT(shadowCompared, kSize * kSize / 20) << name << " at " << degrees;
        }
    }
}

}  // namespace
}  // namespace strata

namespace strata {
namespace {

// Where the ray first meets one of the triangles (a, b, c); the barycentrics of the hit.
struct TriangleHit {
    double t = std::numeric_limits<double>::infinity();
    std::size_t triangle = 0;
    double b1 = 0.0, b2 = 0.0;
};

TEST(GdmMeshReference, HalfSlabOnATorusIsTheShellsMiddleSurface) {
    // The slab 0 <= z <= H / 2 (every tile full up to half the shell) warps into the surface X(u, v, H / 2):
    // in each prism the flat triangle P_i + (T / 2) N_i. Every ray that reaches the solid crosses it first
    // (it encloses the base), so the reference's mask is that surface's and its uvw the texture position
    // sum b_i t_i at w = 1/2; traced here by brute force in double.
    constexpr int kSize = 96;
    constexpr double kHeight = 0.25;
    const SolidMesh slab = boxMesh({-0.25f, -0.25f, 0.0f}, {1.25f, 1.25f, float(kHeight / 2)}, kHeight);
    const Mesh torus = makeBuiltinMesh("torus", {1});
    PrismShellOptions options;
    options.height = kHeight;
    options.tiling = {4.0, 2.0};
    const PrismShell shell = buildPrismShell(torus, options);
    Camera camera;
    camera.eye = {0.3, -1.6, 0.9};
    camera.target = {0.0, 0.0, 0.0};
    camera.fovYDegrees = 40.0;
    GdmMeshReferenceStats stats;
    const GdmSceneImages reference =
        renderGdmMeshReference(slab, torus, options, camera, {1.0, -1.0, 2.0}, kSize, kSize, {}, &stats);
    EXPECT_EQ(stats.prisms, shell.prisms.size());
    EXPECT_EQ(stats.skippedPrisms, 0u);
    EXPECT_EQ(stats.rimFins + stats.seamFins, 0u);  // closed, and the uv seams fall on whole tiles
    EXPECT_EQ(stats.exitFaceCrossings, 0u);
    int hits = 0, maskDisagree = 0;
    double uvError = 0.0, wError = 0.0;
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            const glm::dvec3 direction = pixelRayDirection(camera, kSize, kSize, i + 0.5, j + 0.5);
            TriangleHit best;
            for (std::size_t p = 0; p < shell.prisms.size(); ++p) {
                glm::dvec3 corner[3];
                for (std::size_t k = 0; k < 3; ++k) {
                    const std::uint32_t s = shell.prisms[p][k];
                    corner[k] =
                        glm::dvec3(shell.base[s]) + 0.5 * shell.thickness * glm::dvec3(shell.normal[s]);
                }
                // Moller-Trumbore.
                const glm::dvec3 e1 = corner[1] - corner[0], e2 = corner[2] - corner[0];
                const glm::dvec3 q = glm::cross(direction, e2);
                const double det = glm::dot(e1, q);
                if (std::abs(det) < 1e-14) continue;
                const glm::dvec3 s0 = camera.eye - corner[0];
                const double b1 = glm::dot(s0, q) / det;
                const glm::dvec3 r = glm::cross(s0, e1);
                const double b2 = glm::dot(direction, r) / det;
                const double t = glm::dot(e2, r) / det;
                if (b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0 || t <= 0.0 || t >= best.t) continue;
                best = {t, p, b1, b2};
            }
            const bool expected = std::isfinite(best.t);
            const bool hit = reference.mask.at(i, j) > 0.5f;
            if (expected != hit) {
                ++maskDisagree;
                continue;
            }
            if (!hit) continue;
            ++hits;
            glm::dvec2 uv(0.0);
            const double b[3] = {1.0 - best.b1 - best.b2, best.b1, best.b2};
            for (std::size_t k = 0; k < 3; ++k)
                uv += b[k] * options.tiling * glm::dvec2(torus.vertices[shell.corners[best.triangle][k]].uv);
            for (int c = 0; c < 2; ++c) {
                double d = double(reference.uvw.at(i, j, c)) - (uv[c] - std::floor(uv[c]));
                uvError = std::max(uvError, std::abs(d - std::round(d)));
            }
            wError = std::max(wError, std::abs(double(reference.uvw.at(i, j, 2)) - 0.5));
        }
    EXPECT_GT(hits, kSize * kSize / 8);  // measured 2313 of 9216
    // Only rays within float rounding of the surface's outline could go either way (measured: none).
    EXPECT_LE(maskDisagree, 2);
    // Float Embree against double: 1e-5 tile widths is 1/3000 of a voxel at 32 per tile.
    EXPECT_LT(uvError, 1e-5);
    EXPECT_LT(wError, 1e-5);
}

TEST(GdmMeshReference, RefusesBadInput) {
    const SolidMesh slab = boxMesh({0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.1f}, 0.25);
    const Mesh quad = makeBuiltinMesh("quad");
    const Camera camera = quadCamera(45.0);
    EXPECT_NO_THROW(renderGdmMeshReference(slab, quad, {}, camera, kLight, 4, 4));
    EXPECT_THROW(renderGdmMeshReference(slab, quad, {}, camera, kLight, 0, 4), Error);
    SolidMesh flat = slab;
    flat.height = 0.0;
    EXPECT_THROW(renderGdmMeshReference(flat, quad, {}, camera, kLight, 4, 4), Error);
    SolidMesh broken = slab;
    broken.triangles.push_back({0, 1, 99});
    EXPECT_THROW(renderGdmMeshReference(broken, quad, {}, camera, kLight, 4, 4), Error);
    EXPECT_THROW(renderGdmMeshReference(slab, Mesh{}, {}, camera, kLight, 4, 4), Error);
    GdmMeshReferenceOptions options;
    options.chordTolerance = 0.0;
    EXPECT_THROW(renderGdmMeshReference(slab, quad, {}, camera, kLight, 4, 4, options), Error);
    Camera bad = camera;
    bad.target = bad.eye;
    EXPECT_THROW(renderGdmMeshReference(slab, quad, {}, bad, kLight, 4, 4), Error);
}

}  // namespace
}  // namespace strata
