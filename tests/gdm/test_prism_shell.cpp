// The prism shell of CONVENTIONS §8 (prism_shell.h): the default thickness, the extrusion, the welding of
// seams and creases, and the shell without cracks: every fin triangle of an interior edge is drawn the same
// way by both of its prisms, on closed and open meshes.
#include "strata/core/error.h"
#include "strata/gdm/prism_shell.h"
#include "strata/mesh/builtin_meshes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace strata {
namespace {

// A triangle as a sorted triple of positions (bit-exact), orientation aside.
using Key = std::array<std::array<float, 3>, 3>;

Key keyOf(const ShellTriangle& triangle) {
    Key key;
    for (int c = 0; c < 3; ++c) key[c] = {triangle[c].x, triangle[c].y, triangle[c].z};
    std::sort(key.begin(), key.end());
    return key;
}

// How many times each fin triangle is drawn, over all prisms.
std::map<Key, int> finUses(const PrismShell& shell) {
    std::map<Key, int> uses;
    for (std::size_t p = 0; p < shell.prisms.size(); ++p) {
        const auto faces = prismTriangles(shell, p);
        for (int f = 2; f < 8; ++f) ++uses[keyOf(faces[f])];
    }
    return uses;
}

// Edges of the welded mesh (shell vertex pairs) used by exactly one prism: the mesh's boundary.
std::size_t boundaryEdges(const PrismShell& shell) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (const auto& prism : shell.prisms)
        for (int e = 0; e < 3; ++e) ++edges[std::minmax(prism[e], prism[(e + 1) % 3])];
    return std::size_t(
        std::count_if(edges.begin(), edges.end(), [](const auto& e) { return e.second == 1; }));
}

PrismShellOptions withHeight(double height) {
    PrismShellOptions options;
    options.height = height;
    return options;
}

std::string errorOf(const Mesh& mesh, const PrismShellOptions& options) {
    try {
        buildPrismShell(mesh, options);
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        return e.what();
    }
    return "";
}

TEST(PrismShell, UnitQuadIsTheVerificationShell) {
    // The §7 quad with tiling 1: a tile is the quad itself, so T = H and the tops lie at z = H (§8).
    const PrismShell shell = buildPrismShell(makeBuiltinMesh("quad"), withHeight(0.25));
    EXPECT_DOUBLE_EQ(shell.tileLength, 1.0);
    EXPECT_DOUBLE_EQ(shell.thickness, 0.25);
    ASSERT_EQ(shell.base.size(), 4u);
    ASSERT_EQ(shell.prisms.size(), 2u);
    for (std::size_t s = 0; s < 4; ++s) {
        EXPECT_EQ(shell.normal[s], glm::vec3(0.0f, 0.0f, 1.0f));
        EXPECT_EQ(shell.top[s], shell.base[s] + glm::vec3(0.0f, 0.0f, 0.25f));
    }
    // The diagonal x = y is the one interior edge: its fin is drawn by both prisms, the 4 sides once.
    const auto uses = finUses(shell);
    EXPECT_EQ(uses.size(), 10u);  // (2 interior + 8 side) fin triangles
    EXPECT_EQ(std::count_if(uses.begin(), uses.end(), [](const auto& u) { return u.second == 2; }), 2);
    EXPECT_EQ(boundaryEdges(shell), 4u);
}

TEST(PrismShell, DefaultThicknessFollowsTheUvScaleAndTiling) {
    // The plane is [-1, 1]^2 with uv in [0, 1]: one uv unit is 2 world units, one tile 2 / tiling.
    const Mesh plane = makeBuiltinMesh("plane", {4});
    PrismShellOptions options;
    options.height = 0.2;
    options.tiling = {4.0, 4.0};
    const PrismShell shell = buildPrismShell(plane, options);
    EXPECT_NEAR(shell.tileLength, 0.5, 1e-12);
    EXPECT_NEAR(shell.thickness, 0.1, 1e-12);
    // Anisotropic tiling: the square root of the tile's world area.
    options.tiling = {2.0, 8.0};
    EXPECT_NEAR(buildPrismShell(plane, options).tileLength, std::sqrt(1.0 * 0.25), 1e-12);
    // A given T wins.
    options.thickness = 0.03;
    const PrismShell given = buildPrismShell(plane, options);
    EXPECT_DOUBLE_EQ(given.thickness, 0.03);
    for (std::size_t s = 0; s < given.base.size(); ++s)
        EXPECT_NEAR(glm::length(given.top[s] - given.base[s]), 0.03, 1e-6);
}

