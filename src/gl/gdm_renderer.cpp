#include "strata/gl/gdm_renderer.h"

#include "render_target.h"

#include "strata/core/error.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gl/gl_error.h"
#include "strata/gl/program.h"
#include "strata/mesh/builtin_meshes.h"

#include <epoxy/gl.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace strata::gl {
namespace {

// What the fragment shader reads of the GDM: the raw values, or the SVD's maps.
struct GdmSource {
    GdmDims dims;
    double height = 0.0;
    int rank = 0;  // 0: raw
    const std::vector<float>* raw = nullptr;
    const std::vector<float>* weights = nullptr;
    const std::vector<float>* eigen = nullptr;
    double tolerance = 0.0;
};

// A buffer object that deletes itself.
struct Buffer {
    GLuint id = 0;
    Buffer() { glCreateBuffers(1, &id); }
    ~Buffer() { glDeleteBuffers(1, &id); }
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    template <class T>
    void store(const std::vector<T>& data) {
        // A zero-size buffer cannot be bound as storage on every driver: keep at least one element.
        const std::size_t bytes = std::max<std::size_t>(data.size() * sizeof(T), 16);
        glNamedBufferStorage(id, GLsizeiptr(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
        if (!data.empty()) glNamedBufferSubData(id, 0, GLsizeiptr(data.size() * sizeof(T)), data.data());
    }
};

struct VertexArray {
    GLuint id = 0;
    VertexArray() { glCreateVertexArrays(1, &id); }
    ~VertexArray() { glDeleteVertexArrays(1, &id); }
    VertexArray(const VertexArray&) = delete;
    VertexArray& operator=(const VertexArray&) = delete;
};

struct Vertex {
    float position[3];
    float texture[3];
    std::uint32_t prism;
};

// What a draw shows: the GDM (uvw, then shadow), or the prism ids of the base faces or of the shell's faces
// (top and fins), for the crack test.
enum class Pass { Gdm, BaseIds, ShellIds };

GdmSceneImages render(const GdmSource& source, const Mesh& mesh, const PrismShellOptions& shellOptions,
                      const Camera& camera, const glm::dvec3& light, int width, int height,
                      GdmDirectionLookup directions, Pass pass = Pass::Gdm) {
    validateCamera(camera);
    if (width < 1 || height < 1 || width > Image::kMaxDimension || height > Image::kMaxDimension)
        throw Error(ErrorKind::InvalidInput, "GDM scene: picture size " + std::to_string(width) + " x " +
                                                 std::to_string(height) + " is outside [1, " +
                                                 std::to_string(Image::kMaxDimension) + "]");
    const double shellHeight = source.height;
    PrismShellOptions options = shellOptions;
    options.height = shellHeight;
    const PrismShell shell = buildPrismShell(mesh, options);

    // The faces a ray can enter a prism through (top and fins), and every prism's 8 triangles for the exit
    // search, each corner with its world position and its texture position in the isotropic frame
    // (tiling * uv, w H).
    std::vector<Vertex> vertices;
    std::vector<glm::vec4> faces;
    vertices.reserve(shell.prisms.size() * 21);
    faces.reserve(shell.prisms.size() * 48);
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (std::size_t p = 0; p < shell.prisms.size(); ++p) {
        const auto triangles = prismTriangleCorners(shell, p);
        for (int f = 0; f < 8; ++f)
            for (const PrismCorner& corner : triangles[f]) {
                const std::uint32_t s = shell.prisms[p][corner.corner];
                const glm::vec3 world = corner.top ? shell.top[s] : shell.base[s];
                const glm::vec2 uv = mesh.vertices[shell.corners[p][corner.corner]].uv;
                const glm::vec3 texture(float(options.tiling.x * double(uv.x)),
                                        float(options.tiling.y * double(uv.y)),
                                        corner.top ? float(shellHeight) : 0.0f);
                faces.emplace_back(world, 0.0f);
                faces.emplace_back(texture, 0.0f);
                lo = glm::min(lo, glm::dvec3(world));
                hi = glm::max(hi, glm::dvec3(world));
                if (pass == Pass::BaseIds ? f == 0 : f >= 1)
                    vertices.push_back(
                        {{world.x, world.y, world.z}, {texture.x, texture.y, texture.z}, std::uint32_t(p)});
            }
    }
    // Near and far planes around the shell's bounds.
    const double radius = 0.5 * glm::length(hi - lo);
    const double distance = glm::length(0.5 * (lo + hi) - camera.eye);
    const double farPlane = distance + 2.0 * radius + 1e-6;
    const double nearPlane = std::max(farPlane * 1e-5, distance - 2.0 * radius);

    const BindingGuard guard;
    RenderTarget target;
    target.ensure(width, height, GL_RGBA32F, "GDM scene");
    const Program program =
        buildProgram(ShaderLibrary::embedded(), "gdm/gdm.vert.glsl", "gdm/gdm.frag.glsl", {}, "GDM scene");

    Buffer vertexBuffer, faceBuffer, weightBuffer, eigenBuffer, rawBuffer;
    vertexBuffer.store(vertices);
    faceBuffer.store(faces);
    const std::vector<float> none;
    weightBuffer.store(source.weights ? *source.weights : none);
    eigenBuffer.store(source.eigen ? *source.eigen : none);
    rawBuffer.store(source.raw ? *source.raw : none);
    VertexArray vao;
    glVertexArrayVertexBuffer(vao.id, 0, vertexBuffer.id, 0, sizeof(Vertex));
    glEnableVertexArrayAttrib(vao.id, 0);
    glEnableVertexArrayAttrib(vao.id, 1);
    glEnableVertexArrayAttrib(vao.id, 2);
    glVertexArrayAttribFormat(vao.id, 0, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, position));
    glVertexArrayAttribFormat(vao.id, 1, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, texture));
    glVertexArrayAttribIFormat(vao.id, 2, 1, GL_UNSIGNED_INT, offsetof(Vertex, prism));
    for (GLuint a = 0; a < 3; ++a) glVertexArrayAttribBinding(vao.id, a, 0);
    checkGl("GDM scene: uploading");

