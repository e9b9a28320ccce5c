// computeTangents against the reference MikkTSpace: tangents that Blender 3.4.1 computed
// (mesh.calc_tangents(), Blender's port of mikktspace.c) for four meshes, stored in tests/data/mikktspace/
// with the commands that made them (README.md there). The inputs are written by
// MikktspaceReference.DISABLED_WriteInputs (run with --gtest_also_run_disabled_tests).
#include "strata/mesh/builtin_meshes.h"
#include "strata/mesh/mesh_loader.h"
#include "strata/mesh/tangent_space.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace strata {
namespace {

const std::filesystem::path kDataDir = std::filesystem::path(STRATA_SOURCE_DIR) / "tests/data/mikktspace";

// The teapot's tessellation in the data: 4 segments per patch edge (992 triangles) keeps the file small.
constexpr int kTeapotTessellation = 4;

// One triangle corner of the reference: what Blender fed MikkTSpace and what it answered.
struct ReferenceCorner {
    glm::vec3 position{0.0f};
    glm::vec2 uv{0.0f};
    glm::vec3 normal{0.0f};
    glm::vec3 tangent{0.0f};
    float sign = 0.0f;
};

std::vector<ReferenceCorner> readReference(const std::string& name) {
    std::ifstream in(kDataDir / (name + ".tangents.txt"));
    EXPECT_TRUE(in) << name;
    std::vector<ReferenceCorner> corners;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        ReferenceCorner c;
        s >> c.position.x >> c.position.y >> c.position.z >> c.uv.x >> c.uv.y >> c.normal.x >> c.normal.y >>
            c.normal.z >> c.tangent.x >> c.tangent.y >> c.tangent.z >> c.sign;
        EXPECT_TRUE(s) << name << ": " << line;
        corners.push_back(c);
    }
    return corners;
}

// Where the reference has no tangent: a corner of a triangle with zero uv area that no tangent group
// reached keeps MikkTSpace's initial value, tangent (1, 0, 0) with sign -1 (not orthogonal to N; ours is
// repaired, tangent_space.h). Recognised as that exact value on a triangle with zero uv area.
bool isPlaceholder(const std::vector<ReferenceCorner>& ref, std::size_t corner) {
    const std::size_t t = corner - corner % 3;
    const glm::vec2 d1 = ref[t + 1].uv - ref[t].uv, d2 = ref[t + 2].uv - ref[t].uv;
    return d1.x * d2.y - d1.y * d2.x == 0.0f && ref[corner].tangent == glm::vec3(1, 0, 0) &&
           ref[corner].sign == -1.0f;
}

struct Comparison {
    std::size_t corners = 0;
    std::size_t placeholders = 0;
    std::size_t signMismatches = 0;
    double maxAngleDeg = 0.0;
    double maxNormalDeg = 0.0;  // our normals against the ones Blender used (its custom normals are 16-bit)
    std::size_t verticesBefore = 0, verticesAfter = 0;
    std::size_t nonUnitNormals = 0;  // reference normals that were not unit (normalised for ours)
};

double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
    const double c = glm::dot(a, b) / (glm::length(a) * glm::length(b));
    return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

// Feeds `mesh` the normals Blender used (MikkTSpace takes the normals as given), computes our tangents and
// compares them corner by corner with the reference. Triangles correspond in order; positions and uvs must
// agree (float32 round trip through text with 9 digits, and glTF's 1 - v flip done by both sides).
Comparison compareWithReference(Mesh mesh, const std::string& name) {
    const std::vector<ReferenceCorner> ref = readReference(name);
    Comparison result;
    EXPECT_EQ(ref.size(), mesh.indices.size()) << name;
    if (ref.size() != mesh.indices.size()) return result;
    std::vector<int> normalSource(mesh.vertices.size(), -1);
    for (std::size_t c = 0; c < ref.size(); ++c) {
        MeshVertex& v = mesh.vertices[mesh.indices[c]];
        // Positions: exact float values written with 9 significant digits read back exactly.
        EXPECT_EQ(v.position, ref[c].position) << name << " corner " << c;
        // uv: 1e-6, the float rounding of glTF's v flip (exact for the OBJ inputs).
        EXPECT_LT(glm::length(v.uv - ref[c].uv), 1e-6f) << name << " corner " << c;
        int& source = normalSource[mesh.indices[c]];
        if (source < 0) {
            result.maxNormalDeg = std::max(result.maxNormalDeg, angleDeg(v.normal, ref[c].normal));
            source = static_cast<int>(c);
            v.normal = ref[c].normal;
            // Blender's normal at corner b of collapsed.obj's collapsed triangle is (0, 0, 0.96): ours need
            // unit normals. That corner has no reference tangent (a placeholder), so normalising it changes
            // nothing compared.
            if (std::abs(glm::length(v.normal) - 1.0f) > 1e-3f) {
                v.normal = glm::normalize(v.normal);
                ++result.nonUnitNormals;
            }
        } else {
            // Blender gives all corners of one of our vertices the same normal (one smooth fan).
            EXPECT_EQ(ref[static_cast<std::size_t>(source)].normal, ref[c].normal) << name << " corner " << c;
        }
    }
    result.verticesBefore = mesh.vertices.size();
    computeTangents(mesh);
    result.verticesAfter = mesh.vertices.size();
    for (std::size_t c = 0; c < ref.size(); ++c) {
        ++result.corners;
        if (isPlaceholder(ref, c)) {
            ++result.placeholders;
            continue;
        }
        const glm::vec4& t = mesh.vertices[mesh.indices[c]].tangent;
        result.maxAngleDeg = std::max(result.maxAngleDeg, angleDeg(glm::vec3(t), ref[c].tangent));
        if (t.w != ref[c].sign) {
            ++result.signMismatches;
            ADD_FAILURE() << name << " corner " << c << ": sign " << t.w << ", reference " << ref[c].sign;
        }
    }
    std::printf(
        "%s: %zu corners, %zu without a reference tangent, max angle error %.6f deg, %zu sign "
        "mismatches, normals within %.4f deg, vertices %zu -> %zu\n",
        name.c_str(), result.corners, result.placeholders, result.maxAngleDeg, result.signMismatches,
        result.maxNormalDeg, result.verticesBefore, result.verticesAfter);
    return result;
}

