#include "strata/gdm/solid_mesh_io.h"

#include "level_set_mesh.h"

#include "strata/core/error.h"
#include "strata/core/file.h"

#include <openvdb/io/File.h>
#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace strata {

namespace {

std::string vertexText(const glm::vec3& p) {
    return "(" + formatNumber(p.x) + ", " + formatNumber(p.y) + ", " + formatNumber(p.z) + ")";
}

std::string edgeText(std::uint32_t a, std::uint32_t b) {
    return "edge " + std::to_string(a + 1) + "-" + std::to_string(b + 1);
}

void refuseHeight(double height, const std::string& what) {
    if (!(std::isfinite(height) && height > 0.0))
        throw Error(ErrorKind::InvalidInput,
                    what + ": the shell thickness H must be a number > 0, got " + formatNumber(height));
}

}  // namespace

void validateSolidMesh(const SolidMesh& mesh, const std::string& what) {
    const auto fail = [&](const std::string& message) {
        throw Error(ErrorKind::InvalidInput, what + ": " + message);
    };
    refuseHeight(mesh.height, what);
    if (mesh.triangles.empty()) fail("the mesh is empty (no triangles)");
    // CONVENTIONS §8: geometry that crosses a tile side wraps and geometry outside 0 <= z <= H is clipped
    // away, so a vertex may lie outside the tile box, but no more than kSolidMeshReach tile widths (more
    // would only multiply the translates the bake's periodic scene holds, and lengthen its inside test's
    // rays, which run through the mesh's whole z range).
    const double tol = kSolidMeshTolerance;
    const double reach = kSolidMeshReach + tol;
    const std::string tile = "the tile [0, 1] x [0, 1] x [0, " + formatNumber(mesh.height) + "]";
    glm::dvec3 lo(std::numeric_limits<double>::infinity());
    glm::dvec3 hi(-std::numeric_limits<double>::infinity());
    for (std::size_t n = 0; n < mesh.positions.size(); ++n) {
        const glm::vec3& p = mesh.positions[n];
        const glm::dvec3 q(p);
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
            fail("vertex " + std::to_string(n + 1) + " is not finite " + vertexText(p));
        const auto outside = [&](double value, double tileLo, double tileHi, const char* axis,
                                 const char* why) {
            if (value >= tileLo - reach && value <= tileHi + reach) return;
            fail("vertex " + std::to_string(n + 1) + " " + vertexText(p) + " lies more than " +
                 formatNumber(kSolidMeshReach) + " tile width outside " + tile + " in " + axis + " (" + axis +
                 " must be in [" + formatNumber(tileLo - kSolidMeshReach) + ", " +
                 formatNumber(tileHi + kSolidMeshReach) + "]; " + why + ")");
        };
        const char* wraps = "geometry that crosses a tile side wraps: move the mesh by whole tiles";
        outside(q.x, 0.0, 1.0, "x", wraps);
        outside(q.y, 0.0, 1.0, "y", wraps);
        outside(q.z, 0.0, mesh.height, "z", "geometry outside 0 <= z <= H is clipped away: cut it off");
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    if (hi.x < -tol || lo.x > 1.0 + tol || hi.y < -tol || lo.y > 1.0 + tol || hi.z < -tol ||
        lo.z > mesh.height + tol)
        fail("the mesh lies entirely outside " + tile + " (its bounding box " + vertexText(glm::vec3(lo)) +
             " - " + vertexText(glm::vec3(hi)) + " does not meet it)");
    // Directed edges: each must occur once, and its reverse once.
    std::unordered_map<std::uint64_t, std::size_t> directed;  // (a, b) -> triangle
    directed.reserve(3 * mesh.triangles.size());
    const auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        for (int c = 0; c < 3; ++c)
            if (tri[c] >= mesh.positions.size())
                fail("triangle " + std::to_string(t + 1) + " uses vertex " + std::to_string(tri[c] + 1) +
                     " of " + std::to_string(mesh.positions.size()));
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
            fail("triangle " + std::to_string(t + 1) + " is degenerate (a repeated vertex)");
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = tri[c], b = tri[(c + 1) % 3];
            const auto [it, inserted] = directed.emplace(key(a, b), t);
            if (!inserted) {
                // A third use of the edge (in either direction) makes it non-manifold; a second use in the
                // same direction with the reverse missing is an orientation flip.
                const bool reverse = directed.count(key(b, a)) > 0;
                if (reverse)
                    fail("non-manifold: " + edgeText(a, b) + " is shared by more than two triangles (" +
                         std::to_string(it->second + 1) + ", " + std::to_string(t + 1) + ", ...)");
                fail("inconsistently oriented: triangles " + std::to_string(it->second + 1) + " and " +
                     std::to_string(t + 1) + " both use " + edgeText(a, b) + " in the same direction");
            }
        }
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = tri[c], b = tri[(c + 1) % 3];
            if (directed.count(key(b, a)) == 0) {
                // The edge (a, b) has no partner: open, unless it is used again the same way (caught above).
                fail("open: " + edgeText(a, b) + " of triangle " + std::to_string(t + 1) +
                     " belongs to no other triangle");
            }
        }
    }
}

