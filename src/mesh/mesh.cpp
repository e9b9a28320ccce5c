#include "strata/mesh/mesh.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstddef>

namespace strata {

Bounds meshBounds(const Mesh& mesh) {
    if (mesh.vertices.empty()) return {};
    Bounds bounds{mesh.vertices.front().position, mesh.vertices.front().position};
    for (const MeshVertex& v : mesh.vertices) {
        bounds.min = glm::min(bounds.min, v.position);
        bounds.max = glm::max(bounds.max, v.position);
    }
    return bounds;
}

std::vector<glm::dvec2> uvLengths(const Mesh& mesh) {
    std::vector<glm::dvec2> sum(mesh.vertices.size(), glm::dvec2(0.0));
    std::vector<double> weight(mesh.vertices.size(), 0.0);
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const std::uint32_t ids[3] = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
        const glm::dvec3 p0(mesh.vertices[ids[0]].position);
        const glm::dvec3 e1 = glm::dvec3(mesh.vertices[ids[1]].position) - p0;
        const glm::dvec3 e2 = glm::dvec3(mesh.vertices[ids[2]].position) - p0;
        const glm::dvec2 t0(mesh.vertices[ids[0]].uv);
        const glm::dvec2 d1 = glm::dvec2(mesh.vertices[ids[1]].uv) - t0;
        const glm::dvec2 d2 = glm::dvec2(mesh.vertices[ids[2]].uv) - t0;
        const double det = d1.x * d2.y - d2.x * d1.y;
        const double area = 0.5 * glm::length(glm::cross(e1, e2));
        if (!(std::abs(det) > 1e-20) || !(area > 0.0)) continue;
        const glm::dvec3 dPdu = (e1 * d2.y - e2 * d1.y) / det;
        const glm::dvec3 dPdv = (e2 * d1.x - e1 * d2.x) / det;
        const glm::dvec2 lengths(glm::length(dPdu), glm::length(dPdv));
        if (!std::isfinite(lengths.x) || !std::isfinite(lengths.y)) continue;
        for (const std::uint32_t id : ids) {
            sum[id] += area * lengths;
            weight[id] += area;
        }
    }
    for (std::size_t v = 0; v < sum.size(); ++v)
        sum[v] = weight[v] > 0.0 ? sum[v] / weight[v] : glm::dvec2(1.0);
    return sum;
}

}  // namespace strata
