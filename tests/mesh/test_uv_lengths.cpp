// uvLengths (strata/mesh/mesh.h): the object-space length of a unit of uv along T and B, per vertex.
#include "strata/mesh/mesh.h"

#include <gtest/gtest.h>

#include <vector>

namespace strata {
namespace {

MeshVertex vertex(glm::vec3 position, glm::vec2 uv) {
    MeshVertex v;
    v.position = position;
    v.uv = uv;
    return v;
}

// A 2 x 0.5 rectangle with uv (0, 0)-(1, 1): one unit of u is 2 long, one unit of v 0.5.
Mesh rectangle() {
    Mesh mesh;
    mesh.name = "rectangle";
    mesh.vertices = {vertex({0, 0, 0}, {0, 0}), vertex({2, 0, 0}, {1, 0}), vertex({2, 0.5f, 0}, {1, 1}),
                     vertex({0, 0.5f, 0}, {0, 1})};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

TEST(UvLengths, AreTheJacobianColumnsOfALinearMapping) {
    const std::vector<glm::dvec2> lengths = uvLengths(rectangle());
    ASSERT_EQ(lengths.size(), 4u);
    // Every triangle has the same Jacobian, so every mean is it; sums of a few doubles: 1e-12.
    for (const glm::dvec2& l : lengths) {
        EXPECT_NEAR(l.x, 2.0, 1e-12);
        EXPECT_NEAR(l.y, 0.5, 1e-12);
    }
}

TEST(UvLengths, AreAreaWeightedMeansOverTheTrianglesAroundAVertex) {
    // Two triangles share the edge 0-2: the first maps a unit of u to 1, the second (3 times the area,
    // its positions stretched along x) to 3. Vertex 0 and 2 see both: (1 * 1 + 3 * 3) / (1 + 3) = 2.5.
    Mesh mesh;
    mesh.vertices = {vertex({0, 0, 0}, {0, 0}), vertex({1, 0, 0}, {1, 0}), vertex({0, 1, 0}, {0, 1}),
                     vertex({-3, 0, 0}, {-1, 0})};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    const std::vector<glm::dvec2> lengths = uvLengths(mesh);
    EXPECT_NEAR(lengths[0].x, 2.5, 1e-12);  // a handful of double operations on small integers
    EXPECT_NEAR(lengths[2].x, 2.5, 1e-12);
    EXPECT_NEAR(lengths[1].x, 1.0, 1e-12);
    EXPECT_NEAR(lengths[3].x, 3.0, 1e-12);
    for (const glm::dvec2& l : lengths) EXPECT_NEAR(l.y, 1.0, 1e-12);
}

TEST(UvLengths, AreOneWhereTheUvMappingIsDegenerate) {
    Mesh mesh = rectangle();
    for (MeshVertex& v : mesh.vertices) v.uv = glm::vec2(0.25f);  // every triangle has zero uv area
    mesh.vertices.push_back(vertex({5, 5, 5}, {0, 0}));           // and a vertex in no triangle
    for (const glm::dvec2& l : uvLengths(mesh)) EXPECT_EQ(l, glm::dvec2(1.0));
}

}  // namespace
}  // namespace strata