SolidMesh parseSolidObj(const std::string& objText, const std::string& what, double height) {
    refuseHeight(height, what);
    std::istringstream stream(objText);
    SolidMesh mesh;
    mesh.height = height;
    std::string line;
    int lineNumber = 0;
    const auto malformed = [&](const std::string& why) {
        throw Error(ErrorKind::InvalidInput,
                    what + ":" + std::to_string(lineNumber) + ": " + why + ": \"" + line + "\"");
    };
    while (std::getline(stream, line)) {
        ++lineNumber;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream fields(line);
        std::string tag;
        if (!(fields >> tag) || tag[0] == '#') continue;
        if (tag == "v") {
            std::string text[3];
            if (!(fields >> text[0] >> text[1] >> text[2])) malformed("a vertex needs x y z");
            glm::vec3 p;
            for (int c = 0; c < 3; ++c) {
                char* end = nullptr;
                p[c] = std::strtof(text[c].c_str(), &end);
                if (end == text[c].c_str() || *end != '\0') malformed("not a number \"" + text[c] + "\"");
            }
            mesh.positions.push_back(p);
        } else if (tag == "f") {
            std::vector<std::uint32_t> polygon;
            std::string corner;
            while (fields >> corner) {
                char* end = nullptr;
                const long index = std::strtol(corner.c_str(), &end, 10);
                if (end == corner.c_str() || (*end != '\0' && *end != '/'))
                    malformed("bad vertex index \"" + corner + "\"");
                const long count = static_cast<long>(mesh.positions.size());
                const long resolved = index < 0 ? count + index : index - 1;
                if (index == 0 || resolved < 0 || resolved >= count)
                    malformed("vertex index " + std::to_string(index) + " out of range (" +
                              std::to_string(count) + " vertices so far)");
                polygon.push_back(static_cast<std::uint32_t>(resolved));
            }
            if (polygon.size() < 3) malformed("a face needs at least 3 vertices");
            for (std::size_t n = 1; n + 1 < polygon.size(); ++n)
                mesh.triangles.push_back({polygon[0], polygon[n], polygon[n + 1]});
        }
    }
    validateSolidMesh(mesh, what);
    return mesh;
}

SolidMesh readSolidObj(const std::filesystem::path& path, double height) {
    refuseHeight(height, path.string());
    SolidMesh mesh = parseSolidObj(readTextFile(path), path.string(), height);
    mesh.source = path.filename().string();
    return mesh;
}

SolidMesh readSolidVdb(const std::filesystem::path& path, double height) {
    const std::string what = path.string();
    refuseHeight(height, what);
    detail::initializeOpenVdb();
    if (!std::filesystem::is_regular_file(path))
        throw Error(ErrorKind::Io, what + ": cannot open (no such file)");
    openvdb::GridPtrVecPtr grids;
    try {
        openvdb::io::File file(path.string());
        file.open();
        grids = file.getGrids();
        file.close();
    } catch (const openvdb::Exception& e) {
        throw Error(ErrorKind::InvalidInput, what + ": not a readable OpenVDB file: " + e.what());
    }
    for (const openvdb::GridBase::Ptr& base : *grids) {
        const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!grid || grid->getGridClass() != openvdb::GRID_LEVEL_SET) continue;
        SolidMesh mesh = detail::meshLevelSet(*grid);
        mesh.source = path.filename().string();
        mesh.height = height;
        validateSolidMesh(mesh, what + " (grid \"" + grid->getName() + "\")");
        return mesh;
    }
    throw Error(ErrorKind::InvalidInput, what + ": holds no level-set FloatGrid (" +
                                             std::to_string(grids->size()) +
                                             " grids, none a float grid of class level set)");
}

std::string solidObjText(const SolidMesh& mesh) {
    std::string text = "# strata solid mesh: " + mesh.source +
                       ", tile units (CONVENTIONS 8), H = " + formatNumber(mesh.height) + "\n";
    char buffer[96];
    for (const glm::vec3& p : mesh.positions) {
        std::snprintf(buffer, sizeof buffer, "v %.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z));
        text += buffer;
    }
    for (const auto& t : mesh.triangles) {
        std::snprintf(buffer, sizeof buffer, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
        text += buffer;
    }
    return text;
}

void writeSolidObj(const std::filesystem::path& path, const SolidMesh& mesh) {
    writeTextFileAtomic(path, solidObjText(mesh));
}

}  // namespace strata
