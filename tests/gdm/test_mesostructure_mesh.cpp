// Meshing a mesostructure (closed, counter-clockwise from outside, the tile's share of the periodic solid),
// and solid meshes read from OBJ and VDB files: the round trip and every documented refusal.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/gdm/mesostructure_mesh.h"
#include "strata/gdm/solid_mesh_io.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <string>

namespace strata {
namespace {

// Volume enclosed by a closed mesh (divergence theorem): positive when its triangles are counter-clockwise
// seen from outside.
double signedVolume(const SolidMesh& mesh) {
    double volume = 0.0;
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
        volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return volume;
}

Mesostructure sphereAt(const glm::dvec3& centre, double radius, double height) {
    MesostructurePart part;
    part.name = "sphere";
    part.distance = [=](const glm::dvec3& p) {
        // The nearest copy in u and v: exact for a ball smaller than half a tile.
        glm::dvec3 q = p - centre;
        q.x -= std::floor(q.x + 0.5);
        q.y -= std::floor(q.y + 0.5);
        return glm::length(q) - radius;
    };
    part.albedo = [](const glm::dvec3&) { return glm::dvec3(0.5); };
    return Mesostructure("sphere", height, height, {part});
}

std::string errorOf(const std::function<void()>& call, ErrorKind kind = ErrorKind::InvalidInput) {
    try {
        call();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error";
    return "";
}

TEST(MesostructureMesh, SlabIsClosedOrientedAndExact) {
    MesostructurePart slab;
    slab.name = "slab";
    slab.distance = [](const glm::dvec3& p) { return std::abs(p.z - 0.1) - 0.05; };
    slab.albedo = [](const glm::dvec3&) { return glm::dvec3(0.5); };
    const SolidMesh mesh = meshMesostructure(Mesostructure("slab", 0.25, 0.25, {slab}), 64);
    EXPECT_NO_THROW(validateSolidMesh(mesh, "slab"));
    EXPECT_EQ(mesh.height, 0.25);
    // The slab cut by the tile is the box [0, 1]^2 x [0.05, 0.15]. Its faces are planes, which the linear
    // interpolation of the samples reproduces exactly, but each of the 8 edges where a cut face meets the
    // slab's top or bottom is chamfered (one vertex per cell, at the mean of its crossings) by at most a
    // right triangle of legs dx: 8 dx^2 / 2 = 4 dx^2 lost at most.
    const double dx = 1.0 / 64;
    EXPECT_LT(signedVolume(mesh), 0.1 + 1e-6);  // float positions: ~1e-7
    EXPECT_GT(signedVolume(mesh), 0.1 - 4.0 * dx * dx);
}

TEST(MesostructureMesh, SphereAcrossTheCornerWrapsIntoFourClosedPieces) {
    // A ball of radius 0.1 centred on the tile's corner (0, 0): the tile holds a quarter of it at each of
    // its four corners, which together make the whole ball.
    const SolidMesh mesh = meshMesostructure(sphereAt({0.0, 0.0, 0.125}, 0.1, 0.25), 128);
    EXPECT_NO_THROW(validateSolidMesh(mesh, "sphere"));
    const double ball = 4.0 / 3.0 * std::numbers::pi * 0.001;
    // At 128 voxels per tile the radius is 12.8 voxels. Each vertex is the mean of its cell's crossings,
    // which lies inside a convex surface, so the mesh is a little smaller (about dx / (2 r) = 4% in area
    // terms at worst, far less on average), plus the chamfered rims of the four cut faces: 2% bounds both.
    EXPECT_LT(signedVolume(mesh), ball);
    EXPECT_GT(signedVolume(mesh), 0.98 * ball);
    int corners[4] = {0, 0, 0, 0};
    for (const glm::vec3& p : mesh.positions) {
        EXPECT_TRUE(p.x >= 0.0f && p.x <= 1.0f && p.y >= 0.0f && p.y <= 1.0f) << p.x << ", " << p.y;
        corners[(p.x > 0.5f ? 1 : 0) + (p.y > 0.5f ? 2 : 0)]++;
    }
    for (int c = 0; c < 4; ++c) EXPECT_GT(corners[c], 0) << "corner " << c;
}

TEST(MesostructureMesh, EveryBuiltInMeshesClosedWithItsVolume) {
    for (const auto& info : mesostructureList()) {
        SCOPED_TRACE(info.name);
        const Mesostructure meso = makeMesostructure(info.name);
        const SolidMesh coarse = meshMesostructure(meso, 64);
        EXPECT_EQ(coarse.source, info.name);
        EXPECT_NO_THROW(validateSolidMesh(coarse, info.name));
        const SolidMesh mesh = meshMesostructure(meso, 128);
        EXPECT_NO_THROW(validateSolidMesh(mesh, info.name));
        // Reference: the share of 128^2 x (128 H) cell centres inside. The mesh's vertices (means of
        // crossings) sit inside convex parts, which shrinks thin ones: the chain's links (r = 0.03, 3.8
        // voxels) and the scales (0.024 thick) lose up to ~6%. 8% still catches a missing or inside-out part
        // (tens of percent, or a negative volume).
        const int nz = static_cast<int>(std::ceil(128 * meso.height()));
        double inside = 0.0;
        for (int k = 0; k < nz; ++k)
            for (int j = 0; j < 128; ++j)
                for (int i = 0; i < 128; ++i)
                    inside +=
                        meso.distance({(i + 0.5) / 128, (j + 0.5) / 128, (k + 0.5) / 128}) < 0.0 ? 1 : 0;
        const double reference = inside / (128.0 * 128.0 * 128.0);
        EXPECT_NEAR(signedVolume(mesh), reference, 0.08 * reference);
    }
}

TEST(MesostructureMesh, CutFacesMatchAcrossTheSeams) {
    // The grid's lower rods (radius 0.055) cross the sides u = 0 and u = 1, the upper ones v = 0 and v = 1:
    // each side holds two circular sections, 2 pi r^2 in all, and a side's cut face must be its opposite's
    // translate (the same samples, by periodicity), so that the tiles' union has no step at the seam.
    const SolidMesh mesh = meshMesostructure(makeMesostructure("grid"), 128);
    double area[2][2] = {{0.0, 0.0}, {0.0, 0.0}};  // [axis][side]
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
        const double triangleArea = 0.5 * glm::length(glm::cross(b - a, c - a));
        for (int axis = 0; axis < 2; ++axis)
            for (int side = 0; side < 2; ++side)
                if (a[axis] == side && b[axis] == side && c[axis] == side) area[axis][side] += triangleArea;
    }
    const double sections = 2.0 * std::numbers::pi * 0.055 * 0.055;
    for (int axis = 0; axis < 2; ++axis) {
        // The same up to float rounding of the positions (1e-9 of an area of 0.02).
        EXPECT_NEAR(area[axis][0], area[axis][1], 1e-9) << "axis " << axis;
        // The rims of the cut faces lie about 0.3 voxel inside the true sections (each rim vertex is the
        // mean of its cell's crossings, docs/gdm.md): 92% of the area at 128 voxels per tile; 85% bounds it.
        EXPECT_LT(area[axis][0], sections);
        EXPECT_GT(area[axis][0], 0.85 * sections);
    }
}

TEST(MesostructureMesh, RefusesResolutionsOutOfRange) {
    const Mesostructure weave = makeMesostructure("weave");
    EXPECT_NE(errorOf([&] { meshMesostructure(weave, 3); }).find("got 3"), std::string::npos);
    EXPECT_NE(errorOf([&] { meshMesostructure(weave, 5000); }).find("got 5000"), std::string::npos);
}

TEST(SolidObj, RoundTripsExactly) {
    test::ScratchDir dir("solid-obj");
    const SolidMesh mesh = meshMesostructure(makeMesostructure("grid"), 16);
    writeSolidObj(dir / "grid.obj", mesh);
    const SolidMesh back = readSolidObj(dir / "grid.obj", mesh.height);
    EXPECT_EQ(back.height, mesh.height);
    EXPECT_EQ(back.source, "grid.obj");
    EXPECT_EQ(back.positions, mesh.positions);  // %.9g round-trips every float
    EXPECT_EQ(back.triangles, mesh.triangles);
}

// A closed tetrahedron in the tile, counter-clockwise from outside.
const char* kTetrahedron =
    "v 0.1 0.1 0.01\nv 0.9 0.1 0.01\nv 0.5 0.9 0.01\nv 0.5 0.4 0.2\n"
    "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";

std::string objError(const std::string& text, const std::string& expect) {
    test::ScratchDir dir("solid-obj-bad");
    test::writeBytes(dir / "bad.obj", text);
    const std::string message = errorOf([&] { readSolidObj(dir / "bad.obj", 0.25); });
    EXPECT_NE(message.find((dir / "bad.obj").string()), std::string::npos) << message;
    EXPECT_NE(message.find(expect), std::string::npos) << message;
    return message;
}

TEST(SolidObj, ReadsATetrahedronWithPositiveVolume) {
    test::ScratchDir dir("solid-obj-tet");
    test::writeBytes(dir / "tet.obj", std::string("# a comment\nvn 0 0 1\n") + kTetrahedron);
    const SolidMesh mesh = readSolidObj(dir / "tet.obj", 0.25);
    EXPECT_EQ(mesh.triangles.size(), 4u);
    // Base triangle area 0.5 * 0.8 * 0.8 = 0.32, apex 0.19 above it: 0.32 * 0.19 / 3 (float inputs: 1e-7).
    EXPECT_NEAR(signedVolume(mesh), 0.32 * 0.19 / 3.0, 1e-7);
}

TEST(SolidObj, RefusesEachBadMeshNamingFileAndElement) {
    objError("# nothing\n", "empty");
    objError("v 0.1 0.1 0.1\nv 0.5 0.1 0.1\nv 0.1 0.5 0.1\nf 1 2 3\n", "open: edge 1-2 of triangle 1");
    objError(std::string(kTetrahedron) + "v 0.5 0.1 0.2\nf 1 2 5\n", "non-manifold: edge 1-2");
    objError(
        "v 0.1 0.1 0.01\nv 0.9 0.1 0.01\nv 0.5 0.9 0.01\nv 0.5 0.4 0.2\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 3 4\n",
        "inconsistently oriented");
    objError(
        "v 0.1 0.1 0.01\nv 0.9 0.1 0.01\nv 0.5 0.9 0.01\nv 0.5 0.4 nan\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
        "vertex 4 is not finite");
    // CONVENTIONS §8 wraps and clips what lies outside the tile box
    // (SolidObj.AcceptsGeometryThatWrapsOrIsClipped), up to one tile width out.
    objError(
        "v 0.1 0.1 0.01\nv 3 0.1 0.01\nv 0.5 0.9 0.01\nv 0.5 0.4 0.2\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
        "vertex 2 (3, 0.1, 0.01) lies more than 1 tile width outside the tile [0, 1] x [0, 1] x [0, 0.25] in "
        "x "
        "(x must be in [-1, 2]");
    objError(
        "v 0.1 0.1 0.01\nv 0.9 -1.5 0.01\nv 0.5 0.9 0.01\nv 0.5 0.4 0.2\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 "
        "4\n",
        "vertex 2 (0.9, -1.5, 0.01) lies more than 1 tile width outside the tile [0, 1] x [0, 1] x [0, 0.25] "
        "in y");
    objError(
        "v 0.1 0.1 0.01\nv 0.9 0.1 0.01\nv 0.5 0.9 0.01\nv 0.5 0.4 1.5\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
        "vertex 4 (0.5, 0.4, 1.5) lies more than 1 tile width outside the tile [0, 1] x [0, 1] x [0, 0.25] "
        "in z "
        "(z must be in [-1, 1.25]");
    // Entirely above the shell, or entirely in the neighbouring tile.
    objError(
        "v 0.1 0.1 0.3\nv 0.9 0.1 0.3\nv 0.5 0.9 0.3\nv 0.5 0.4 0.5\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
        "the mesh lies entirely outside the tile [0, 1] x [0, 1] x [0, 0.25] (its bounding box (0.1, 0.1, "
        "0.3) - "
        "(0.9, 0.9, 0.5) does not meet it)");
    objError(
        "v 1.1 0.1 0.01\nv 1.9 0.1 0.01\nv 1.5 0.9 0.01\nv 1.5 0.4 0.2\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
        "the mesh lies entirely outside the tile");
    objError("v 0.1 0.1\n", ":1: a vertex needs x y z");
    objError("v 0.1 0.1 0.1\nv 0.2 0.1 0.1\nv 0.1 0.2 0.1\nf 1 2 7\n", ":4: vertex index 7 out of range");
    objError("v 0.1 0.1 0.1\nv 0.2 0.1 0.1\nv 0.1 0.2 0.1\nf 1 1 2\n", "triangle 1 is degenerate");
}

TEST(SolidObj, AcceptsGeometryThatWrapsOrIsClipped) {
    // CONVENTIONS §8: the tetrahedron crossing x = 0 and y = 1 (it wraps), with its apex above H and its
    // base below 0 (clipped away), one tile width out at most.
    test::ScratchDir dir("solid-obj-wrap");
    test::writeBytes(dir / "tet.obj",
                     "v -0.3 0.1 -0.05\nv 0.5 0.1 -0.05\nv 0.1 1.9 -0.05\nv 0.1 0.4 1.25\n"
                     "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
    const SolidMesh mesh = readSolidObj(dir / "tet.obj", 0.25);
    EXPECT_EQ(mesh.triangles.size(), 4u);
    EXPECT_GT(signedVolume(mesh), 0.0);
    // Exactly at the bounds, and a mesh that only touches the tile box at a corner.
    test::writeBytes(dir / "edge.obj",
                     "v -1 -1 -1\nv 0 -1 -1\nv -1 0 -1\nv -1 -1 0\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
    EXPECT_NO_THROW(readSolidObj(dir / "edge.obj", 0.25));
}

TEST(SolidObj, MissingFileIsAnIoError) {
    test::ScratchDir dir("solid-obj-missing");
    errorOf([&] { readSolidObj(dir / "none.obj", 0.25); }, ErrorKind::Io);
}

TEST(SolidVdb, ReadsALevelSetAndRefusesOtherGrids) {
    openvdb::initialize();
    test::ScratchDir dir("solid-vdb");
    // A sphere of radius 0.1 at (0.5, 0.5, 0.125), voxel 1/128, as OpenVDB's own tool builds it.
    openvdb::FloatGrid::Ptr sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        0.1f, openvdb::Vec3f(0.5f, 0.5f, 0.125f), 1.0f / 128);
    sphere->setName("ball");
    openvdb::io::File(dir / "ball.vdb").write({sphere});
    const SolidMesh mesh = readSolidVdb(dir / "ball.vdb", 0.25);
    EXPECT_NO_THROW(validateSolidMesh(mesh, "ball"));
    const double ball = 4.0 / 3.0 * std::numbers::pi * 0.001;
    EXPECT_NEAR(signedVolume(mesh), ball,
                0.01 * ball);  // as for the wrapped sphere above: < 1% at 12.8 voxels

    openvdb::FloatGrid::Ptr fog = openvdb::FloatGrid::create(0.0f);
    fog->setGridClass(openvdb::GRID_FOG_VOLUME);
    fog->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    openvdb::io::File(dir / "fog.vdb").write({fog});
    const std::string noLevelSet = errorOf([&] { readSolidVdb(dir / "fog.vdb", 0.25); });
    EXPECT_NE(noLevelSet.find("fog.vdb: holds no level-set FloatGrid"), std::string::npos) << noLevelSet;

    test::writeBytes(dir / "junk.vdb", "not a vdb");
    EXPECT_NE(errorOf([&] { readSolidVdb(dir / "junk.vdb", 0.25); }).find("junk.vdb"), std::string::npos);
    // The ball pokes out of a shell of H = 0.1 (z in [0.025, 0.225]): accepted, the bake clips it (§8). Under
    // H = 0.01 it lies entirely above the shell: refused.
    EXPECT_EQ(readSolidVdb(dir / "ball.vdb", 0.1).triangles.size(), mesh.triangles.size());
    const std::string above = errorOf([&] { readSolidVdb(dir / "ball.vdb", 0.01); });
    EXPECT_NE(above.find("ball.vdb (grid \"ball\"): the mesh lies entirely outside the tile"),
              std::string::npos)
        << above;
}

}  // namespace
}  // namespace strata
