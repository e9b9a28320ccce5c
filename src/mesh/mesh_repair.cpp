#include "strata/mesh/mesh_repair.h"

#include "strata/core/error.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace strata {
namespace {

// Relative flatness below which a triangle (in positions or in uvs) counts as degenerate: about float
// epsilon, the rounding of the stored coordinates themselves.
constexpr double kDegenerateRatio = 1e-7;

template <int N>
bool allFinite(const float* values) {
    for (int i = 0; i < N; ++i) {
        if (!std::isfinite(values[i])) return false;
    }
    return true;
}

void refuse(const Mesh& mesh, const std::string& what) {
    throw Error(ErrorKind::InvalidInput, mesh.name + ": " + what);
}

glm::dvec3 position(const Mesh& mesh, std::uint32_t index) {
    return glm::dvec3(mesh.vertices[index].position);
}

}  // namespace

MeshRepairReport repairMesh(Mesh& mesh, std::vector<std::uint32_t>* vertexRemap) {
    MeshRepairReport report;
    if (mesh.vertices.empty() || mesh.indices.empty()) refuse(mesh, "is empty (no triangles)");
    if (mesh.indices.size() % 3 != 0) {
        refuse(mesh, "has " + std::to_string(mesh.indices.size()) + " indices, not a multiple of 3");
    }
    for (std::size_t k = 0; k < mesh.indices.size(); ++k) {
        if (mesh.indices[k] >= mesh.vertices.size()) {
            refuse(mesh, "index " + std::to_string(mesh.indices[k]) + " (triangle " + std::to_string(k / 3) +
                             ") is out of range: there are " + std::to_string(mesh.vertices.size()) +
                             " vertices");
        }
    }
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const MeshVertex& v = mesh.vertices[i];
        const char* bad = !allFinite<3>(glm::value_ptr(v.position))  ? "position"
                          : !allFinite<3>(glm::value_ptr(v.normal))  ? "normal"
                          : !allFinite<2>(glm::value_ptr(v.uv))      ? "texture coordinate"
                          : !allFinite<4>(glm::value_ptr(v.tangent)) ? "tangent"
                                                                     : nullptr;
        if (bad) refuse(mesh, "vertex " + std::to_string(i) + " has a non-finite " + bad);
    }

    const std::size_t triangleCount = mesh.indices.size() / 3;
    std::vector<std::uint32_t> kept;
    kept.reserve(mesh.indices.size());
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const std::uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1], c = mesh.indices[3 * t + 2];
        if (a == b || b == c || a == c) {
            ++report.repeatedIndexTriangles;
            continue;
        }
        const glm::dvec3 e1 = position(mesh, b) - position(mesh, a);
        const glm::dvec3 e2 = position(mesh, c) - position(mesh, a);
        const glm::dvec3 e3 = position(mesh, c) - position(mesh, b);
        const double longest2 = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
        if (glm::length(glm::cross(e1, e2)) <= kDegenerateRatio * longest2) {
            ++report.zeroAreaTriangles;
            continue;
        }
        const glm::dvec2 d1 = glm::dvec2(mesh.vertices[b].uv) - glm::dvec2(mesh.vertices[a].uv);
        const glm::dvec2 d2 = glm::dvec2(mesh.vertices[c].uv) - glm::dvec2(mesh.vertices[a].uv);
        if (std::abs(d1.x * d2.y - d1.y * d2.x) <= kDegenerateRatio * glm::length(d1) * glm::length(d2)) {
            ++report.zeroUvAreaTriangles;
        }
        kept.insert(kept.end(), {a, b, c});
    }
    if (kept.empty())
        refuse(mesh, "all " + std::to_string(triangleCount) + " triangles are degenerate (zero area)");
    if (report.zeroUvAreaTriangles == kept.size() / 3) {
        refuse(mesh,
               "texture coordinates are degenerate (zero uv area) on every triangle; relief mapping needs "
               "them");
    }
    mesh.indices = std::move(kept);

    // Compact: drop the vertices no triangle uses any more.
    std::vector<std::uint32_t> remap(mesh.vertices.size(), kRemovedVertex);
    for (std::uint32_t index : mesh.indices) remap[index] = 0;
    std::vector<MeshVertex> vertices;
    vertices.reserve(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        if (remap[i] == kRemovedVertex) continue;
        remap[i] = static_cast<std::uint32_t>(vertices.size());
        vertices.push_back(mesh.vertices[i]);
    }
    report.removedVertices = mesh.vertices.size() - vertices.size();
    mesh.vertices = std::move(vertices);
    for (std::uint32_t& index : mesh.indices) index = remap[index];
    if (vertexRemap) *vertexRemap = std::move(remap);
    return report;
}

}  // namespace strata