    const glm::dmat4 viewProjection =
        projectionMatrix(camera, double(width) / double(height), nearPlane, farPlane) * viewMatrix(camera);
    const glm::mat4 viewProjectionF(viewProjection);
    const GLuint id = program.id();
    glUseProgram(id);
    glUniformMatrix4fv(program.uniformLocation("uViewProjection"), 1, GL_FALSE,
                       glm::value_ptr(viewProjectionF));
    glUniform3f(program.uniformLocation("uEye"), float(camera.eye.x), float(camera.eye.y),
                float(camera.eye.z));
    glUniform3f(program.uniformLocation("uLight"), float(light.x), float(light.y), float(light.z));
    glUniform3i(program.uniformLocation("uVoxels"), source.dims.nx, source.dims.ny, source.dims.nz);
    glUniform2i(program.uniformLocation("uDirections"), source.dims.ntheta, source.dims.nphi);
    glUniform1f(program.uniformLocation("uHeight"), float(shellHeight));
    glUniform1i(program.uniformLocation("uRank"), source.rank);
    glUniform1f(program.uniformLocation("uTolerance"), float(source.tolerance));
    glUniform1i(program.uniformLocation("uBilinearDirections"), directions == GdmDirectionLookup::Bilinear);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, faceBuffer.id);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, weightBuffer.id);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, eigenBuffer.id);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, rawBuffer.id);
    glBindVertexArray(vao.id);
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (pass != Pass::BaseIds) {  // the shell as the GDM pass draws it: entry faces only
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        glFrontFace(GL_CCW);
    }
    glDisable(GL_BLEND);

    GdmSceneImages images{Image(width, height, 4), Image(width, height, 1), Image(width, height, 1)};
    std::vector<float> pixels(std::size_t(width) * std::size_t(height) * 4);
    const int firstOutput = pass == Pass::Gdm ? 0 : 2, lastOutput = pass == Pass::Gdm ? 1 : 2;
    for (int output = firstOutput; output <= lastOutput; ++output) {
        glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glUniform1i(program.uniformLocation("uOutput"), output);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size()));
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, pixels.data());
        checkGl("GDM scene: drawing");
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                // GL's row 0 is the bottom one; the picture's is the top (CONVENTIONS §7).
                const float* p = pixels.data() + (std::size_t(height - 1 - y) * std::size_t(width) + x) * 4;
                const bool hit = p[3] > 0.5f;
                if (output == 2) {
                    images.mask.at(x, y) = hit ? p[0] : 0.0f;  // the prism id + 1
                } else if (output == 0) {
                    for (int c = 0; c < 4; ++c) images.uvw.at(x, y, c) = hit ? p[c] : 0.0f;
                    images.mask.at(x, y) = hit ? 1.0f : 0.0f;
                } else {
                    images.shadow.at(x, y) = hit && p[0] > 0.5f ? 1.0f : 0.0f;
                }
            }
    }
    glDisable(GL_CULL_FACE);
    glBindVertexArray(0);
    glUseProgram(0);
    return images;
}

}  // namespace

