// Built-in meshes: the unit quad of CONVENTIONS §7 exactly, and the frame, winding and layout of the rest.
#include "strata/core/error.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/mesh/tangent_space.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <utility>

namespace strata {
namespace {

glm::vec3 bitangentOf(const MeshVertex& v) {
    return v.tangent.w * glm::cross(v.normal, glm::vec3(v.tangent));
}

double degrees(double radians) {
    return radians * 180.0 / std::numbers::pi;
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0));
}

// Frame and winding checks every built-in must pass.
void expectWellFormed(const Mesh& mesh) {
    ASSERT_FALSE(mesh.vertices.empty());
    ASSERT_EQ(mesh.indices.size() % 3, 0u);
    for (const MeshVertex& v : mesh.vertices) {
        // Unit vectors built in double and stored as float: a few float ulps.
        EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-6f) << mesh.name;
        EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-6f) << mesh.name;
        EXPECT_NEAR(glm::dot(v.normal, glm::vec3(v.tangent)), 0.0f, 1e-6f) << mesh.name;
        EXPECT_TRUE(v.tangent.w == 1.0f || v.tangent.w == -1.0f) << mesh.name;
    }
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        const MeshVertex& a = mesh.vertices.at(mesh.indices[t]);
        const MeshVertex& b = mesh.vertices.at(mesh.indices[t + 1]);
        const MeshVertex& c = mesh.vertices.at(mesh.indices[t + 2]);
        const glm::vec3 face = glm::cross(b.position - a.position, c.position - a.position);
        ASSERT_GT(glm::length(face), 0.0f) << mesh.name << " triangle " << t / 3;
        // Counter-clockwise seen from outside: the winding normal agrees with all three vertex normals.
        EXPECT_GT(glm::dot(face, a.normal), 0.0f) << mesh.name << " triangle " << t / 3;
        EXPECT_GT(glm::dot(face, b.normal), 0.0f) << mesh.name << " triangle " << t / 3;
        EXPECT_GT(glm::dot(face, c.normal), 0.0f) << mesh.name << " triangle " << t / 3;
    }
}

