// Loading OFF files (mesh_loader.h) and meshes without texture coordinates (MeshLoadOptions::requireUvs).
#include "strata/core/error.h"
#include "strata/mesh/mesh_loader.h"

#include "test_support.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cstdlib>
#include <string>

namespace strata {
namespace {

using test::ScratchDir;
using test::writeBytes;

MeshLoadOptions withoutUvs() {
    MeshLoadOptions options;
    options.requireUvs = false;
    return options;
}

void expectLoadError(const std::filesystem::path& path, const MeshLoadOptions& options, ErrorKind kind,
                     const std::string& needle) {
    try {
        loadMesh(path, options);
        ADD_FAILURE() << "no error for " << path;
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        const std::string message = e.what();
        EXPECT_NE(message.find(needle), std::string::npos) << message;
        EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    }
}

// A unit square pyramid: four triangles and a quad base (two triangles as a fan), counter-clockwise from
// outside, with comments, blank lines and a trailing colour on one face.
constexpr const char* kPyramid = R"(OFF
# a square pyramid
5 5 8

0 0 0
1 0 0
1 1 0   # comment after a vertex
0 1 0
0.5 0.5 1
3 0 1 4
3 1 2 4
3 2 3 4 255 0 0
3 3 0 4
4 0 3 2 1
)";

TEST(OffLoader, ReadsAPyramidWithPlanarUvsAndSmoothNormals) {
    ScratchDir dir("off");
    writeBytes(dir / "pyramid.off", kPyramid);
    MeshRepairReport report;
    const Mesh mesh = loadMesh(dir / "pyramid.off", withoutUvs(), report);
    // 5 points; the planar uvs (u = y, v = z) wrap the -x face the other way round from the +x face, so
    // the apex is in two MikkTSpace tangent groups of opposite handedness and computeTangents splits it.
    EXPECT_EQ(mesh.vertices.size(), 6u);
    EXPECT_EQ(mesh.indices.size(), 6u * 3u);  // 4 sides + the quad as a fan of 2
    EXPECT_TRUE(report.normalsComputed);
    EXPECT_EQ(mesh.vertices[4].position, glm::vec3(0.5f, 0.5f, 1.0f));
    for (const MeshVertex& v : mesh.vertices) {
        EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-5f);
        // Planar uvs: the bounds are 1 x 1 x 1, so the smallest extent is x (the first of equals)... any
        // pair of axes scaled by the larger extent lands in [0, 1].
        EXPECT_GE(v.uv.x, 0.0f);
        EXPECT_LE(v.uv.x, 1.0f);
        EXPECT_GE(v.uv.y, 0.0f);
        EXPECT_LE(v.uv.y, 1.0f);
    }
    // The apex's smooth normal points up; the base corners' have a downward part.
    EXPECT_GT(mesh.vertices[4].normal.z, 0.99f);
    EXPECT_LT(mesh.vertices[0].normal.z, 0.0f);
}

TEST(OffLoader, CountsMayShareTheHeaderLine) {
    ScratchDir dir("off-header");
    writeBytes(dir / "t.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    const Mesh mesh = loadMesh(dir / "t.off", withoutUvs());
    EXPECT_EQ(mesh.indices.size(), 3u);
}

TEST(OffLoader, Refusals) {
    ScratchDir dir("off-bad");
    writeBytes(dir / "pyramid.off", kPyramid);
    // Relief mapping needs uvs; OFF has none.
    expectLoadError(dir / "pyramid.off", {}, ErrorKind::InvalidInput, "has no texture coordinates");
    writeBytes(dir / "range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    expectLoadError(dir / "range.off", withoutUvs(), ErrorKind::InvalidInput, "index out of range (3)");
    writeBytes(dir / "short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n");
    expectLoadError(dir / "short.off", withoutUvs(), ErrorKind::InvalidInput, "the counts say 4 vertices");
    writeBytes(dir / "face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n");
    expectLoadError(dir / "face.off", withoutUvs(), ErrorKind::InvalidInput, "fewer than 3 indices");
    writeBytes(dir / "vertex.off", "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n");
    expectLoadError(dir / "vertex.off", withoutUvs(), ErrorKind::InvalidInput, "line 4");
    writeBytes(dir / "nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
    // Stream extraction reads no "nan": a malformed vertex line, never a NaN position.
    expectLoadError(dir / "nan.off", withoutUvs(), ErrorKind::InvalidInput, "line 4");
    writeBytes(dir / "colour.off", "COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n0 1 0 1 0 0 1\n3 0 1 2\n");
    expectLoadError(dir / "colour.off", withoutUvs(), ErrorKind::Unsupported, "COFF");
    writeBytes(dir / "ply.off", "ply\nformat ascii 1.0\n");
    expectLoadError(dir / "ply.off", withoutUvs(), ErrorKind::InvalidInput, "not \"OFF\"");
    writeBytes(dir / "empty.off", "");
    expectLoadError(dir / "empty.off", withoutUvs(), ErrorKind::InvalidInput, "empty");
}

TEST(OffLoader, ObjWithoutUvsLoadsWhenAllowed) {
    ScratchDir dir("obj-nouv");
    writeBytes(dir / "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
    expectLoadError(dir / "t.obj", {}, ErrorKind::InvalidInput, "has no texture coordinates");
    const Mesh mesh = loadMesh(dir / "t.obj", withoutUvs());
    EXPECT_EQ(mesh.indices.size(), 12u);
}

// The Stanford bunny that Debian ships (libcgal-demo, inside /usr/share/doc/libcgal-dev/data.tar.gz):
// extracted here when both the archive and tar are present; skipped otherwise.
TEST(OffLoader, ReadsTheStanfordBunnyIfInstalled) {
    const std::filesystem::path archive = "/usr/share/doc/libcgal-dev/data.tar.gz";
    if (!std::filesystem::exists(archive))
        GTEST_SKIP() << archive << " missing (apt-get install libcgal-demo)";
    ScratchDir dir("bunny");
    const std::string command =
        "tar -xzf " + archive.string() + " -C '" + dir.path().string() + "' data/meshes/bunny00.off";
    if (std::system(command.c_str()) != 0) GTEST_SKIP() << "cannot extract bunny00.off";
    MeshRepairReport report;
    const Mesh bunny = loadMesh(dir / "data/meshes/bunny00.off", withoutUvs(), report);
    // The file's header: 37706 vertices, 75408 triangles; whatever the repairs drop is counted.
    EXPECT_EQ(bunny.indices.size() / 3 + report.droppedTriangles(), 75408u);
    EXPECT_EQ(bunny.vertices.size() + report.removedVertices, 37706u);
}

}  // namespace
}  // namespace strata
