#include "strata/mesh/mesh.h"

#include <glm/common.hpp>

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

}  // namespace strata