TEST(BuiltinMeshes, QuadIsExactlyTheVerificationQuad) {
    const Mesh quad = makeBuiltinMesh("quad");
    EXPECT_EQ(quad.name, "quad");
    ASSERT_EQ(quad.vertices.size(), 4u);
    ASSERT_EQ(quad.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
    const glm::vec3 corners[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (std::size_t i = 0; i < 4; ++i) {
        const MeshVertex& v = quad.vertices[i];
        // Exact: CONVENTIONS §7 is a specification, not an approximation.
        EXPECT_EQ(v.position, corners[i]);
        EXPECT_EQ(v.uv, glm::vec2(corners[i]));
        EXPECT_EQ(v.normal, glm::vec3(0, 0, 1));
        EXPECT_EQ(v.tangent, glm::vec4(1, 0, 0, 1));
        EXPECT_EQ(bitangentOf(v), glm::vec3(0, 1, 0));
    }
    expectWellFormed(quad);
    const Bounds bounds = meshBounds(quad);
    EXPECT_EQ(bounds.min, glm::vec3(0, 0, 0));
    EXPECT_EQ(bounds.max, glm::vec3(1, 1, 0));
}

TEST(BuiltinMeshes, AllAreWellFormed) {
    for (const std::string& name : builtinMeshList()) {
        SCOPED_TRACE(name);
        // The default tessellation: at 4 segments per patch edge the teapot's spout lip is too coarse for
        // its winding normals to stay within 90 degrees of its (analytic) vertex normals.
        const Mesh mesh = makeBuiltinMesh(name);
        EXPECT_EQ(mesh.name, name);
        expectWellFormed(mesh);
        // The tangent frame follows the uvs: on every triangle the uv-derived dP/du has a positive
        // component along T, and dP/dv along B (tangents and uvs agree in direction and handedness).
        for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
            const MeshVertex& a = mesh.vertices[mesh.indices[t]];
            const MeshVertex& b = mesh.vertices[mesh.indices[t + 1]];
            const MeshVertex& c = mesh.vertices[mesh.indices[t + 2]];
            const glm::vec3 e1 = b.position - a.position, e2 = c.position - a.position;
            const glm::vec2 d1 = b.uv - a.uv, d2 = c.uv - a.uv;
            const float det = d1.x * d2.y - d2.x * d1.y;
            ASSERT_NE(det, 0.0f);
            // Counter-clockwise in uv as well (the uv map preserves orientation).
            EXPECT_GT(det, 0.0f) << "triangle " << t / 3;
            const glm::vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det;
            const glm::vec3 dpdv = (e2 * d1.x - e1 * d2.x) / det;
            for (const MeshVertex* v : {&a, &b, &c}) {
                EXPECT_GT(glm::dot(dpdu, glm::vec3(v->tangent)), 0.0f) << "triangle " << t / 3;
                EXPECT_GT(glm::dot(dpdv, bitangentOf(*v)), 0.0f) << "triangle " << t / 3;
            }
        }
    }
}

TEST(BuiltinMeshes, CubeFaces) {
    const Mesh cube = makeBuiltinMesh("cube", {1});
    ASSERT_EQ(cube.vertices.size(), 24u);  // 6 faces x 4 corners, not shared (each face has its own uvs)
    ASSERT_EQ(cube.indices.size(), 36u);
    const Bounds bounds = meshBounds(cube);
    EXPECT_EQ(bounds.min, glm::vec3(-0.5f));
    EXPECT_EQ(bounds.max, glm::vec3(0.5f));
    int facesSeen = 0;
    for (std::size_t f = 0; f < 6; ++f) {
        const MeshVertex* v = &cube.vertices[4 * f];
        // The face's corners lie in the plane n . p = 0.5 and its uvs cover [0, 1]^2 with u along T, v along
        // B.
        for (int k = 0; k < 4; ++k) {
            EXPECT_FLOAT_EQ(glm::dot(v[k].normal, v[k].position), 0.5f);
            const glm::vec3 offset = v[k].position - v[0].position;
            EXPECT_FLOAT_EQ(glm::dot(offset, glm::vec3(v[0].tangent)), v[k].uv.x - v[0].uv.x);
            EXPECT_FLOAT_EQ(glm::dot(offset, bitangentOf(v[0])), v[k].uv.y - v[0].uv.y);
        }
        EXPECT_EQ(v[0].uv, glm::vec2(0, 0));
        EXPECT_EQ(v[3].uv, glm::vec2(1, 1));
        facesSeen |= 1 << (static_cast<int>(std::lround(glm::dot(v[0].normal, glm::vec3(1, 2, 3)))) + 3);
        // Side faces read upright: v runs up (+z).
        if (v[0].normal.z == 0.0f) {
            EXPECT_EQ(bitangentOf(v[0]), glm::vec3(0, 0, 1));
        }
    }
    // Normals +-x, +-y, +-z hash to 1 +- ..., 2, 3 (+3): six different bits.
    EXPECT_EQ(facesSeen, (1 << 0) | (1 << 1) | (1 << 2) | (1 << 4) | (1 << 5) | (1 << 6));
}

TEST(BuiltinMeshes, SphereFrameIsAnalytic) {
    const int n = 16;
    const Mesh sphere = makeBuiltinMesh("sphere", {n});
    // 2n - 1 rings of 4n + 1 vertices (the seam is doubled) and 4n vertices at each pole.
    EXPECT_EQ(sphere.vertices.size(), static_cast<std::size_t>((2 * n - 1) * (4 * n + 1) + 2 * 4 * n));
    for (const MeshVertex& v : sphere.vertices) {
        // Radius 0.5 and N = p / |p|, in float.
        EXPECT_NEAR(glm::length(v.position), 0.5f, 1e-6f);
        EXPECT_LT(glm::length(v.normal - v.position / 0.5f), 1e-6f);
        const double phi = 2.0 * std::numbers::pi * static_cast<double>(v.uv.x);
        const double lat = std::numbers::pi * (static_cast<double>(v.uv.y) - 0.5);
        EXPECT_NEAR(v.position.z, 0.5 * std::sin(lat), 1e-6);
        // T = d/du direction (east), B = north, w = +1.
        EXPECT_LT(angleBetween(glm::dvec3(v.tangent), {-std::sin(phi), std::cos(phi), 0.0}), 1e-6);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(BuiltinMeshes, ComputedSphereTangentsMatchAnalytic) {
    // computeTangents on the sphere (analytic frames wiped) against the analytic d/du direction.
    const int n = 16;
    Mesh sphere = makeBuiltinMesh("sphere", {n});
    const Mesh analytic = sphere;
    for (MeshVertex& v : sphere.vertices) v.tangent = glm::vec4(0.0f);
    EXPECT_EQ(computeTangents(sphere), 0u);
    double maxInterior = 0.0, maxSeam = 0.0, maxPole = 0.0;
    for (std::size_t i = 0; i < sphere.vertices.size(); ++i) {
        const MeshVertex& v = sphere.vertices[i];
        EXPECT_EQ(v.tangent.w, 1.0f);
        const double error = angleBetween(glm::dvec3(v.tangent), glm::dvec3(analytic.vertices[i].tangent));
        double& bucket = v.uv.y == 0.0f || v.uv.y == 1.0f   ? maxPole
                         : v.uv.x == 0.0f || v.uv.x == 1.0f ? maxSeam
                                                            : maxInterior;
        bucket = std::max(bucket, error);
    }
    const double halfSegment = 360.0 / (4 * n) / 2;
    std::printf(
        "[ measured ] sphere n=%d: computed vs analytic tangent, max %.4f deg inside, %.4f deg on the "
        "u seam, %.4f deg at the poles (half a segment: %.4f deg)\n",
        n, degrees(maxInterior), degrees(maxSeam), degrees(maxPole), halfSegment);
    // Each triangle's uv-derived tangent is a chord of a latitude ring, half a segment away from the analytic
    // direction at the vertex on either side; inside, the angle-weighted sum balances the two sides up to
    // the unequal corner angles near the poles. 0.5 degree bounds that at n = 16 (measured above).
    EXPECT_LT(degrees(maxInterior), 0.5);
    // On the seam a vertex has triangles on one side only (its twin at u = 1 has the others): up to half a
    // segment.
    EXPECT_LT(degrees(maxSeam), halfSegment);
    // A pole vertex has one triangle, whose chord is exactly east at the vertex's u (float rounding: 1e-4).
    EXPECT_LT(degrees(maxPole), 1e-4);
}

TEST(BuiltinMeshes, SizesAndCounts) {
    struct Expected {
        const char* name;
        glm::vec3 min, max;
    };
    // Documented extents (builtin_meshes.h); float evaluation of cos/sin, hence 1e-6.
    const Expected expected[] = {
        {"cube", glm::vec3(-0.5f), glm::vec3(0.5f)},
        {"sphere", glm::vec3(-0.5f), glm::vec3(0.5f)},
        {"torus", {-0.5f, -0.5f, -0.15f}, {0.5f, 0.5f, 0.15f}},
        {"cylinder", glm::vec3(-0.5f), glm::vec3(0.5f)},
        {"plane", {-1.0f, -1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}},
    };
    for (const Expected& e : expected) {
        SCOPED_TRACE(e.name);
        const Bounds b = meshBounds(makeBuiltinMesh(e.name, {4}));
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(b.min[k], e.min[k], 1e-6f);
            EXPECT_NEAR(b.max[k], e.max[k], 1e-6f);
        }
    }
    EXPECT_EQ(makeBuiltinMesh("plane", {3}).indices.size(), 3u * 2 * 9);
    EXPECT_EQ(makeBuiltinMesh("torus", {2}).vertices.size(), 9u * 9);
    EXPECT_EQ(meshBounds(Mesh{}).min, glm::vec3(0.0f));
    EXPECT_EQ(meshBounds(Mesh{}).max, glm::vec3(0.0f));
}

// Edges used by one triangle only (by position, so uv seams count as shared).
std::size_t openEdges(const Mesh& mesh) {
    std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> uses;
    const auto key = [&](std::uint32_t i) {
        const glm::vec3& p = mesh.vertices[i].position;
        return std::array<float, 3>{p.x, p.y, p.z};
    };
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            auto a = key(mesh.indices[t + std::size_t(e)]),
                 b = key(mesh.indices[t + std::size_t((e + 1) % 3)]);
            if (b < a) std::swap(a, b);
            ++uses[{a, b}];
        }
    return std::size_t(std::count_if(uses.begin(), uses.end(), [](const auto& u) { return u.second == 1; }));
}

TEST(BuiltinMeshes, VaseIsOpenAtBothEndsWithIsotropicUvs) {
    const Mesh vase = makeBuiltinMesh("vase", {8});
    // Two rims of 4n edges each, nothing else open.
    EXPECT_EQ(openEdges(vase), 2u * 32u);
    const Bounds bounds = meshBounds(vase);
    EXPECT_FLOAT_EQ(bounds.min.z, -0.5f);
    EXPECT_FLOAT_EQ(bounds.max.z, 0.5f);
    // The radius at the rims: r(0) = 0.22, r(1) = 0.22 + 0.12.
    for (const MeshVertex& v : vase.vertices) {
        const float r = std::hypot(v.position.x, v.position.y);
        if (v.position.z == -0.5f) {
            EXPECT_NEAR(r, 0.22f, 1e-6f);
        }
        if (v.position.z == 0.5f) {
            EXPECT_NEAR(r, 0.34f, 1e-6f);
        }
    }
    // A uv square is about square: the world area over the uv area, per unit of either, is the mean scale
    // squared; |dP/du| and |dP/dv| averaged over the mesh agree within 10 % (they differ locally: the
    // radius varies from 0.22 to 0.4 while u's scale is the mean circumference).
    double su = 0.0, sv = 0.0, weight = 0.0;
    for (std::size_t t = 0; t < vase.indices.size(); t += 3) {
        const MeshVertex& a = vase.vertices[vase.indices[t]];
        const MeshVertex& b = vase.vertices[vase.indices[t + 1]];
        const MeshVertex& c = vase.vertices[vase.indices[t + 2]];
        const glm::dvec3 e1 = b.position - a.position, e2 = c.position - a.position;
        const glm::dvec2 d1 = b.uv - a.uv, d2 = c.uv - a.uv;
        const double det = d1.x * d2.y - d2.x * d1.y;
        const double area = 0.5 * glm::length(glm::cross(e1, e2));
        su += area * glm::length((e1 * d2.y - e2 * d1.y) / det);
        sv += area * glm::length((e2 * d1.x - e1 * d2.x) / det);
        weight += area;
    }
    EXPECT_NEAR(su / sv, 1.0, 0.1);
}

TEST(BuiltinMeshes, PatchIsAnOpenArcWithUvInWorldUnits) {
    const Mesh patch = makeBuiltinMesh("patch", {4});
    // Its four sides, 2n edges each.
    EXPECT_EQ(openEdges(patch), 4u * 8u);
    for (const MeshVertex& v : patch.vertices) {
        // On the cylinder of radius 0.6 about the axis (0, y, -0.6), with the radial normal.
        const glm::vec3 fromAxis(v.position.x, 0.0f, v.position.z + 0.6f);
        EXPECT_NEAR(glm::length(fromAxis), 0.6f, 1e-6f);
        EXPECT_NEAR(glm::distance(v.normal, fromAxis / 0.6f), 0.0f, 1e-6f);
        // u is the arc length from the rim at -60 degrees, v = y + 0.5.
        const double angle = std::atan2(double(v.position.x), double(v.position.z) + 0.6);
        EXPECT_NEAR(v.uv.x, 0.6 * (angle + std::numbers::pi / 3.0), 1e-6);
        EXPECT_FLOAT_EQ(v.uv.y, v.position.y + 0.5f);
    }
}

// The trunk's documented axis (builtin_meshes.h): x = 0.05 sin(pi z), y = 0.
glm::dvec3 trunkAxis(double z) {
    return {0.05 * std::sin(std::numbers::pi * z), 0.0, z};
}

TEST(BuiltinMeshes, TrunkCountsOpenEndsAndSeam) {
    for (const int n : {1, 4, 16}) {
        SCOPED_TRACE(n);
        const Mesh trunk = makeBuiltinMesh("trunk", {n});
        // 4n segments around and 4n along: (4n + 1)^2 vertices (the seam column doubled), 2 (4n)^2
        // triangles, none left out.
        const std::size_t side = std::size_t(4 * n) + 1;
        ASSERT_EQ(trunk.vertices.size(), side * side);
        EXPECT_EQ(trunk.indices.size(), 3u * 2u * std::size_t(16 * n * n));
        // Open at both ends (no caps): the ground rim and the top rim, 4n edges each, nothing else open.
        EXPECT_EQ(openEdges(trunk), 2u * std::size_t(4 * n));
        for (std::size_t j = 0; j < side; ++j) {
            // The seam: vertex (0, j) at u = 0 and (4n, j) at u = 2, otherwise bit-identical.
            const MeshVertex& a = trunk.vertices[j * side];
            const MeshVertex& b = trunk.vertices[j * side + side - 1];
            EXPECT_EQ(a.position, b.position);
            EXPECT_EQ(a.normal, b.normal);
            EXPECT_EQ(a.tangent, b.tangent);
            EXPECT_EQ(a.uv.x, 0.0f);
            EXPECT_EQ(b.uv.x, 2.0f);
            EXPECT_EQ(a.uv.y, b.uv.y);
        }
    }
}

TEST(BuiltinMeshes, TrunkFrameIsOutwardAndFollowsTheSurface) {
    const int n = 16;
    const Mesh trunk = makeBuiltinMesh("trunk", {n});
    const int side = 4 * n + 1;
    const auto at = [&](int i, int j) -> const MeshVertex& {
        return trunk.vertices[std::size_t(j * side + i)];
    };
    double minOutward = 1.0, maxNormalError = 0.0, maxRimNormalError = 0.0, maxTangentError = 0.0;
    for (int j = 0; j < side; ++j) {
        for (int i = 0; i < side; ++i) {
            const MeshVertex& v = at(i, j);
            const glm::dvec3 p(v.position), normal(v.normal), tangent(v.tangent);
            EXPECT_NEAR(glm::length(normal), 1.0, 1e-6);
            EXPECT_NEAR(glm::dot(normal, tangent), 0.0, 1e-6);
            EXPECT_EQ(v.tangent.w, 1.0f);
            // Outward: along the horizontal direction away from the axis at the vertex's height.
            glm::dvec3 radial = p - trunkAxis(p.z);
            radial.z = 0.0;
            minOutward = std::min(minOutward, glm::dot(normal, glm::normalize(radial)));
            // Against the surface the vertices sample: central differences on the grid (one-sided on the
            // rims; around the seam the column next to the twin).
            const int im = i == 0 ? side - 2 : i - 1, ip = i == side - 1 ? 1 : i + 1;
            const int jm = std::max(j - 1, 0), jp = std::min(j + 1, side - 1);
            const glm::dvec3 du = glm::dvec3(at(ip, j).position) - glm::dvec3(at(im, j).position);
            const glm::dvec3 dv = glm::dvec3(at(i, jp).position) - glm::dvec3(at(i, jm).position);
            double& normalError = j == 0 || j == side - 1 ? maxRimNormalError : maxNormalError;
            normalError = std::max(normalError, angleBetween(normal, glm::cross(du, dv)));
            maxTangentError =
                std::max(maxTangentError, angleBetween(tangent, du - normal * glm::dot(normal, du)));
        }
    }
    std::printf(
        "[ measured ] trunk n=%d: min N . (horizontal direction from the axis) %.3f; vertex normal vs the "
        "grid's central-difference normal max %.2f deg inside, %.2f deg on the rims (one-sided); tangent "
        "vs the grid's u chord max %.2f deg\n",
        n, minOutward, degrees(maxNormalError), degrees(maxRimNormalError), degrees(maxTangentError));
    // N = dP/dtheta x dP/dz has N . radial = r > 0 exactly (builtin_meshes.cpp); the flare tilts N down
    // by 42 degrees at the ground (slope -0.905), the root lobes sideways as well (measured 0.626, 51 deg).
    EXPECT_GT(minOutward, 0.55);
    // The analytic normal is the surface's: central differences on the 64 x 64 grid agree to second order
    // (measured 1.10 degrees, where the root lobes curve most); on the rims the difference is one-sided, half
    // a row off, and the profile at the ground curves by about 3 per unit length: half of a row's 0.042
    // of arc is 3.6 degrees (measured 4.08 with the lobes). T against the chord across a vertex: measured
    // 0.70 degrees.
    EXPECT_LT(degrees(maxNormalError), 2.0);
    EXPECT_LT(degrees(maxRimNormalError), 6.0);
    EXPECT_LT(degrees(maxTangentError), 2.0);
    // No degenerate triangles: the smallest area is a sizeable part of a cell's (2 / 64)^2 / 2 (measured
    // 0.887).
    double minArea = 1e9;
    for (std::size_t t = 0; t < trunk.indices.size(); t += 3) {
        const glm::dvec3 a(trunk.vertices[trunk.indices[t]].position);
        const glm::dvec3 b(trunk.vertices[trunk.indices[t + 1]].position);
        const glm::dvec3 c(trunk.vertices[trunk.indices[t + 2]].position);
        minArea = std::min(minArea, 0.5 * glm::length(glm::cross(b - a, c - a)));
    }
    const double cellHalf = 0.5 * (2.0 / (4 * n)) * (2.0 / (4 * n));
    std::printf("[ measured ] trunk n=%d: smallest triangle %.3g of a half cell\n", n, minArea / cellHalf);
    EXPECT_GT(minArea, 0.5 * cellHalf);
}

struct Range {
    double lo = 1e9, hi = -1e9;
    void add(double x) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
    }
};

