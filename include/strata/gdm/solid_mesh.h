// A mesostructure's solid as a triangle mesh in the tile's isotropic frame (CONVENTIONS §8): x, y in
// [0, 1] (geometry that crosses a tile side wraps: the solid is the union of the mesh translated by every
// integer (i, j)), z in [0, H] (geometry outside is clipped away). Closed and consistently oriented, normals
// (counter-clockwise triangles) pointing out of the solid; the solid is the inside. The GDM bake
// (gdm_bake.h) and the exact CPU reference cast their rays against it.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace strata {

struct SolidMesh {
    std::string source;                // where it came from, for messages ("weave", "a.obj")
    double height = 0.25;              // H, tile widths
    std::vector<glm::vec3> positions;  // (u, v, z), z = w H
    std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from outside the solid
};

}  // namespace strata