namespace {

GdmSource rawSource(const Gdm& gdm) {
    validateGdmDims(gdm.dims, gdm.height, "GDM scene");
    if (gdm.values.size() != gdm.dims.valueCount())
        throw Error(ErrorKind::InvalidInput, "GDM scene: the GDM holds " + std::to_string(gdm.values.size()) +
                                                 " values, its dims need " +
                                                 std::to_string(gdm.dims.valueCount()));
    GdmSource source;
    source.dims = gdm.dims;
    source.height = gdm.height;
    source.raw = &gdm.values;
    source.tolerance = 1e-4 * gdm.height / gdm.dims.nz;  // emulateGdm's for the raw GDM
    return source;
}

GdmSource svdSource(const GdmSvd& svd) {
    validateGdmDims(svd.dims, svd.height, "GDM scene");
    if (svd.layout != GdmLayout::XyPhiByThetaZ)
        throw Error(ErrorKind::InvalidInput,
                    std::string("GDM scene: the GL renderer reads the paper's layout ") +
                        toString(GdmLayout::XyPhiByThetaZ) + ", not " + toString(svd.layout));
    if (svd.weights.size() != svd.rows * std::size_t(svd.rank) ||
        svd.eigen.size() != std::size_t(svd.rank) * svd.cols)
        throw Error(ErrorKind::InvalidInput, "GDM scene: the SVD's maps do not match its rank and layout");
    GdmSource source;
    source.dims = svd.dims;
    source.height = svd.height;
    source.rank = svd.rank;
    source.weights = &svd.weights;
    source.eigen = &svd.eigen;
    source.tolerance = svd.exitTolerance;
    return source;
}

}  // namespace

GdmSceneImages renderGdmScene(const Gdm& gdm, const Camera& camera, glm::dvec3 light, int width, int height,
                              GdmDirectionLookup directions) {
    return render(rawSource(gdm), makeBuiltinMesh("quad"), {}, camera, light, width, height, directions);
}

GdmSceneImages renderGdmScene(const GdmSvd& svd, const Camera& camera, glm::dvec3 light, int width,
                              int height, GdmDirectionLookup directions) {
    return render(svdSource(svd), makeBuiltinMesh("quad"), {}, camera, light, width, height, directions);
}

GdmSceneImages renderGdmMesh(const Gdm& gdm, const Mesh& mesh, const PrismShellOptions& shell,
                             const Camera& camera, glm::dvec3 light, int width, int height,
                             GdmDirectionLookup directions) {
    return render(rawSource(gdm), mesh, shell, camera, light, width, height, directions);
}

GdmSceneImages renderGdmMesh(const GdmSvd& svd, const Mesh& mesh, const PrismShellOptions& shell,
                             const Camera& camera, glm::dvec3 light, int width, int height,
                             GdmDirectionLookup directions) {
    return render(svdSource(svd), mesh, shell, camera, light, width, height, directions);
}

Image renderPrismIds(const Mesh& mesh, const PrismShellOptions& shell, const Camera& camera, int width,
                     int height, PrismFaces faces) {
    GdmSource source;  // no GDM is read
    source.height = shell.height;
    source.dims = GdmDims{1, 1, 1, 1, 1};
    return render(source, mesh, shell, camera, glm::dvec3(0.0), width, height, GdmDirectionLookup::Nearest,
                  faces == PrismFaces::Base ? Pass::BaseIds : Pass::ShellIds)
        .mask;
}

}  // namespace strata::gl
