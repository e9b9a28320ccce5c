// Small closed solids for the GDM tests: an axis-aligned box and an icosphere.
#pragma once

#include "strata/gdm/solid_mesh.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace strata {

// A closed axis-aligned box, faces counter-clockwise seen from outside.
inline SolidMesh boxMesh(glm::vec3 lo, glm::vec3 hi, double height) {
    SolidMesh mesh;
    mesh.source = "box";
    mesh.height = height;
    for (int corner = 0; corner < 8; ++corner)
        mesh.positions.push_back(
            {corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z});
    // Each face as a quad (a, b, c, d), counter-clockwise from outside.
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        mesh.triangles.push_back({std::uint32_t(f[0]), std::uint32_t(f[1]), std::uint32_t(f[2])});
        mesh.triangles.push_back({std::uint32_t(f[0]), std::uint32_t(f[2]), std::uint32_t(f[3])});
    }
    return mesh;
}

// An icosphere: the icosahedron subdivided `levels` times, vertices on the sphere (so the polyhedron lies
// inside it).
inline SolidMesh icosphere(glm::dvec3 centre, double radius, int levels, double height) {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<glm::dvec3> unit = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                    {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                    {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (auto& p : unit) p = glm::normalize(p);
    std::vector<std::array<std::uint32_t, 3>> faces = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
        const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto found = midpoints.find(key);
            if (found != midpoints.end()) return found->second;
            unit.push_back(glm::normalize(unit[a] + unit[b]));
            return midpoints[key] = std::uint32_t(unit.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> finer;
        for (const auto& f : faces) {
            const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]),
                                ca = midpoint(f[2], f[0]);
            finer.push_back({f[0], ab, ca});
            finer.push_back({f[1], bc, ab});
            finer.push_back({f[2], ca, bc});
            finer.push_back({ab, bc, ca});
        }
        faces = std::move(finer);
    }
    SolidMesh mesh;
    mesh.source = "icosphere";
    mesh.height = height;
    for (const auto& p : unit) mesh.positions.push_back(glm::vec3(centre + radius * p));
    mesh.triangles = faces;
    return mesh;
}

}  // namespace strata