TEST(BuiltinMeshes, TrunkUvsAreInWorldUnits) {
    const int n = 16;
    const Mesh trunk = makeBuiltinMesh("trunk", {n});
    const int side = 4 * n + 1;
    const auto at = [&](int i, int j) -> const MeshVertex& {
        return trunk.vertices[std::size_t(j * side + i)];
    };
    // u = 2 i / 4n in [0, 2]; v the same along each row (rows are horizontal), 0 at the ground, increasing.
    for (int j = 0; j < side; ++j) {
        for (int i = 0; i < side; ++i) {
            EXPECT_FLOAT_EQ(at(i, j).uv.x, float(2.0 * i / (4 * n)));
            EXPECT_EQ(at(i, j).uv.y, at(0, j).uv.y);
            EXPECT_EQ(at(i, j).position.z, at(0, j).position.z);
        }
        if (j > 0) {
            EXPECT_GT(at(0, j).uv.y, at(0, j - 1).uv.y);
        }
    }
    EXPECT_EQ(at(0, 0).uv.y, 0.0f);
    EXPECT_EQ(at(0, 0).position.z, 0.0f);
    EXPECT_EQ(at(0, side - 1).position.z, 2.0f);
    // v is a function of z alone, whatever the tessellation: the coarsest trunk's rows (z = 0, 0.5, .., 2)
    // have the v of the same heights at n = 16 (Simpson's rule per row: float rounding, 1e-6).
    const Mesh coarse = makeBuiltinMesh("trunk", {1});
    for (int j = 0; j <= 4; ++j) {
        EXPECT_NEAR(coarse.vertices[std::size_t(5 * j)].uv.y, at(0, 16 * j).uv.y, 1e-6f) << j;
    }
    const float top = at(0, side - 1).uv.y;
    std::printf("[ measured ] trunk: v at the top %.4f\n", double(top));
    EXPECT_NEAR(top, 2.007f, 1e-3f);  // documented
    // World length per unit of uv along the grid's iso-lines: |dP/du| on the cells' u edges (chords: at 64
    // segments around they are 0.9996 of the arc), |dP/dv| on their v edges, and their ratio per cell (the
    // aspect a tile keeps).
    Range su, sv, aspect, suTrunk, svTrunk, aspectTrunk, shearTrunk;
    for (int j = 0; j + 1 < side; ++j) {
        for (int i = 0; i + 1 < side; ++i) {
            const MeshVertex &a = at(i, j), &b = at(i + 1, j), &c = at(i, j + 1);
            const glm::dvec3 alongU = glm::dvec3(b.position) - glm::dvec3(a.position);
            const glm::dvec3 alongV = glm::dvec3(c.position) - glm::dvec3(a.position);
            const double lu = glm::length(alongU) / double(b.uv.x - a.uv.x);
            const double lv = glm::length(alongV) / double(c.uv.y - a.uv.y);
            su.add(lu);
            sv.add(lv);
            aspect.add(lu / lv);
            if (a.position.z >= 0.5f) {
                suTrunk.add(lu);
                svTrunk.add(lv);
                aspectTrunk.add(lu / lv);
                shearTrunk.add(std::abs(degrees(angleBetween(alongU, alongV)) - 90.0));
            }
        }
    }
    std::printf(
        "[ measured ] trunk n=%d: |dP/du| in [%.3f, %.3f], |dP/dv| in [%.3f, %.3f], |dP/du| / |dP/dv| per "
        "cell in [%.3f, %.3f] everywhere; above z = 0.5 [%.3f, %.3f], [%.3f, %.3f] and [%.3f, %.3f], the "
        "u and v edges within %.2f deg of square\n",
        n, su.lo, su.hi, sv.lo, sv.hi, aspect.lo, aspect.hi, suTrunk.lo, suTrunk.hi, svTrunk.lo, svTrunk.hi,
        aspectTrunk.lo, aspectTrunk.hi, shearTrunk.hi);
    // Above the root flare (z >= 0.5) a unit of uv is a unit of length within 12 %: u's scale is the local
    // radius over 1 / pi, which the taper takes from 1.045 (z = 0.5) to 0.91 (z = 2) and the lumps move by
    // up to 3.5 % either way (measured 0.883 to 1.090); v is built to follow u's scale (measured 0.906 to
    // 1.050), so a tile keeps its aspect within 6 % (measured 0.964 to 1.040), and the S-bend's lean (at
    // most atan(0.05 pi) = 8.9 degrees, horizontal rows on a leaning axis) shears it by at most 10 degrees.
    EXPECT_GT(suTrunk.lo, 0.85);
    EXPECT_LT(suTrunk.hi, 1.12);
    EXPECT_GT(svTrunk.lo, 0.85);
    EXPECT_LT(svTrunk.hi, 1.12);
    EXPECT_GT(aspectTrunk.lo, 0.94);
    EXPECT_LT(aspectTrunk.hi, 1.06);
    EXPECT_LT(shearTrunk.hi, 10.0);
    // At the ground the flare widens the trunk by 1.3 (and the root lobes by up to 6 % more), and u and v
    // stretch together: up to 1.6 (measured 1.563 and 1.575). The lobes' slopes make the aspect the worst
    // there: within 0.9 to 1.25 (measured 0.946 to 1.199).
    EXPECT_GT(su.lo, 0.85);
    EXPECT_LT(su.hi, 1.6);
    EXPECT_GT(sv.lo, 0.85);
    EXPECT_LT(sv.hi, 1.6);
    EXPECT_GT(aspect.lo, 0.9);
    EXPECT_LT(aspect.hi, 1.25);
}