// The tolerance on the tangent direction: Blender computes in float and weights the corners with an
// approximate acos (max error 4.5e-5 rad); the data is printed with 9 digits. Measured errors are below
// 1e-3 deg (docs/meshes.md); 0.01 deg leaves room for float rounding without hiding a real difference (a
// different weighting or grouping moves tangents by degrees).
constexpr double kMaxAngleDeg = 0.01;
// Blender stores custom normals in 16-bit spherical coordinates; ours must be what we meant to give it.
constexpr double kMaxNormalDeg = 0.1;

void expectMatches(const Comparison& c) {
    EXPECT_GT(c.corners, 0u);
    EXPECT_LE(c.maxAngleDeg, kMaxAngleDeg);
    EXPECT_EQ(c.signMismatches, 0u);
    EXPECT_LE(c.maxNormalDeg, kMaxNormalDeg);
}

TEST(MikktspaceReference, Teapot) {
    // The built-in's analytic tangents are replaced by computed ones (normals: Blender's, see above).
    const Comparison c = compareWithReference(makeBuiltinMesh("teapot", {kTeapotTessellation}), "teapot");
    expectMatches(c);
    EXPECT_EQ(c.placeholders, 0u);
}

TEST(MikktspaceReference, MirroredUvs) {
    const Comparison c = compareWithReference(loadMesh(kDataDir / "mirrored.obj"), "mirrored");
    expectMatches(c);
    EXPECT_EQ(c.placeholders, 0u);
    // The mirror column's 3 vertices have two tangent groups each (one per uv orientation): loadMesh splits
    // each in two, 21 vertices in the file, 24 loaded; computing again welds and splits them the same way.
    EXPECT_EQ(c.verticesBefore, 24u);
    EXPECT_EQ(c.verticesAfter, 24u);
}

TEST(MikktspaceReference, DegenerateUvs) {
    const Comparison c = compareWithReference(loadMesh(kDataDir / "degenerate.obj"), "degenerate");
    expectMatches(c);
    // The lone triangle with collapsed uvs: no group reaches it, the reference leaves its 3 corners unset.
    EXPECT_EQ(c.placeholders, 3u);
}

TEST(MikktspaceReference, Gltf) {
    const Comparison c = compareWithReference(loadMesh(kDataDir / "cylinder.gltf"), "cylinder");
    expectMatches(c);
    EXPECT_EQ(c.placeholders, 0u);
}

// Every corner its own vertex, straight from the reference (no loader, no repair): computeTangents must weld
// the corners as MikkTSpace does (identical position, normal and uv) to find the same groups, and keep a
// triangle with two corners at one position (collapsed.obj; the loader drops those) out of them.
TEST(MikktspaceReference, RawCorners) {
    for (const std::string name : {"teapot", "mirrored", "degenerate", "cylinder", "collapsed"}) {
        const std::vector<ReferenceCorner> ref = readReference(name);
        Mesh mesh;
        mesh.name = name;
        for (const ReferenceCorner& c : ref) {
            mesh.indices.push_back(static_cast<std::uint32_t>(mesh.vertices.size()));
            mesh.vertices.push_back({c.position, c.normal, c.uv, {}});
        }
        const Comparison c = compareWithReference(mesh, name);
        expectMatches(c);
        // Nothing to split: every corner is a vertex.
        EXPECT_EQ(c.verticesAfter, c.verticesBefore) << name;
        // No tangent in the reference: degenerate's lone collapsed-uv triangle, and collapsed's collapsed
        // triangle (its corners' Blender normals differ from the grid's: no welded good corner to copy).
        EXPECT_EQ(c.placeholders, name == "degenerate" || name == "collapsed" ? 3u : 0u) << name;
        EXPECT_EQ(c.nonUnitNormals, name == "collapsed" ? 1u : 0u) << name;
    }
}