TEST(PrismShell, ClosedMeshesHaveNoCracks) {
    // Every edge of a closed mesh is interior once its seams are welded: each fin triangle is drawn twice,
    // by the two prisms on its edge, as the same three points.
    for (const std::string name : {"sphere", "torus", "cube", "cylinder"}) {
        const Mesh mesh = makeBuiltinMesh(name, {3});
        const PrismShell shell = buildPrismShell(mesh, withHeight(0.25));
        EXPECT_LT(shell.base.size(), mesh.vertices.size()) << name;  // seams and creases welded
        EXPECT_EQ(boundaryEdges(shell), 0u) << name;
        for (const auto& [key, count] : finUses(shell)) EXPECT_EQ(count, 2) << name;
        for (std::size_t s = 0; s < shell.base.size(); ++s)
            EXPECT_NEAR(glm::length(shell.normal[s]), 1.0f, 1e-6f) << name;
    }
}

TEST(PrismShell, CreasesExtrudeAlongTheMeanNormal) {
    // The cube's corners: three faces' normals, welded into one vertex extruded along their mean.
    const PrismShell shell = buildPrismShell(makeBuiltinMesh("cube", {2}), withHeight(0.25));
    int corners = 0;
    for (std::size_t s = 0; s < shell.base.size(); ++s) {
        const glm::vec3 p = shell.base[s];
        if (std::abs(std::abs(p.x) - 0.5f) > 1e-6f || std::abs(std::abs(p.y) - 0.5f) > 1e-6f ||
            std::abs(std::abs(p.z) - 0.5f) > 1e-6f)
            continue;
        ++corners;
        const glm::vec3 expected = glm::normalize(glm::sign(p));
        EXPECT_NEAR(glm::length(shell.normal[s] - expected), 0.0f, 1e-6f);
    }
    EXPECT_EQ(corners, 8);
}

TEST(PrismShell, TheTeapotIsCrackFreeWhereItsPatchesMeet) {
    // Newell's patches repeat every position along their shared edges (and evaluate them separately):
    // welded, every fin is drawn twice except over the mesh's own open edges, drawn once.
    const PrismShell shell = buildPrismShell(makeBuiltinMesh("teapot", {4}), withHeight(0.25));
    std::size_t once = 0;
    for (const auto& [key, count] : finUses(shell)) {
        EXPECT_LE(count, 2);
        once += count == 1;
    }
    EXPECT_EQ(once, 2 * boundaryEdges(shell));
    EXPECT_LT(boundaryEdges(shell), shell.prisms.size() / 10);  // the spout's and handle's ends, not seams
}

TEST(PrismShell, FinsFaceOutOfTheirPrism) {
    // Each fin triangle's normal points away from its prism's centre; base and top face along +N.
    const PrismShell shell = buildPrismShell(makeBuiltinMesh("sphere", {2}), withHeight(0.25));
    for (std::size_t p = 0; p < shell.prisms.size(); ++p) {
        const auto faces = prismTriangles(shell, p);
        glm::vec3 centre(0.0f);
        for (const std::uint32_t s : shell.prisms[p]) centre += (shell.base[s] + shell.top[s]) / 6.0f;
        for (int f = 2; f < 8; ++f) {
            const glm::vec3 n = glm::cross(faces[f][1] - faces[f][0], faces[f][2] - faces[f][0]);
            const glm::vec3 mid = (faces[f][0] + faces[f][1] + faces[f][2]) / 3.0f;
            EXPECT_GT(glm::dot(n, mid - centre), 0.0f) << "prism " << p << " face " << f;
        }
        const glm::vec3 up = shell.normal[shell.prisms[p][0]];
        for (int f = 0; f < 2; ++f)
            EXPECT_GT(glm::dot(glm::cross(faces[f][1] - faces[f][0], faces[f][2] - faces[f][0]), up), 0.0f);
    }
}

TEST(PrismShell, RefusesBadInputNamingTheMesh) {
    const Mesh quad = makeBuiltinMesh("quad");
    EXPECT_NE(errorOf(quad, withHeight(0.0)).find("prism shell of quad: the shell thickness H"),
              std::string::npos);
    PrismShellOptions options;
    options.tiling = {0.0, 1.0};
    EXPECT_NE(errorOf(quad, options).find("tiling"), std::string::npos);
    options = {};
    options.thickness = -1.0;
    EXPECT_NE(errorOf(quad, options).find("thickness T"), std::string::npos);
    Mesh broken = quad;
    broken.indices.push_back(0);
    EXPECT_NE(errorOf(broken, {}).find("not a multiple of 3"), std::string::npos);
    broken = quad;
    broken.indices[4] = 9;
    EXPECT_NE(errorOf(broken, {}).find("index 4"), std::string::npos);
    broken = quad;
    broken.vertices[2].position.x = NAN;
    EXPECT_NE(errorOf(broken, {}).find("vertex 2"), std::string::npos);
    EXPECT_NE(errorOf(Mesh{"none", {}, {}}, {}).find("empty"), std::string::npos);
    broken = quad;
    for (MeshVertex& v : broken.vertices) v.uv = glm::vec2(0.5f);  // no uv scale to measure a tile by
    EXPECT_NE(errorOf(broken, {}).find("give T"), std::string::npos);
}

}  // namespace
}  // namespace strata
