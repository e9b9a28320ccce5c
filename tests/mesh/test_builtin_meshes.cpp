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