// The reference's copy for a triangle with two corners at one position, which Blender's data cannot show
// (collapsed.obj above): each corner takes the tangent of the first good corner at the same welded vertex.
TEST(MikktspaceReference, CollapsedTriangleCopiesFromItsWeldedVertex) {
    Mesh mesh;
    mesh.name = "quad + collapsed";
    const glm::vec3 n(0, 0, 1);
    // The unit quad (uv = (x, y)), then vertex 4: a copy of vertex 1 (welds with it).
    mesh.vertices = {{{0, 0, 0}, n, {0, 0}, {}},
                     {{1, 0, 0}, n, {1, 0}, {}},
                     {{1, 1, 0}, n, {1, 1}, {}},
                     {{0, 1, 0}, n, {0, 1}, {}},
                     {{1, 0, 0}, n, {1, 0}, {}}};
    mesh.indices = {0, 1, 2, 0, 2, 3, 0, 1, 4};  // the last: corners 1 and 4 at one position
    EXPECT_EQ(computeTangents(mesh), 0u);        // nothing repaired: vertex 4 copies vertex 1's group
    ASSERT_EQ(mesh.vertices.size(), 5u);         // one group per vertex: no split
    for (const MeshVertex& v : mesh.vertices) {
        // A flat quad with uv = (x, y): T = +x, w = +1, computed in double and stored as float.
        EXPECT_LT(glm::length(glm::vec3(v.tangent) - glm::vec3(1, 0, 0)), 1e-6f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

// ---- The inputs (run once; see tests/data/mikktspace/README.md) ----

void writeObj(const Mesh& mesh, const std::filesystem::path& path) {
    std::ofstream out(path);
    out << "# " << path.filename().string()
        << ": written by MikktspaceReference.DISABLED_WriteInputs "
           "(tests/mesh/test_mikktspace_reference.cpp)\n";
    char line[160];
    for (const MeshVertex& v : mesh.vertices) {
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\nvt %.9g %.9g\nvn %.9g %.9g %.9g\n",
                      double(v.position.x), double(v.position.y), double(v.position.z), double(v.uv.x),
                      double(v.uv.y), double(v.normal.x), double(v.normal.y), double(v.normal.z));
        out << line;
    }
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        out << "f";
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t i = mesh.indices[t + k] + 1;
            out << ' ' << i << '/' << i << '/' << i;
        }
        out << '\n';
    }
}

// A grid over a gently curved sheet z = 0.15 (x^2 + xy), x in [x0, x1] (nx cells), y in [0, 1] (ny cells);
// uv(x, y) given; smooth normals of the sheet (analytic).
template <class Uv>
Mesh sheet(int nx, int ny, float x0, float x1, Uv uvOf) {
    Mesh mesh;
    for (int j = 0; j <= ny; ++j) {
        for (int i = 0; i <= nx; ++i) {
            const float x = x0 + (x1 - x0) * float(i) / float(nx), y = float(j) / float(ny);
            MeshVertex v;
            v.position = {x, y, 0.15f * (x * x + x * y)};
            v.normal = glm::normalize(glm::vec3(-0.15f * (2.0f * x + y), -0.15f * x, 1.0f));
            v.uv = uvOf(i, j, x, y);
            mesh.vertices.push_back(v);
        }
    }
    const auto at = [nx](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return mesh;
}

std::string base64(const std::string& bytes) {
    static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t chunk = 0;
        const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
        for (std::size_t k = 0; k < 3; ++k)
            chunk = (chunk << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
        for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kDigits[(chunk >> (18 - 6 * k)) & 63u] : '=';
    }
    return out;
}

// A glTF 2.0 file with one indexed primitive (POSITION, NORMAL, TEXCOORD_0 with v_gltf = 1 - v), embedded.
void writeGltf(const Mesh& mesh, const std::filesystem::path& path) {
    std::string buffer;
    const auto append = [&buffer](const void* data, std::size_t size) {
        buffer.append(static_cast<const char*>(data), size);
    };
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const MeshVertex& v : mesh.vertices) {
        append(&v.position, 12);
        lo = glm::min(lo, v.position);
        hi = glm::max(hi, v.position);
    }
    for (const MeshVertex& v : mesh.vertices) append(&v.normal, 12);
    for (const MeshVertex& v : mesh.vertices) {
        const glm::vec2 uv(v.uv.x, 1.0f - v.uv.y);
        append(&uv, 8);
    }
    append(mesh.indices.data(), mesh.indices.size() * 4);
    const std::size_t n = mesh.vertices.size();
    char json[4096];
    std::snprintf(
        json, sizeof json,
        R"({"asset":{"version":"2.0","generator":"strata MikktspaceReference.DISABLED_WriteInputs"},)"
        R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"name":"cylinder"}],)"
        R"("meshes":[{"name":"cylinder","primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3}]}],)"
        R"("accessors":[{"bufferView":0,"componentType":5126,"count":%zu,"type":"VEC3","min":[%.9g,%.9g,%.9g],"max":[%.9g,%.9g,%.9g]},)"
        R"({"bufferView":1,"componentType":5126,"count":%zu,"type":"VEC3"},)"
        R"({"bufferView":2,"componentType":5126,"count":%zu,"type":"VEC2"},)"
        R"({"bufferView":3,"componentType":5125,"count":%zu,"type":"SCALAR"}],)"
        R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":%zu},{"buffer":0,"byteOffset":%zu,"byteLength":%zu},)"
        R"({"buffer":0,"byteOffset":%zu,"byteLength":%zu},{"buffer":0,"byteOffset":%zu,"byteLength":%zu}],)"
        R"("buffers":[{"byteLength":%zu,"uri":"data:application/octet-stream;base64,)",
        n, double(lo.x), double(lo.y), double(lo.z), double(hi.x), double(hi.y), double(hi.z), n, n,
        mesh.indices.size(), n * 12, n * 12, n * 12, n * 24, n * 8, n * 32, mesh.indices.size() * 4,
        buffer.size());
    std::ofstream out(path);
    out << json << base64(buffer) << "\"}]}\n";
}

