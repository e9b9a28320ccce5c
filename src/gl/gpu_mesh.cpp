#include "strata/gl/gpu_mesh.h"

#include "strata/core/error.h"
#include "strata/gl/gl_error.h"

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace strata::gl {

namespace {

// One vertex as the vertex shader reads it (shaders/relief/relief.vert.glsl, locations 0-4).
struct GpuVertex {
    float position[3];
    float normal[3];
    float uv[2];
    float tangent[4];
    float uvLength[2];  // object-space |dP/du|, |dP/dv|
};
static_assert(sizeof(GpuVertex) == 14 * sizeof(float), "GpuVertex must be tightly packed");

}  // namespace

GpuMesh::~GpuMesh() {
    if (mVao != 0) glDeleteVertexArrays(1, &mVao);
    if (mVbo != 0) glDeleteBuffers(1, &mVbo);
    if (mIbo != 0) glDeleteBuffers(1, &mIbo);
}

GpuMesh::GpuMesh(GpuMesh&& other) noexcept
    : mVao(std::exchange(other.mVao, 0)),
      mVbo(std::exchange(other.mVbo, 0)),
      mIbo(std::exchange(other.mIbo, 0)),
      mIndexCount(std::exchange(other.mIndexCount, 0)),
      mBounds(other.mBounds),
      mMaxUvLength(other.mMaxUvLength) {}

GpuMesh& GpuMesh::operator=(GpuMesh&& other) noexcept {
    if (this != &other) {
        GpuMesh old(std::move(*this));
        mVao = std::exchange(other.mVao, 0);
        mVbo = std::exchange(other.mVbo, 0);
        mIbo = std::exchange(other.mIbo, 0);
        mIndexCount = std::exchange(other.mIndexCount, 0);
        mBounds = other.mBounds;
        mMaxUvLength = other.mMaxUvLength;
    }
    return *this;
}

GpuMesh uploadMesh(const Mesh& mesh) {
    const std::string name = "uploadMesh('" + mesh.name + "')";
    if (mesh.vertices.empty() || mesh.indices.empty()) {
        throw Error(ErrorKind::InvalidInput, name + ": the mesh has no triangles");
    }
    if (mesh.indices.size() % 3 != 0) {
        throw Error(ErrorKind::InvalidInput,
                    name + ": " + std::to_string(mesh.indices.size()) + " indices is not a multiple of 3");
    }
    if (mesh.indices.size() > static_cast<std::size_t>(std::numeric_limits<GLsizei>::max())) {
        throw Error(ErrorKind::InvalidInput, name + ": too many indices");
    }
    for (const std::uint32_t index : mesh.indices) {
        if (index >= mesh.vertices.size()) {
            throw Error(ErrorKind::InvalidInput, name + ": index " + std::to_string(index) +
                                                     " out of range (" +
                                                     std::to_string(mesh.vertices.size()) + " vertices)");
        }
    }
    const std::vector<glm::dvec2> lengths = uvLengths(mesh);
    std::vector<GpuVertex> vertices(mesh.vertices.size());
    GpuMesh result;
    result.mMaxUvLength = 0.0;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const MeshVertex& in = mesh.vertices[i];
        GpuVertex& out = vertices[i];
        std::copy_n(glm::value_ptr(in.position), 3, out.position);
        std::copy_n(glm::value_ptr(in.normal), 3, out.normal);
        std::copy_n(glm::value_ptr(in.uv), 2, out.uv);
        std::copy_n(glm::value_ptr(in.tangent), 4, out.tangent);
        out.uvLength[0] = static_cast<float>(lengths[i].x);
        out.uvLength[1] = static_cast<float>(lengths[i].y);
        result.mMaxUvLength = std::max({result.mMaxUvLength, lengths[i].x, lengths[i].y});
    }
    result.mBounds = meshBounds(mesh);
    result.mIndexCount = static_cast<int>(mesh.indices.size());

    glCreateBuffers(1, &result.mVbo);
    glNamedBufferStorage(result.mVbo, static_cast<GLsizeiptr>(vertices.size() * sizeof(GpuVertex)),
                         vertices.data(), 0);
    glCreateBuffers(1, &result.mIbo);
    glNamedBufferStorage(result.mIbo, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
                         mesh.indices.data(), 0);
    glCreateVertexArrays(1, &result.mVao);
    glVertexArrayVertexBuffer(result.mVao, 0, result.mVbo, 0, sizeof(GpuVertex));
    glVertexArrayElementBuffer(result.mVao, result.mIbo);
    const struct {
        GLuint location;
        GLint size;
        std::size_t offset;
    } attributes[] = {{0, 3, offsetof(GpuVertex, position)},
                      {1, 3, offsetof(GpuVertex, normal)},
                      {2, 2, offsetof(GpuVertex, uv)},
                      {3, 4, offsetof(GpuVertex, tangent)},
                      {4, 2, offsetof(GpuVertex, uvLength)}};
    for (const auto& attribute : attributes) {
        glEnableVertexArrayAttrib(result.mVao, attribute.location);
        glVertexArrayAttribFormat(result.mVao, attribute.location, attribute.size, GL_FLOAT, GL_FALSE,
                                  static_cast<GLuint>(attribute.offset));
        glVertexArrayAttribBinding(result.mVao, attribute.location, 0);
    }
    checkGl(name.c_str());
    return result;
}

}  // namespace strata::gl
