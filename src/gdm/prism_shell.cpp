#include "strata/gdm/prism_shell.h"

#include "strata/core/error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

namespace strata {

namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Welds positions closer than `tolerance` (per axis) into shell vertices: a hash grid of cells of that size,
// each position compared with the shell vertices in the 27 cells around its own. Returns the shell vertex
// of every mesh vertex; `base` receives the first position of each.
std::vector<std::uint32_t> weld(const Mesh& mesh, double tolerance, std::vector<glm::vec3>& base) {
    const auto cellOf = [&](const glm::vec3& p) { return glm::ivec3(glm::floor(glm::dvec3(p) / tolerance)); };
    const auto key = [](const glm::ivec3& c) {
        return (std::uint64_t(std::uint32_t(c.x) & 0x1fffff) << 42) |
               (std::uint64_t(std::uint32_t(c.y) & 0x1fffff) << 21) |
               std::uint64_t(std::uint32_t(c.z) & 0x1fffff);
    };
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
    std::vector<std::uint32_t> shellOf(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const glm::vec3& p = mesh.vertices[v].position;
        const glm::ivec3 cell = cellOf(p);
        std::uint32_t found = std::uint32_t(-1);
        for (int dz = -1; dz <= 1 && found == std::uint32_t(-1); ++dz)
            for (int dy = -1; dy <= 1 && found == std::uint32_t(-1); ++dy)
                for (int dx = -1; dx <= 1 && found == std::uint32_t(-1); ++dx) {
                    const auto it = cells.find(key(cell + glm::ivec3(dx, dy, dz)));
                    if (it == cells.end()) continue;
                    for (const std::uint32_t s : it->second) {
                        const glm::dvec3 d = glm::abs(glm::dvec3(base[s]) - glm::dvec3(p));
                        if (d.x <= tolerance && d.y <= tolerance && d.z <= tolerance) {
                            found = s;
                            break;
                        }
                    }
                }
        if (found == std::uint32_t(-1)) {
            found = std::uint32_t(base.size());
            base.push_back(p);
            cells[key(cell)].push_back(found);
        }
        shellOf[v] = found;
    }
    return shellOf;
}

// A triangle's world length of one tile, sqrt(|dP/du| |dP/dv| / (tiling.x tiling.y)), and its area; 0 area
// where its uvs are degenerate.
struct TileMeasure {
    double length = 0.0;
    double area = 0.0;
};

TileMeasure tileMeasure(const MeshVertex& a, const MeshVertex& b, const MeshVertex& c,
                        const glm::dvec2& tiling) {
    const glm::dvec3 e1 = glm::dvec3(b.position) - glm::dvec3(a.position);
    const glm::dvec3 e2 = glm::dvec3(c.position) - glm::dvec3(a.position);
    const glm::dvec2 d1 = glm::dvec2(b.uv) - glm::dvec2(a.uv);
    const glm::dvec2 d2 = glm::dvec2(c.uv) - glm::dvec2(a.uv);
    const double det = d1.x * d2.y - d2.x * d1.y;
    const double area = 0.5 * glm::length(glm::cross(e1, e2));
    if (!(std::abs(det) > 1e-20) || !(area > 0.0)) return {};
    const glm::dvec3 dPdu = (e1 * d2.y - e2 * d1.y) / det;
    const glm::dvec3 dPdv = (e2 * d1.x - e1 * d2.x) / det;
    const double length = std::sqrt(glm::length(dPdu) * glm::length(dPdv) / (tiling.x * tiling.y));
    if (!std::isfinite(length)) return {};
    return {length, area};
}

}  // namespace

std::array<std::array<PrismCorner, 3>, 8> prismTriangleCorners(const PrismShell& shell, std::size_t p) {
    const auto& prism = shell.prisms[p];
    std::array<std::array<PrismCorner, 3>, 8> faces;
    faces[0] = {{{0, false}, {1, false}, {2, false}}};
    faces[1] = {{{0, true}, {1, true}, {2, true}}};
    for (int e = 0; e < 3; ++e) {
        const int a = e, b = (e + 1) % 3;
        // Outward: the prism lies to the left of a -> b seen along +N.
        if (prism[a] < prism[b]) {  // diagonal base a - top b
            faces[2 + 2 * e] = {{{a, false}, {b, false}, {b, true}}};
            faces[3 + 2 * e] = {{{a, false}, {b, true}, {a, true}}};
        } else {  // diagonal base b - top a
            faces[2 + 2 * e] = {{{a, false}, {b, false}, {a, true}}};
            faces[3 + 2 * e] = {{{b, false}, {b, true}, {a, true}}};
        }
    }
    return faces;
}