TEST(BuiltinMeshes, TrunkBounds) {
    // Documented extents (builtin_meshes.h), from n = 64 (256 segments around: the vertices reach within
    // 1e-4 of the surface's extreme); n = 16 reaches within 3e-3 of them.
    const glm::vec3 min(-0.429f, -0.464f, 0.0f), max(0.488f, 0.458f, 2.0f);
    for (const int n : {64, 16}) {
        const Bounds b = meshBounds(makeBuiltinMesh("trunk", {n}));
        std::printf("[ measured ] trunk n=%d bounds (%.4f %.4f %.4f) - (%.4f %.4f %.4f)\n", n,
                    double(b.min.x), double(b.min.y), double(b.min.z), double(b.max.x), double(b.max.y),
                    double(b.max.z));
        const float tolerance = n == 64 ? 1e-3f : 3e-3f;
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(b.min[k], min[k], tolerance) << n << " " << k;
            EXPECT_NEAR(b.max[k], max[k], tolerance) << n << " " << k;
        }
        // Exactly on the ground and 2 high.
        EXPECT_EQ(b.min.z, 0.0f);
        EXPECT_EQ(b.max.z, 2.0f);
    }
}

TEST(BuiltinMeshes, UnknownNameAndBadTessellationAreRefused) {
    try {
        makeBuiltinMesh("teapott");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        const std::string message = e.what();
        EXPECT_NE(message.find("teapott"), std::string::npos) << message;
        for (const std::string& name : builtinMeshList())
            EXPECT_NE(message.find(name), std::string::npos) << message;
    }
    EXPECT_THROW(makeBuiltinMesh("sphere", {0}), Error);
    EXPECT_THROW(makeBuiltinMesh("sphere", {257}), Error);
}

}  // namespace
}  // namespace strata
