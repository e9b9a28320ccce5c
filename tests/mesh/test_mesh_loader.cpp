// Loading OBJ and glTF files that the tests write, repairs and refusals.
#include "strata/core/error.h"
#include "strata/mesh/mesh_loader.h"
#include "strata/mesh/mesh_repair.h"
#include "strata/mesh/tangent_space.h"

#include "test_support.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <limits>

namespace strata {
namespace {

using test::ScratchDir;
using test::writeBytes;

// Expects loadMesh(path) to throw Error(kind) with a message containing `needle` (and the path).
void expectLoadError(const std::filesystem::path& path, ErrorKind kind, const std::string& needle) {
    try {
        loadMesh(path);
        FAIL() << "no error for " << path;
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        const std::string message = e.what();
        EXPECT_NE(message.find(needle), std::string::npos) << message;
        EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
    }
}

// The unit quad of CONVENTIONS §7 as an OBJ with texture coordinates; optional extra lines.
std::string objQuad(const std::string& extra = "", bool normals = true) {
    std::string s = "# unit quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    if (normals)
        s += "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";
    else
        s += "f 1/1 2/2 3/3 4/4\n";
    return s + extra;
}

void expectVerificationQuadFrame(const Mesh& mesh) {
    for (const MeshVertex& v : mesh.vertices) {
        // uv = (x, y) of the quad; float parsing of "0" and "1" is exact.
        EXPECT_EQ(v.uv, glm::vec2(v.position.x, v.position.y));
        // Smooth normals / tangents of a flat quad, computed in double and stored as float.
        EXPECT_LT(glm::length(v.normal - glm::vec3(0, 0, 1)), 1e-6f);
        EXPECT_LT(glm::length(glm::vec3(v.tangent) - glm::vec3(1, 0, 0)), 1e-6f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(MeshLoader, ObjQuad) {
    ScratchDir dir("mesh-obj");
    writeBytes(dir / "quad.obj", objQuad());
    MeshRepairReport report;
    const Mesh mesh = loadMesh(dir / "quad.obj", {}, report);
    EXPECT_EQ(mesh.name, (dir / "quad.obj").string());
    ASSERT_EQ(mesh.vertices.size(), 4u);
    ASSERT_EQ(mesh.indices.size(), 6u);
    expectVerificationQuadFrame(mesh);
    EXPECT_FALSE(report.normalsComputed);
    EXPECT_TRUE(report.tangentsComputed);
    EXPECT_EQ(report.droppedTriangles(), 0u);
    EXPECT_EQ(report.tangentsRepaired, 0u);
    // Counter-clockwise about +z as the file has it.
    const glm::vec3 face =
        glm::cross(mesh.vertices[mesh.indices[1]].position - mesh.vertices[mesh.indices[0]].position,
                   mesh.vertices[mesh.indices[2]].position - mesh.vertices[mesh.indices[0]].position);
    EXPECT_GT(face.z, 0.0f);
}

TEST(MeshLoader, ObjWithoutNormalsGetsSmoothNormalsAndUnweldsSeams) {
    ScratchDir dir("mesh-obj-seam");
    // Two quads sharing the edge x = 1 in position but not in uv (a seam), in the plane z = 0 and a second
    // one folded up by 90 degrees about that edge: unwelded vertices, but one smooth normal per position.
    writeBytes(dir / "fold.obj",
               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 1\nv 1 1 1\n"
               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0\nvt 0.5 1\n"
               "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 2/5 5/2 6/3\nf 2/5 6/3 3/6\n");
    MeshRepairReport report;
    const Mesh mesh = loadMesh(dir / "fold.obj", {}, report);
    EXPECT_TRUE(report.normalsComputed);
    EXPECT_EQ(mesh.vertices.size(), 8u);  // positions 2 and 3 appear with two uvs each
    for (const MeshVertex& v : mesh.vertices) {
        // The sum of cross(p1 - p0, p2 - p0) over the triangles around each position: (1, 0, 0) touches one
        // triangle of the floor and both of the wall, (1, 1, 0) both of the floor and one of the wall.
        // 1e-6: float.
        glm::vec3 expected = v.position.z == 0.0f ? glm::vec3(0, 0, 1) : glm::vec3(-1, 0, 0);
        if (v.position == glm::vec3(1, 0, 0)) expected = glm::normalize(glm::vec3(-2, 0, 1));
        if (v.position == glm::vec3(1, 1, 0)) expected = glm::normalize(glm::vec3(-1, 0, 2));
        EXPECT_LT(glm::length(v.normal - expected), 1e-6f)
            << v.position.x << " " << v.position.y << " " << v.position.z;
    }
}

TEST(MeshLoader, DegenerateTrianglesAreDropped) {
    ScratchDir dir("mesh-degenerate");
    // The quad plus a collinear triangle (zero area) and one that repeats an index.
    writeBytes(dir / "degenerate.obj", objQuad("v 2 0 0\nf 1/1/1 2/2/1 5/1/1\nf 1/1/1 1/1/1 3/3/1\n"));
    MeshRepairReport report;
    const Mesh mesh = loadMesh(dir / "degenerate.obj", {}, report);
    EXPECT_EQ(report.zeroAreaTriangles, 1u);
    EXPECT_EQ(report.repeatedIndexTriangles, 1u);
    EXPECT_EQ(report.removedVertices, 1u);  // the vertex only the collinear triangle used
    EXPECT_EQ(mesh.indices.size(), 6u);
    EXPECT_EQ(mesh.vertices.size(), 4u);
    expectVerificationQuadFrame(mesh);
}

TEST(MeshLoader, RefusesBadFiles) {
    ScratchDir dir("mesh-errors");
    expectLoadError(dir / "missing.obj", ErrorKind::Io, "no such file");
    expectLoadError(dir / "missing.glb", ErrorKind::Io, "no such file");
    writeBytes(dir / "quad.ply", "ply\n");
    expectLoadError(dir / "quad.ply", ErrorKind::Unsupported, ".ply");

    writeBytes(dir / "nouv.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
    expectLoadError(dir / "nouv.obj", ErrorKind::InvalidInput,
                    "has no texture coordinates; relief mapping needs them");

    writeBytes(dir / "flatuv.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0.5 0.5\nf 1/1 2/1 3/1\n");
    expectLoadError(dir / "flatuv.obj", ErrorKind::InvalidInput, "degenerate");

    writeBytes(dir / "empty.obj", "# nothing here\n");
    expectLoadError(dir / "empty.obj", ErrorKind::InvalidInput, "empty");

    writeBytes(dir / "line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n");
    expectLoadError(dir / "line.obj", ErrorKind::InvalidInput, "degenerate");

    writeBytes(dir / "garbage.glb", std::string("glTF\x02\0\0\0garbage-garbage-garbage", 31));
    expectLoadError(dir / "garbage.glb", ErrorKind::InvalidInput, "cannot parse glTF");
    writeBytes(dir / "garbage.gltf", "{ this is not json");
    expectLoadError(dir / "garbage.gltf", ErrorKind::InvalidInput, "cannot parse glTF");
}

// --- glTF ---------------------------------------------------------------------------------------------

std::string base64(const std::string& bytes) {
    static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const auto b = (static_cast<unsigned>(static_cast<unsigned char>(bytes[i])) << 16) |
                       (static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 1])) << 8) |
                       static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 2]));
        for (int k = 3; k >= 0; --k) out += kAlphabet[(b >> (6 * k)) & 63];
    }
    if (i < bytes.size()) {
        unsigned b = static_cast<unsigned>(static_cast<unsigned char>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) b |= static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 1])) << 8;
        out += kAlphabet[(b >> 18) & 63];
        out += kAlphabet[(b >> 12) & 63];
        out += i + 1 < bytes.size() ? kAlphabet[(b >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

template <typename T>
void append(std::string& buffer, std::initializer_list<T> values) {
    for (T v : values) buffer.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// The unit quad in a glTF with an embedded base64 buffer: positions, glTF uvs (v down: v_gltf = 1 - y),
// indices, optional normals; one node with `nodeTransform` (JSON members) instancing it.
std::string gltfQuad(const std::string& nodeTransform, bool normals, float firstX = 0.0f) {
    std::string buffer;
    append<float>(buffer, {firstX, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});  // 48 bytes
    append<float>(buffer, {0, 1, 1, 1, 1, 0, 0, 0});                   // 32 bytes
    append<std::uint16_t>(buffer, {0, 1, 2, 0, 2, 3});                 // 12 bytes
    if (normals) append<float>(buffer, {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    std::string json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0)" +
                       nodeTransform + R"(}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1)" +
                       std::string(normals ? R"(, "NORMAL": 3)" : "") + R"(}, "indices": 2}]}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
    {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3"}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 48},
    {"buffer": 0, "byteOffset": 48, "byteLength": 32},
    {"buffer": 0, "byteOffset": 80, "byteLength": 12},
    {"buffer": 0, "byteOffset": 92, "byteLength": 48}],
  "buffers": [{"byteLength": )" +
                       std::to_string(buffer.size()) + R"(, "uri": "data:application/octet-stream;base64,)" +
                       base64(buffer) + R"("}]})";
    if (!normals) {
        // Drop the fourth accessor and view (their buffer range does not exist).
        const auto cut = [&](const std::string& from, const std::string& to) {
            json.erase(json.find(from), to.size());
        };
        cut(R"(,
    {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3"})",
            R"(,
    {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3"})");
        cut(R"(,
    {"buffer": 0, "byteOffset": 92, "byteLength": 48})",
            R"(,
    {"buffer": 0, "byteOffset": 92, "byteLength": 48})");
    }
    return json;
}

TEST(MeshLoader, GltfQuadFlipsVAndAppliesTheNodeTransform) {
    ScratchDir dir("mesh-gltf");
    // Rotation by 90 degrees about +z (quaternion x, y, z, w), then scale 2 and a translation.
    const float h = std::sqrt(0.5f);
    writeBytes(dir / "quad.gltf",
               gltfQuad(R"(, "translation": [1, 2, 3], "rotation": [0, 0, )" + std::to_string(h) + ", " +
                            std::to_string(h) + R"(], "scale": [2, 2, 2])",
                        true));
    MeshRepairReport report;
    const Mesh mesh = loadMesh(dir / "quad.gltf", {}, report);
    ASSERT_EQ(mesh.vertices.size(), 4u);
    ASSERT_EQ(mesh.indices.size(), 6u);
    EXPECT_FALSE(report.normalsComputed);
    EXPECT_TRUE(report.tangentsComputed);
    const glm::vec2 quadUv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (std::size_t i = 0; i < 4; ++i) {
        const MeshVertex& v = mesh.vertices[i];
        // The file's v is 1 - y; Strata's is y again (exact: 1 - 1 and 1 - 0).
        EXPECT_EQ(v.uv, quadUv[i]);
        // p' = T + R(90 deg) * 2p: (x, y) -> (-2y, 2x); std::to_string's 6 digits of sqrt(0.5): 1e-5.
        const glm::vec3 expected(1.0f - 2.0f * quadUv[i].y, 2.0f + 2.0f * quadUv[i].x, 3.0f);
        EXPECT_LT(glm::length(v.position - expected), 1e-5f);
        // Normals stay +z, the tangent (+x) turns to +y, B = +y turns to -x.
        EXPECT_LT(glm::length(v.normal - glm::vec3(0, 0, 1)), 1e-5f);
        EXPECT_LT(glm::length(glm::vec3(v.tangent) - glm::vec3(0, 1, 0)), 1e-5f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(MeshLoader, GltfMirroringTransformKeepsTrianglesOutward) {
    ScratchDir dir("mesh-gltf-mirror");
    // Scale (1, -1, 1) mirrors: the winding must be reversed, and the frame is still T = +x, B = -y (v now
    // runs along -y), N = +z, so w = -1.
    writeBytes(dir / "mirror.gltf", gltfQuad(R"(, "scale": [1, -1, 1])", true));
    const Mesh mesh = loadMesh(dir / "mirror.gltf");
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        const glm::vec3 face =
            glm::cross(mesh.vertices[mesh.indices[t + 1]].position - mesh.vertices[mesh.indices[t]].position,
                       mesh.vertices[mesh.indices[t + 2]].position - mesh.vertices[mesh.indices[t]].position);
        EXPECT_GT(glm::dot(face, mesh.vertices[mesh.indices[t]].normal), 0.0f);
    }
    for (const MeshVertex& v : mesh.vertices) {
        EXPECT_LT(glm::length(v.normal - glm::vec3(0, 0, 1)), 1e-6f);  // float, as above
        EXPECT_LT(glm::length(glm::vec3(v.tangent) - glm::vec3(1, 0, 0)), 1e-6f);
        EXPECT_EQ(v.tangent.w, -1.0f);
    }
}

TEST(MeshLoader, GltfWithoutNormalsAndMatrixNode) {
    ScratchDir dir("mesh-gltf-matrix");
    // A column-major matrix: translate by (0, 0, 5).
    writeBytes(dir / "quad.gltf", gltfQuad(R"(, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1])", false));
    MeshRepairReport report;
    const Mesh mesh = loadMesh(dir / "quad.gltf", {}, report);
    EXPECT_TRUE(report.normalsComputed);
    for (const MeshVertex& v : mesh.vertices) EXPECT_EQ(v.position.z, 5.0f);
    expectVerificationQuadFrame(mesh);
}

TEST(MeshLoader, GltfRefusesMissingUvsAndNonFiniteValues) {
    ScratchDir dir("mesh-gltf-bad");
    std::string noUv = gltfQuad("", true);
    noUv.erase(noUv.find(R"(, "TEXCOORD_0": 1)"), std::strlen(R"(, "TEXCOORD_0": 1)"));
    writeBytes(dir / "nouv.gltf", noUv);
    expectLoadError(dir / "nouv.gltf", ErrorKind::InvalidInput,
                    "has no texture coordinates; relief mapping needs them");

    writeBytes(dir / "nan.gltf", gltfQuad("", true, std::numeric_limits<float>::quiet_NaN()));
    expectLoadError(dir / "nan.gltf", ErrorKind::InvalidInput, "non-finite");
}

// Indices that tinygltf leaves unchecked: a buffer view's buffer, an accessor's buffer view, a node's mesh.
// Each was std::out_of_range escaping loadMesh before (fuzz_gltf and fuzz_glb found the first; the inputs are
// in fuzz/corpus/fuzz_gltf and fuzz_glb as crash-*); now Error(InvalidInput) naming the index.
TEST(MeshLoader, GltfRefusesIndicesOfListsThatDoNotHaveThem) {
    ScratchDir dir("mesh-gltf-indices");
    const auto replaced = [](std::string text, const std::string& from, const std::string& to) {
        const auto at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) text.replace(at, from.size(), to);
        return text;
    };
    // No "buffers" list at all (the fuzzer's input: the key renamed), so buffer 0 does not exist.
    writeBytes(dir / "nobuffers.gltf", replaced(gltfQuad("", true), R"("buffers")", R"("byteOff")"));
    expectLoadError(dir / "nobuffers.gltf", ErrorKind::InvalidInput, "buffer 0 does not exist");
    writeBytes(dir / "view.gltf",
               replaced(gltfQuad("", true), R"({"bufferView": 1,)", R"({"bufferView": 9,)"));
    expectLoadError(dir / "view.gltf", ErrorKind::InvalidInput, "buffer view 9 does not exist");
    // tinygltf itself refuses a primitive's index accessor out of range (its message, through loadMesh).
    writeBytes(dir / "indices.gltf", replaced(gltfQuad("", true), R"("indices": 2)", R"("indices": 7)"));
    expectLoadError(dir / "indices.gltf", ErrorKind::InvalidInput, "indices accessor out of bounds");
    writeBytes(dir / "mesh.gltf",
               replaced(gltfQuad("", true), R"("nodes": [{"mesh": 0)", R"("nodes": [{"mesh": 3)"));
    expectLoadError(dir / "mesh.gltf", ErrorKind::InvalidInput, "mesh 3 does not exist");
}

TEST(MeshRepair, RefusesBrokenMeshesAndRepairsTangents) {
    Mesh mesh;
    mesh.name = "test-mesh";
    EXPECT_THROW(repairMesh(mesh), Error);  // empty
    mesh.vertices.resize(3);
    mesh.indices = {0, 1, 5};
    try {
        repairMesh(mesh);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("test-mesh: index 5"), std::string::npos) << e.what();
    }
    // A triangle whose uvs are degenerate but which has a neighbour with good ones: kept, counted, and its
    // own vertex gets a repaired tangent orthogonal to its normal.
    Mesh two;
    two.name = "two";
    two.vertices = {{{0, 0, 0}, {0, 0, 1}, {0, 0}, {}},       {{1, 0, 0}, {0, 0, 1}, {1, 0}, {}},
                    {{0, 1, 0}, {0, 0, 1}, {0, 1}, {}},       {{5, 5, 0}, {0, 0, 1}, {0.5f, 0.5f}, {}},
                    {{6, 5, 0}, {0, 0, 1}, {0.5f, 0.5f}, {}}, {{5, 6, 0}, {0, 0, 1}, {0.5f, 0.5f}, {}}};
    two.indices = {0, 1, 2, 3, 4, 5};
    const MeshRepairReport report = repairMesh(two);
    EXPECT_EQ(report.zeroUvAreaTriangles, 1u);
    EXPECT_EQ(two.indices.size(), 6u);
    for (MeshVertex& v : two.vertices) v.tangent = glm::vec4(0.0f);
    EXPECT_EQ(computeTangents(two), 3u);
    for (const MeshVertex& v : two.vertices) {
        EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-6f);  // unit, float
        EXPECT_NEAR(glm::dot(glm::vec3(v.tangent), v.normal), 0.0f, 1e-6f);
    }
    EXPECT_EQ(two.vertices[0].tangent, glm::vec4(1, 0, 0, 1));
}

}  // namespace
}  // namespace strata
