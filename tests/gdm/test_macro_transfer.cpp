// The macro transfer of bi-scale PRT (strata/gdm/macro_transfer.h): without occlusion it is the SH rotation
// into each vertex's tangent frame (Ivanic & Ruedenberg's, sh_rotation.h, an independent computation); with
// it, a sphere hides the cone of directions it subtends, in closed form.
#include "strata/core/error.h"
#include "strata/environment/sh_rotation.h"
#include "strata/environment/spherical_harmonics.h"
#include "strata/gdm/macro_transfer.h"
#include "strata/mesh/builtin_meshes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace strata {
namespace {

// Rows T, B, N of a vertex (its tangent made orthogonal to N), as macro_transfer.h defines the frame.
glm::dmat3 frameOf(const MeshVertex& vertex) {
    const glm::dvec3 n = glm::normalize(glm::dvec3(vertex.normal));
    const glm::dvec3 t =
        glm::normalize(glm::dvec3(vertex.tangent) - glm::dot(glm::dvec3(vertex.tangent), n) * n);
    return glm::transpose(glm::dmat3(t, glm::cross(n, t), n));
}

TEST(MacroTransfer, WithoutOcclusionItIsTheRotationIntoTheTangentFrame) {
    // Checked against the definition, not the code's route: the world lighting f, seen in a vertex's frame,
    // is g(u) = f(R^T u), and its projection (shProject, exact for a band-3 f) is what M must give.
    ShColor world{};
    for (int k = 0; k < kShCount; ++k)
        world[std::size_t(k)] = glm::dvec3(std::sin(1.0 + k), std::cos(2.0 * k), 0.1 * k - 0.5);
    const Mesh torus = makeBuiltinMesh("torus", {2});
    MacroTransferOptions options;
    options.occlusion = false;
    const MacroTransfer transfer = bakeMacroTransfer(torus, options);
    ASSERT_EQ(transfer.vertexCount(), torus.vertices.size());
    double worst = 0.0;
    for (std::size_t v = 0; v < torus.vertices.size(); v += 7) {
        const glm::dmat3 frame = frameOf(torus.vertices[v]);
        const ShColor expected =
            shProject([&](const glm::dvec3& u) { return shReconstruct(world, glm::transpose(frame) * u); });
        const ShColor got = applyMacroTransfer(transfer.matrix(v), world);
        for (int k = 0; k < kShCount; ++k)
            worst = std::max(worst, glm::length(got[std::size_t(k)] - expected[std::size_t(k)]));
        // And M is the rotation's matrix entry by entry (Ivanic & Ruedenberg's, sh_rotation.h).
        const ShRotation rotation(frame);
        for (int l = 0; l < kShBands; ++l)
            for (int a = -l; a <= l; ++a)
                for (int lb = 0; lb < kShBands; ++lb)
                    for (int b = -lb; b <= lb; ++b)
                        EXPECT_NEAR(double(transfer.matrix(v)[shIndex(l, a) * kShCount + shIndex(lb, b)]),
                                    l == lb ? rotation.entry(l, a, b) : 0.0, 1e-6);
    }
    std::printf("rotation: worst coefficient off by %.3g\n", worst);
    // The matrices are stored as float (half an ulp of an entry <= 1 is 6e-8) and applied to coefficients of
    // magnitude <= 1.5 over 16 terms: measured 6.3e-8.
    EXPECT_LT(worst, 1e-5);
}

TEST(MacroTransfer, ASphereHidesTheConeItSubtends) {
    // From a point at distance d from the centre of a sphere of radius r, the sphere covers a cone of half
    // angle asin(r / d): 2 pi (1 - cos) steradians. M_00 = the visible solid angle / (4 pi) (Y_00 is the
    // constant 1 / sqrt(4 pi)).
    const Mesh sphere = makeBuiltinMesh("sphere", {16});
    MacroTransferOptions options;
    options.shellThickness = 0.05;
    options.lowerHemisphere = true;  // the sphere lies below every vertex's tangent plane
    const MacroTransfer transfer = bakeMacroTransfer(sphere, options);
    const Bounds bounds = meshBounds(sphere);
    const double d =
        0.5 + options.shellThickness + options.offset * glm::length(glm::dvec3(bounds.max - bounds.min));
    const double cosine = std::sqrt(1.0 - (0.5 / d) * (0.5 / d));
    const double expected = 1.0 - 0.5 * (1.0 - cosine);
    double worst = 0.0;
    for (std::size_t v = 0; v < sphere.vertices.size(); v += 11)
        worst = std::max(worst, std::abs(double(transfer.matrix(v)[0]) - expected));
    // V is a step along the cone's rim, which the 2560-node rule resolves to about a node's spacing (5.6
    // degrees in azimuth, finer in polar angle), and the mesh's facets (16 segments per quarter turn) move
    // the rim a little: measured 0.0032 at worst; the bound is about 5 times that.
    std::printf("sphere: M_00 expected %.5f, worst vertex off by %.5f\n", expected, worst);
    EXPECT_LT(worst, 0.015) << "expected " << expected;
    // Light from straight above the vertex (+N, the local +z) reaches it: M carries a world lobe towards
    // the vertex's normal to a local lobe towards +z.
    const std::size_t north = 0;
    ShColor world{};
    const glm::dvec3 n = glm::normalize(glm::dvec3(sphere.vertices[north].normal));
    const ShVector lobe = shEvaluate(n);
    for (int k = 0; k < kShCount; ++k) world[std::size_t(k)] = glm::dvec3(lobe[std::size_t(k)]);
    const ShColor local = applyMacroTransfer(transfer.matrix(north), world);
    ShVector luminance{};
    for (int k = 0; k < kShCount; ++k) luminance[std::size_t(k)] = local[std::size_t(k)].x;
    EXPECT_GT(shDominantDirection(luminance).z, 0.95);
}

TEST(MacroTransfer, ThePlaneBelowIsLeftToTheMesoScale) {
    // The quad hides nothing above its own plane: by default M is the identity (the quad's frame is world).
    // Tested below the plane too, a corner vertex sees the quad fill a quarter of the lower hemisphere, an
    // eighth of the sphere: M_00 = 7/8 (the quadrature resolves the quarter's straight edges through the
    // corner exactly up to its node spacing).
    const Mesh quad = makeBuiltinMesh("quad");
    const MacroTransfer transfer = bakeMacroTransfer(quad);
    double worst = 0.0;
    for (std::size_t v = 0; v < quad.vertices.size(); ++v)
        for (int i = 0; i < kShCount; ++i)
            for (int j = 0; j < kShCount; ++j)
                worst = std::max(
                    worst, std::abs(double(transfer.matrix(v)[i * kShCount + j]) - (i == j ? 1.0 : 0.0)));
    EXPECT_LT(worst, 1e-6);
    MacroTransferOptions options;
    options.lowerHemisphere = true;
    const MacroTransfer below = bakeMacroTransfer(quad, options);
    for (std::size_t v = 0; v < quad.vertices.size(); ++v) EXPECT_NEAR(below.matrix(v)[0], 0.875, 0.01) << v;
}

TEST(MacroTransfer, RefusesBadInput) {
    EXPECT_THROW(bakeMacroTransfer(Mesh{}), Error);
    MacroTransferOptions negative;
    negative.shellThickness = -1.0;
    EXPECT_THROW(bakeMacroTransfer(makeBuiltinMesh("quad"), negative), Error);
    MacroTransferOptions zero;
    zero.offset = 0.0;
    EXPECT_THROW(bakeMacroTransfer(makeBuiltinMesh("quad"), zero), Error);
    Mesh broken = makeBuiltinMesh("quad");
    broken.indices.push_back(99);
    EXPECT_THROW(bakeMacroTransfer(broken), Error);
}

}  // namespace
}  // namespace strata