TEST(MikktspaceReference, DISABLED_WriteInputs) {
    std::filesystem::create_directories(kDataDir);
    writeObj(makeBuiltinMesh("teapot", {kTeapotTessellation}), kDataDir / "teapot.obj");
    // Mirrored: u = |x| on x in [-1, 1]: the left half's uvs are the right half's mirrored, the x = 0
    // column is shared by both halves (same position, normal and uv).
    writeObj(sheet(6, 2, -1.0f, 1.0f, [](int, int, float x, float y) { return glm::vec2(std::abs(x), y); }),
             kDataDir / "mirrored.obj");
    // Degenerate: a 4 x 4 grid with uv = (x, y) except: the vertex (1, 1) and (2, 1) collapsed onto
    // (1, 1)'s uv (zero-area uv triangles next to good ones), row j = 3 given row 2's v (a collinear strip),
    // and a lone triangle whose three uvs are one point (no good neighbour).
    Mesh degenerate = sheet(4, 4, 0.0f, 1.0f, [](int i, int j, float x, float y) {
        if (j == 1 && i == 2) return glm::vec2(0.25f, 0.25f);
        if (j == 3) return glm::vec2(x, 0.5f);
        return glm::vec2(x, y);
    });
    const auto base = static_cast<std::uint32_t>(degenerate.vertices.size());
    for (const glm::vec3 p : {glm::vec3(2, 0, 0), glm::vec3(3, 0, 0), glm::vec3(2, 1, 0)})
        degenerate.vertices.push_back({p, {0, 0, 1}, {0.5f, 0.5f}, {}});
    degenerate.indices.insert(degenerate.indices.end(), {base, base + 1, base + 2});
    writeObj(degenerate, kDataDir / "degenerate.obj");
    writeGltf(makeBuiltinMesh("cylinder", {2}), kDataDir / "cylinder.gltf");
    // Collapsed: a 3 x 2 grid plus a triangle (a, b, b') with two corners at one position: a and b are
    // grid vertices, b' is at b's position with a's uv (so its uv area is zero). The loader drops such a
    // triangle; MikkTSpace keeps it and would copy tangents from good triangles at the same welded vertex,
    // but Blender's split normals at its corners are not the grid's, so none is found (RawCorners).
    Mesh collapsed = sheet(3, 2, 0.0f, 1.0f, [](int, int, float x, float y) { return glm::vec2(x, y); });
    const std::uint32_t a = 5, b = 6;  // interior vertex (1, 1) and its right neighbour (2, 1)
    MeshVertex bPrime = collapsed.vertices[b];
    bPrime.uv = collapsed.vertices[a].uv;
    collapsed.vertices.push_back(bPrime);
    collapsed.indices.insert(collapsed.indices.end(),
                             {a, b, static_cast<std::uint32_t>(collapsed.vertices.size() - 1)});
    writeObj(collapsed, kDataDir / "collapsed.obj");
}

}  // namespace
}  // namespace strata
