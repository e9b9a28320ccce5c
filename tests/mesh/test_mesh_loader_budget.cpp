// OBJ values that are not finite numbers, and mesh sizes against the memory budget (docs/images.md).
#include "strata/core/error.h"
#include "strata/core/memory_budget.h"
#include "strata/mesh/mesh_loader.h"

#include "test_support.h"

#include <gtest/gtest.h>

namespace strata {
namespace {

using test::ScratchDir;
using test::writeBytes;

// Texture coordinates not required, as dual-depth loads: the position accessor is what is tested.
std::string loadError(const std::filesystem::path& path, ErrorKind* kind) {
    try {
        MeshLoadOptions options;
        options.requireUvs = false;
        loadMesh(path, options);
    } catch (const Error& e) {
        *kind = e.kind();
        return e.what();
    }
    return "no error";
}

const std::string kQuadTail = "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";

TEST(ObjFiniteValues, NanInfAndUnparsableValuesAreErrorsWithTheirLine) {
    ScratchDir dir("obj-nan");
    // tinyobjloader reads each of these as 0; line 3, 2, 4, 3 and 6 hold them.
    const struct {
        const char* text;
        const char* message;
    } cases[] = {
        {"# quad\nv 0 0 0\nv nan 0 0\nv 1 1 0\nv 0 1 0\n", "line 3: 'v' value 'nan' is not a finite number"},
        {"v 0 0 0\nv 1 0 inf\nv 1 1 0\nv 0 1 0\n", "line 2: 'v' value 'inf' is not a finite number"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1e999 0\n", "line 4: 'v' value '1e999' is not a finite number"},
        {"v 0 0 0\nv 1 0 0\nv 1 1 zero\nv 0 1 0\n", "line 3: 'v' value 'zero' is not a finite number"},
    };
    for (const auto& c : cases) {
        writeBytes(dir / "bad.obj", std::string(c.text) + kQuadTail);
        ErrorKind kind = ErrorKind::Runtime;
        EXPECT_EQ(loadError(dir / "bad.obj", &kind), (dir / "bad.obj").string() + ": " + c.message);
        EXPECT_EQ(kind, ErrorKind::InvalidInput);
    }
    writeBytes(dir / "vt.obj",
               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt -inf 0\nvt 1 1\nvt 0 1\n"
               "f 1/1 2/2 3/3 4/4\n");
    ErrorKind kind = ErrorKind::Runtime;
    EXPECT_EQ(loadError(dir / "vt.obj", &kind),
              (dir / "vt.obj").string() + ": line 6: 'vt' value '-inf' is not a finite number");
    EXPECT_EQ(kind, ErrorKind::InvalidInput);
    // The same quad with finite values loads.
    writeBytes(dir / "ok.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n" + kQuadTail);
    EXPECT_EQ(loadMesh(dir / "ok.obj").vertices.size(), 4u);
}

class MeshBudget : public ::testing::Test {
protected:
    void TearDown() override { setMemoryBudget(mSaved); }
    std::uint64_t mSaved = memoryBudget();
};

TEST_F(MeshBudget, AnObjOverTheBudgetIsRefusedBeforeParsing) {
    ScratchDir dir("obj-budget");
    writeBytes(dir / "ok.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n" + kQuadTail);
    setMemoryBudget(100);  // bytes: 20 floats (80 bytes) plus 4 face corners do not fit
    ErrorKind kind = ErrorKind::Runtime;
    const std::string message = loadError(dir / "ok.obj", &kind);
    EXPECT_EQ(kind, ErrorKind::Unsupported);
    EXPECT_EQ(
        message.rfind(
            (dir / "ok.obj").string() + ": an OBJ with 20 attribute values and 4 face corners needs ", 0),
        0u)
        << message;
    EXPECT_NE(message.find("more than the memory budget of 100 bytes (--max-memory)"), std::string::npos)
        << message;
}

TEST(GltfPositions, AnAccessorWithoutABufferViewIsRefusedBeforeAllocating) {
    ScratchDir dir("gltf-no-view");
    // All-zero positions by the glTF spec: any count in a few bytes of JSON, and a degenerate mesh.
    writeBytes(dir / "huge.gltf", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0,
 "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "accessors": [{"componentType": 5126, "count": 400000000, "type": "VEC3",
                "min": [0, 0, 0], "max": [0, 0, 0]}]})");
    ErrorKind kind = ErrorKind::Runtime;
    EXPECT_EQ(
        loadError(dir / "huge.gltf", &kind),
        (dir / "huge.gltf").string() +
            ": POSITION accessor 0 of 400000000 elements has no buffer view (every position would be 0)");
    EXPECT_EQ(kind, ErrorKind::InvalidInput);
}

TEST_F(MeshBudget, AGltfAccessorWithAHugeCountIsRefusedBeforeAllocating) {
    ScratchDir dir("gltf-budget");
    // 400 M positions declared over a 12-byte buffer: the budget refuses before the bounds check.
    writeBytes(dir / "huge.gltf", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0,
 "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "buffers": [{"byteLength": 12, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}],
 "bufferViews": [{"buffer": 0, "byteLength": 12}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 400000000, "type": "VEC3",
                "min": [0, 0, 0], "max": [0, 0, 0]}]})");
    setMemoryBudget(std::uint64_t{1} << 30);
    ErrorKind kind = ErrorKind::Runtime;
    const std::string message = loadError(dir / "huge.gltf", &kind);
    EXPECT_EQ(kind, ErrorKind::Unsupported);
    EXPECT_EQ(
        message.rfind((dir / "huge.gltf").string() + ": POSITION accessor 0 of 400000000 elements needs ", 0),
        0u)
        << message;
    EXPECT_NE(message.find("more than the memory budget of 1.00 GiB (--max-memory)"), std::string::npos)
        << message;
}

TEST(GltfAccessorBounds, AHugeCountWithABufferViewDoesNotWrapIntoRange) {
    ScratchDir dir("gltf-wrap");
    // 2^62 elements of 12 bytes: stride * (count - 1) wraps around 2^64 without saturation.
    writeBytes(dir / "wrap.gltf", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0,
 "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "buffers": [{"byteLength": 12, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}],
 "bufferViews": [{"buffer": 0, "byteLength": 12}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4611686018427387904, "type": "VEC3",
                "min": [0, 0, 0], "max": [0, 0, 0]}]})");
    ErrorKind kind = ErrorKind::Runtime;
    const std::string message = loadError(dir / "wrap.gltf", &kind);
    // Refused by the budget (2^62 elements need more than any machine has) before the bounds check.
    EXPECT_EQ(kind, ErrorKind::Unsupported) << message;
    EXPECT_NE(message.find("POSITION accessor 0 of 4611686018427387904 elements needs "), std::string::npos)
        << message;
}

}  // namespace
}  // namespace strata