std::array<ShellTriangle, 8> prismTriangles(const PrismShell& shell, std::size_t p) {
    const auto& prism = shell.prisms[p];
    const auto corners = prismTriangleCorners(shell, p);
    std::array<ShellTriangle, 8> faces;
    for (int f = 0; f < 8; ++f)
        for (int c = 0; c < 3; ++c) {
            const PrismCorner corner = corners[f][c];
            const std::uint32_t s = prism[corner.corner];
            faces[f][c] = corner.top ? shell.top[s] : shell.base[s];
        }
    return faces;
}

PrismShell buildPrismShell(const Mesh& mesh, const PrismShellOptions& options) {
    const std::string what = "prism shell of " + (mesh.name.empty() ? std::string("a mesh") : mesh.name);
    const auto fail = [&](const std::string& message) {
        throw Error(ErrorKind::InvalidInput, what + ": " + message);
    };
    if (!(std::isfinite(options.height) && options.height > 0.0))
        fail("the shell thickness H must be > 0 tile widths, got " + formatNumber(options.height));
    if (!(options.tiling.x > 0.0 && options.tiling.y > 0.0 && std::isfinite(options.tiling.x) &&
          std::isfinite(options.tiling.y)))
        fail("the tiling must be > 0, got " + formatNumber(options.tiling.x) + " x " +
             formatNumber(options.tiling.y));
    if (options.thickness && !(std::isfinite(*options.thickness) && *options.thickness > 0.0))
        fail("the thickness T must be > 0 world units, got " + formatNumber(*options.thickness));
    if (mesh.vertices.empty() || mesh.indices.size() < 3) fail("the mesh is empty");
    if (mesh.indices.size() % 3 != 0)
        fail(std::to_string(mesh.indices.size()) + " indices, not a multiple of 3");
    for (std::size_t n = 0; n < mesh.indices.size(); ++n)
        if (mesh.indices[n] >= mesh.vertices.size())
            fail("index " + std::to_string(n) + " is " + std::to_string(mesh.indices[n]) + ", past the " +
                 std::to_string(mesh.vertices.size()) + " vertices");
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        if (!finite(mesh.vertices[v].position) || !finite(mesh.vertices[v].normal))
            fail("vertex " + std::to_string(v) + " has a position or normal that is not finite");

    PrismShell shell;
    const Bounds bounds = meshBounds(mesh);
    const double size = std::max(double(glm::length(bounds.max - bounds.min)), 1e-30);
    const std::vector<std::uint32_t> shellOf = weld(mesh, 1e-6 * size, shell.base);

    // Normals: the sum of the welded mesh vertices' normals; the triangles' area-weighted normals where it
    // vanishes.
    std::vector<glm::dvec3> sum(shell.base.size(), glm::dvec3(0.0));
    std::vector<glm::dvec3> faceSum(shell.base.size(), glm::dvec3(0.0));
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        sum[shellOf[v]] += glm::dvec3(mesh.vertices[v].normal);
    double measured = 0.0, area = 0.0;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::array<std::uint32_t, 3> v = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        const std::array<std::uint32_t, 3> s = {shellOf[v[0]], shellOf[v[1]], shellOf[v[2]]};
        const MeshVertex &a = mesh.vertices[v[0]], &b = mesh.vertices[v[1]], &c = mesh.vertices[v[2]];
        const TileMeasure tile = tileMeasure(a, b, c, options.tiling);
        measured += tile.length * tile.area;
        area += tile.area;
        if (s[0] == s[1] || s[1] == s[2] || s[0] == s[2]) {
            ++shell.degenerateTriangles;
            continue;
        }
        const glm::dvec3 n = glm::cross(glm::dvec3(b.position) - glm::dvec3(a.position),
                                        glm::dvec3(c.position) - glm::dvec3(a.position));
        for (const std::uint32_t corner : s) faceSum[corner] += n;
        shell.prisms.push_back(s);
        shell.corners.push_back(v);
    }
    if (shell.prisms.empty()) fail("every triangle is degenerate");
    shell.normal.resize(shell.base.size());
    for (std::size_t s = 0; s < shell.base.size(); ++s) {
        glm::dvec3 n = sum[s];
        if (!(glm::length(n) > 1e-12)) n = faceSum[s];
        if (!(glm::length(n) > 0.0)) n = glm::dvec3(0.0, 0.0, 1.0);  // an unused, isolated vertex
        shell.normal[s] = glm::vec3(glm::normalize(n));
    }

    shell.tileLength = area > 0.0 ? measured / area : 0.0;
    shell.thickness = options.thickness ? *options.thickness : options.height * shell.tileLength;
    if (!(shell.thickness > 0.0))
        fail("the default thickness H times a tile's world length is 0: no triangle has usable uvs (give T)");
    shell.top.resize(shell.base.size());
    for (std::size_t s = 0; s < shell.base.size(); ++s)
        shell.top[s] = glm::vec3(glm::dvec3(shell.base[s]) + shell.thickness * glm::dvec3(shell.normal[s]));
    return shell;
}

}  // namespace strata
