#include "strata/gl/gdm_renderer.h"

#include "render_target.h"

#include "strata/core/error.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gl/gl_error.h"
#include "strata/gl/program.h"
#include "strata/image/srgb.h"
#include "strata/mesh/builtin_meshes.h"

#include <epoxy/gl.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace strata::gl {
namespace {

// A buffer object that deletes itself.
struct Buffer {
    GLuint id = 0;
    std::size_t bytes = 0;  // of the store
    Buffer() { glCreateBuffers(1, &id); }
    ~Buffer() { glDeleteBuffers(1, &id); }
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    // Replaces the contents (a new store each time: the sizes change with the GDM or the mesh).
    template <class T>
    void store(const std::vector<T>& data) {
        glDeleteBuffers(1, &id);
        glCreateBuffers(1, &id);
        // A zero-size buffer cannot be bound as storage on every driver: keep at least one element.
        bytes = std::max<std::size_t>(data.size() * sizeof(T), 16);
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
    float tangent[3];  // the mesh's frame at the corner, for shading
    float bitangent[3];
    float normal[3];
};

}  // namespace

struct GdmRenderer::Impl {
    Program program;
    RenderTarget target;
    // The GDM: dims, H, rank (0: raw), the exit rule's tolerance, and its buffers.
    std::optional<GdmDims> dims;
    double shellHeight = 0.0;  // H
    int rank = 0;
    double tolerance = 0.0;
    Buffer weights, eigen, raw;
    Buffer occupancy, albedo;  // for shading: float per voxel, linear RGB per voxel
    bool hasOccupancy = false, hasAlbedo = false;
    Buffer signedDistance;  // per voxel, for refine and the normals
    bool hasDistance = false;
    glm::ivec3 distanceVoxels{1};
    GdmLightFrame lightFrame = GdmLightFrame::Tangent;
    Lighting lighting;  // colour, ambient, specular and shininess of the shaded picture
    // The mesh's shell: entry faces (tops and fins) and base faces to draw, every prism's 8 triangles for
    // the exit search, and the shell's bounds.
    bool hasMesh = false;
    Buffer entryVertices, baseVertices, faces;
    Buffer lightFrames;  // per prism, the rows of J^-1 (gdmPrismJacobian) as 3 vec4
    // Environment lighting (setRtv, setMacroTransfer, setEnvironment). One buffer each, so that the fragment
    // stage stays within 10 storage blocks:
    //   rtv: the basis (rank x 48), then the weights (voxels x rank), then the inside flags (1 inside, per
    //        voxel): the GLSL reads them at uRtvWeightsAt and uRtvInsideAt;
    //   environment: per prism its 3 corners (tile u, v, mesh vertex index, 0), then per mesh vertex its
    //        meso-scale lighting (16 coefficients x RGB), at uLightingAt.
    Buffer rtv, environment;
    int rtvRank = 0;  // 0: none
    std::size_t rtvWeightsAt = 0, rtvInsideAt = 0;
    // The rtv buffer's two parts, kept to upload them together: the diffuse RTV (basis, weights, inside
    // flags) and after it the glossy RTV's SVD (setGlossyRtv: its weights W_k, then its bases E_k).
    std::vector<float> rtvDiffuse, rtvGlossy;
    int glossyRank = 0;  // 0: none
    int glossyViewRows = 0, glossyViews = 0;
    double glossySpecular = 0.0;
    std::vector<float> prismCorners;  // 4 floats per corner, 3 corners per prism (setMesh)
    std::size_t meshVertexCount = 0;
    std::vector<float> macroTransfer;  // 256 floats per mesh vertex; empty: none
    bool hasEnvironment = false;
    // The entry array holds the tops and fins, then the base faces turned to face down (entries from below);
    // entryCount counts the first part only.
    GLsizei entryCount = 0, baseCount = 0, belowCount = 0;
    bool baseEntry = true;
    GLsizei entryDrawCount() const { return entryCount + (baseEntry ? belowCount : 0); }
    VertexArray entryArray, baseArray;
    glm::dvec3 lo{0.0}, hi{0.0};

    void setGdm(const GdmDims& d, double h, int k, double tol) {
        dims = d;
        shellHeight = h;
        const std::vector<float> none;
        occupancy.store(none);
        albedo.store(none);
        signedDistance.store(none);
        hasOccupancy = hasAlbedo = hasDistance = false;
        rtv.store(none);
        rtvRank = 0;
        rtvDiffuse.clear();
        rtvGlossy.clear();
        glossyRank = 0;
        hasEnvironment = false;
        macroTransfer.clear();
        rank = k;
        tolerance = tol;
        hasMesh = false;  // the shell's thickness and texture positions depend on H
    }

    // The flat RTV buffer of setRtv: basis, weights, inside flags.
    void storeRtv(const GdmDims& grid, int rtvRankIn, const std::vector<float>& basis,
                  const std::vector<float>& rtvWeights, const std::vector<float>& distance,
                  const char* what) {
        if (!this->dims)
            throw Error(ErrorKind::InvalidInput, std::string("GdmRenderer: set the GDM before ") + what);
        if (grid.nx != dims->nx || grid.ny != dims->ny || grid.nz != dims->nz)
            throw Error(ErrorKind::InvalidInput,
                        std::string("GdmRenderer: ") + what + " is on a " + std::to_string(grid.nx) + " x " +
                            std::to_string(grid.ny) + " x " + std::to_string(grid.nz) + " grid, the GDM on " +
                            std::to_string(dims->nx) + " x " + std::to_string(dims->ny) + " x " +
                            std::to_string(dims->nz));
        const std::size_t voxels = grid.voxelCount();
        const std::size_t width = std::size_t(kShCount) * 3;
        if (rtvRankIn < 1 || basis.size() != std::size_t(rtvRankIn) * width ||
            rtvWeights.size() != voxels * std::size_t(rtvRankIn) || distance.size() != voxels)
            throw Error(ErrorKind::InvalidInput,
                        std::string("GdmRenderer: ") + what + "'s maps do not match its rank and grid");
        std::vector<float> data;
        data.reserve(basis.size() + rtvWeights.size() + voxels);
        data.insert(data.end(), basis.begin(), basis.end());
        data.insert(data.end(), rtvWeights.begin(), rtvWeights.end());
        for (const float d : distance) data.push_back(d < 0.0f ? 1.0f : 0.0f);
        rtvDiffuse = std::move(data);
        rtvRank = rtvRankIn;
        rtvWeightsAt = basis.size();
        rtvInsideAt = basis.size() + rtvWeights.size();
        uploadRtv();
    }
    // The rtv buffer: the diffuse part, then the glossy one.
    void uploadRtv() {
        std::vector<float> data(rtvDiffuse);
        data.insert(data.end(), rtvGlossy.begin(), rtvGlossy.end());
        rtv.store(data);
        checkGl("GdmRenderer: uploading the RTV");
    }
    static void describe(const VertexArray& array, const Buffer& buffer) {
        glVertexArrayVertexBuffer(array.id, 0, buffer.id, 0, sizeof(Vertex));
        for (GLuint a = 0; a < 6; ++a) {
            glEnableVertexArrayAttrib(array.id, a);
            glVertexArrayAttribBinding(array.id, a, 0);
        }
        glVertexArrayAttribFormat(array.id, 0, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, position));
        glVertexArrayAttribFormat(array.id, 1, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, texture));
        glVertexArrayAttribIFormat(array.id, 2, 1, GL_UNSIGNED_INT, offsetof(Vertex, prism));
        glVertexArrayAttribFormat(array.id, 3, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, tangent));
        glVertexArrayAttribFormat(array.id, 4, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, bitangent));
        glVertexArrayAttribFormat(array.id, 5, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, normal));
    }

    // Draws `array` (`count` vertices) into the target with output `output` (gdm.frag.glsl's uOutput), and
    // reads the RGBA float picture back, top row first.
    std::vector<float> draw(const VertexArray& array, GLsizei count, int output, bool cull,
                            const Camera& camera, const glm::dvec3& light, int width, int height,
                            GdmDirectionLookup directions, GdmTechnique technique = GdmTechnique::Gdm) {
        const double radius = 0.5 * glm::length(hi - lo);
        const double distance = glm::length(0.5 * (lo + hi) - camera.eye);
        const double farPlane = distance + 2.0 * radius + 1e-6;
        const double nearPlane = std::max(farPlane * 1e-5, distance - 2.0 * radius);
        const glm::mat4 viewProjection(
            projectionMatrix(camera, double(width) / double(height), nearPlane, farPlane) *
            viewMatrix(camera));
        glUseProgram(program.id());
        glUniformMatrix4fv(program.uniformLocation("uViewProjection"), 1, GL_FALSE,
                           glm::value_ptr(viewProjection));
        glUniform3f(program.uniformLocation("uEye"), float(camera.eye.x), float(camera.eye.y),
                    float(camera.eye.z));
        glUniform3f(program.uniformLocation("uLight"), float(light.x), float(light.y), float(light.z));
        glUniform3i(program.uniformLocation("uVoxels"), dims->nx, dims->ny, dims->nz);
        glUniform2i(program.uniformLocation("uDirections"), dims->ntheta, dims->nphi);
        glUniform1f(program.uniformLocation("uHeight"), float(shellHeight));
        glUniform1i(program.uniformLocation("uRank"), rank);
        glUniform1f(program.uniformLocation("uTolerance"), float(tolerance));
        glUniform1i(program.uniformLocation("uBilinearDirections"),
                    directions == GdmDirectionLookup::Bilinear);
        glUniform1i(program.uniformLocation("uOutput"), output);
        glUniform1i(program.uniformLocation("uHasAlbedo"), hasAlbedo ? 1 : 0);
        glUniform1i(program.uniformLocation("uHasDistance"), hasDistance ? 1 : 0);
        glUniform3i(program.uniformLocation("uDistanceVoxels"), distanceVoxels.x, distanceVoxels.y,
                    distanceVoxels.z);
        glUniform1i(program.uniformLocation("uJacobianLight"), lightFrame == GdmLightFrame::Jacobian ? 1 : 0);
        glUniform3f(program.uniformLocation("uLightColor"), float(lighting.lightColor.r),
                    float(lighting.lightColor.g), float(lighting.lightColor.b));
        glUniform1f(program.uniformLocation("uAmbient"), float(lighting.ambient));
        glUniform1f(program.uniformLocation("uSpecular"), float(lighting.specular));
        glUniform1f(program.uniformLocation("uShininess"), float(lighting.shininess));
        glUniform1i(program.uniformLocation("uTechnique"), technique == GdmTechnique::Gdm      ? 0
                                                           : technique == GdmTechnique::Refine ? 1
                                                                                               : 2);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, faces.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, weights.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, eigen.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, raw.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, occupancy.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, albedo.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, signedDistance.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, lightFrames.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, rtv.id);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, environment.id);
        const bool lit = hasEnvironment && rtvRank > 0;
        glUniform1i(program.uniformLocation("uEnvironment"), lit ? 1 : 0);
        glUniform1i(program.uniformLocation("uRtvRank"), rtvRank);
        glUniform1i(program.uniformLocation("uRtvWeightsAt"), GLint(rtvWeightsAt));
        glUniform1i(program.uniformLocation("uRtvInsideAt"), GLint(rtvInsideAt));
        glUniform1i(program.uniformLocation("uGlossyRank"), glossyRank);
        glUniform1i(program.uniformLocation("uGlossyWeightsAt"), GLint(rtvDiffuse.size()));
        glUniform1i(program.uniformLocation("uGlossyBasisAt"),
                    GLint(rtvDiffuse.size() +
                          std::size_t(kShCount) * dims->voxelCount() * std::size_t(std::max(glossyRank, 0))));
        glUniform3i(program.uniformLocation("uGlossyViews"), dims->ntheta, glossyViewRows, glossyViews);
        glUniform1f(program.uniformLocation("uGlossySpecular"), float(glossySpecular));
        glUniform1i(program.uniformLocation("uLightingAt"), GLint(prismCorners.size()));
        glBindVertexArray(array.id);
        glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
        glViewport(0, 0, width, height);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        if (cull) {  // the faces a ray enters a prism through
            glEnable(GL_CULL_FACE);
            glCullFace(GL_BACK);
            glFrontFace(GL_CCW);
        } else {
            glDisable(GL_CULL_FACE);
        }
        glDisable(GL_BLEND);
        glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glDrawArrays(GL_TRIANGLES, 0, count);
        std::vector<float> pixels(std::size_t(width) * std::size_t(height) * 4);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, pixels.data());
        glDisable(GL_CULL_FACE);
        glBindVertexArray(0);
        glUseProgram(0);
        checkGl("GdmRenderer: drawing");
        // GL's row 0 is the bottom one; the picture's is the top (CONVENTIONS §7).
        std::vector<float> flipped(pixels.size());
        const std::size_t row = std::size_t(width) * 4;
        for (int y = 0; y < height; ++y)
            std::copy_n(pixels.data() + std::size_t(height - 1 - y) * row, row,
                        flipped.data() + std::size_t(y) * row);
        return flipped;
    }
};

GdmRenderer::GdmRenderer() : mImpl(std::make_unique<Impl>()) {
    mImpl->program =
        buildProgram(ShaderLibrary::embedded(), "gdm/gdm.vert.glsl", "gdm/gdm.frag.glsl", {}, "GDM renderer");
}

GdmRenderer::~GdmRenderer() = default;

void GdmRenderer::setGdm(const Gdm& gdm) {
    validateGdmDims(gdm.dims, gdm.height, "GdmRenderer");
    if (gdm.values.size() != gdm.dims.valueCount())
        throw Error(ErrorKind::InvalidInput,
                    "GdmRenderer: the GDM holds " + std::to_string(gdm.values.size()) +
                        " values, its dims need " + std::to_string(gdm.dims.valueCount()));
    const std::vector<float> none;
    mImpl->raw.store(gdm.values);
    mImpl->weights.store(none);
    mImpl->eigen.store(none);
    checkGl("GdmRenderer: uploading the GDM");
    mImpl->setGdm(gdm.dims, gdm.height, 0, 1e-4 * gdm.height / gdm.dims.nz);  // emulateGdm's raw tolerance
}

void GdmRenderer::setGdm(const GdmSvd& svd) {
    validateGdmDims(svd.dims, svd.height, "GdmRenderer");
    if (svd.layout != GdmLayout::XyPhiByThetaZ)
        throw Error(ErrorKind::InvalidInput, std::string("GdmRenderer: it reads the paper's layout ") +
                                                 toString(GdmLayout::XyPhiByThetaZ) + ", not " +
                                                 toString(svd.layout));
    if (svd.rank < 1 || svd.weights.size() != svd.rows * std::size_t(svd.rank) ||
        svd.eigen.size() != std::size_t(svd.rank) * svd.cols)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: the SVD's maps do not match its rank and layout");
    const std::vector<float> none;
    mImpl->raw.store(none);
    mImpl->weights.store(svd.weights);
    mImpl->eigen.store(svd.eigen);
    checkGl("GdmRenderer: uploading the SVD");
    mImpl->setGdm(svd.dims, svd.height, svd.rank, svd.exitTolerance);
}

void GdmRenderer::setMesh(const Mesh& mesh, const PrismShellOptions& shellOptions) {
    if (!mImpl->dims) throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the GDM before the mesh");
    PrismShellOptions options = shellOptions;
    options.height = mImpl->shellHeight;
    const PrismShell shell = buildPrismShell(mesh, options);
    // Every corner with its world position and its texture position in the isotropic frame (tiling * uv,
    // w H).
    std::vector<Vertex> entry, base;
    std::vector<glm::vec4> faces;
    entry.reserve(shell.prisms.size() * 21);
    base.reserve(shell.prisms.size() * 3);
    faces.reserve(shell.prisms.size() * 48);
    std::vector<glm::vec4> lightFrames;
    lightFrames.reserve(shell.prisms.size() * 3);
    std::vector<float> prismCorners;
    prismCorners.reserve(shell.prisms.size() * 12);
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (std::size_t p = 0; p < shell.prisms.size(); ++p) {
        std::array<glm::dvec3, 3> prismBase, prismTop;
        std::array<glm::dvec2, 3> prismTile;
        for (int c = 0; c < 3; ++c) {
            prismBase[c] = glm::dvec3(shell.base[shell.prisms[p][c]]);
            prismTop[c] = glm::dvec3(shell.top[shell.prisms[p][c]]);
            prismTile[c] = options.tiling * glm::dvec2(mesh.vertices[shell.corners[p][c]].uv);
            // The corner's tile position as the faces' texture positions have it, and its mesh vertex (a
            // float holds an index exactly up to 2^24).
            prismCorners.insert(prismCorners.end(), {float(prismTile[c].x), float(prismTile[c].y),
                                                     float(shell.corners[p][c]), 0.0f});
        }
        const glm::dmat3 jacobian = gdmPrismJacobian(prismBase, prismTop, prismTile, options.height);
        const double determinant = glm::determinant(jacobian);
        // A degenerate prism keeps the tangent-frame direction (marked by a zero first row).
        const glm::dmat3 inverse = std::isfinite(determinant) && std::abs(determinant) > 1e-300
                                       ? glm::inverse(jacobian)
                                       : glm::dmat3(0.0);
        // glm is column-major: row r of the inverse is (inverse[0][r], inverse[1][r], inverse[2][r]).
        for (int r = 0; r < 3; ++r)
            lightFrames.emplace_back(float(inverse[0][r]), float(inverse[1][r]), float(inverse[2][r]), 0.0f);
        const auto triangles = prismTriangleCorners(shell, p);
        for (int f = 0; f < 8; ++f)
            for (const PrismCorner& corner : triangles[f]) {
                const std::uint32_t s = shell.prisms[p][corner.corner];
                const glm::vec3 world = corner.top ? shell.top[s] : shell.base[s];
                const glm::vec2 uv = mesh.vertices[shell.corners[p][corner.corner]].uv;
                const glm::vec3 texture(float(options.tiling.x * double(uv.x)),
                                        float(options.tiling.y * double(uv.y)),
                                        corner.top ? float(options.height) : 0.0f);
                faces.emplace_back(world, 0.0f);
                faces.emplace_back(texture, 0.0f);
                lo = glm::min(lo, glm::dvec3(world));
                hi = glm::max(hi, glm::dvec3(world));
                const MeshVertex& m = mesh.vertices[shell.corners[p][corner.corner]];
                const glm::vec3 t = glm::vec3(m.tangent), b = m.tangent.w * glm::cross(m.normal, t);
                const Vertex vertex{{world.x, world.y, world.z},
                                    {texture.x, texture.y, texture.z},
                                    std::uint32_t(p),
                                    {t.x, t.y, t.z},
                                    {b.x, b.y, b.z},
                                    {m.normal.x, m.normal.y, m.normal.z}};
                (f == 0 ? base : entry).push_back(vertex);
            }
    }
    // The base faces, turned over: the faces a ray coming through the base surface from below (the base is
    // not solid, §8) enters a prism through.
    const std::size_t tops = entry.size();
    for (std::size_t v = 0; v < base.size(); v += 3)
        entry.insert(entry.end(), {base[v], base[v + 2], base[v + 1]});
    mImpl->entryVertices.store(entry);
    mImpl->baseVertices.store(base);
    mImpl->faces.store(faces);
    mImpl->lightFrames.store(lightFrames);
    Impl::describe(mImpl->entryArray, mImpl->entryVertices);
    Impl::describe(mImpl->baseArray, mImpl->baseVertices);
    checkGl("GdmRenderer: uploading the shell");
    mImpl->entryCount = GLsizei(tops);
    mImpl->belowCount = GLsizei(entry.size() - tops);
    mImpl->baseCount = GLsizei(base.size());
    mImpl->lo = lo;
    mImpl->hi = hi;
    mImpl->hasMesh = true;
    mImpl->prismCorners = std::move(prismCorners);
    mImpl->meshVertexCount = mesh.vertices.size();
    mImpl->macroTransfer.clear();
    mImpl->environment.store(std::vector<float>{});
    mImpl->hasEnvironment = false;
}

GdmSceneImages GdmRenderer::render(const Camera& camera, glm::dvec3 light, int width, int height,
                                   GdmDirectionLookup directions, GdmTechnique technique) {
    validateCamera(camera);
    validateGdmPicture(width, height);
    if (!mImpl->hasMesh) throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the GDM and the mesh first");
    if ((technique == GdmTechnique::March && !mImpl->hasOccupancy) ||
        (technique == GdmTechnique::Refine && !mImpl->hasOccupancy && !mImpl->hasDistance))
        throw Error(ErrorKind::InvalidInput,
                    "GdmRenderer: march reads the occupancy volume (setVolumes), "
                    "refine the distance volume (setDistance) or the occupancy");
    const BindingGuard guard;
    mImpl->target.ensure(width, height, GL_RGBA32F, "GdmRenderer");
    GdmSceneImages images{Image(width, height, 4), Image(width, height, 1), Image(width, height, 1)};
    for (int output = 0; output < 2; ++output) {
        const std::vector<float> pixels =
            mImpl->draw(mImpl->entryArray, mImpl->entryDrawCount(), output, true, camera, light, width,
                        height, directions, technique);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const float* p = pixels.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4;
                const bool hit = p[3] > 0.5f;
                if (output == 0) {
                    for (int c = 0; c < 4; ++c) images.uvw.at(x, y, c) = hit ? p[c] : 0.0f;
                    images.mask.at(x, y) = hit ? 1.0f : 0.0f;
                } else {
                    images.shadow.at(x, y) = hit && p[0] > 0.5f ? 1.0f : 0.0f;
                }
            }
    }
    return images;
}

void GdmRenderer::setVolumes(const std::vector<std::uint8_t>& occupancy,
                             const std::vector<std::uint8_t>& albedo) {
    if (!mImpl->dims) throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the GDM before its volumes");
    const std::size_t voxels = std::size_t(mImpl->dims->nx) * mImpl->dims->ny * mImpl->dims->nz;
    if (occupancy.size() != voxels || (!albedo.empty() && albedo.size() != 3 * voxels))
        throw Error(ErrorKind::InvalidInput,
                    "GdmRenderer: the volumes do not match the GDM's " + std::to_string(voxels) + " voxels");
    std::vector<float> occupied(occupancy.begin(), occupancy.end());
    std::vector<float> linear(albedo.size());
    for (std::size_t n = 0; n < albedo.size(); ++n)
        linear[n] = float(srgbToLinear(double(albedo[n]) / 255.0));
    mImpl->occupancy.store(occupied);
    mImpl->albedo.store(linear);
    checkGl("GdmRenderer: uploading the volumes");
    mImpl->hasOccupancy = true;
    mImpl->hasAlbedo = !albedo.empty();
}

void GdmRenderer::setDistance(const std::vector<float>& distance) {
    if (!mImpl->dims)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the GDM before its distance volume");
    setDistance(distance, glm::ivec3(mImpl->dims->nx, mImpl->dims->ny, mImpl->dims->nz));
}

void GdmRenderer::setDistance(const std::vector<float>& distance, glm::ivec3 size) {
    if (!mImpl->dims)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the GDM before its distance volume");
    if (size.x < 1 || size.y < 1 || size.z < 1)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: the distance volume's grid must be >= 1 voxel");
    const std::size_t voxels = std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z);
    if (!distance.empty() && distance.size() != voxels)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: the distance volume has " +
                                                 std::to_string(distance.size()) + " voxels, its grid " +
                                                 std::to_string(voxels));
    mImpl->signedDistance.store(distance);
    checkGl("GdmRenderer: uploading the distance volume");
    mImpl->hasDistance = !distance.empty();
    mImpl->distanceVoxels = size;
}

void GdmRenderer::setLightFrame(GdmLightFrame frame) {
    mImpl->lightFrame = frame;
}

GdmGpuMemory GdmRenderer::gpuMemory() const {
    const Impl& m = *mImpl;
    GdmGpuMemory memory;
    memory.gdm = m.weights.bytes + m.eigen.bytes + m.raw.bytes;
    memory.volumes = m.occupancy.bytes + m.albedo.bytes + m.signedDistance.bytes;
    memory.shell = m.entryVertices.bytes + m.baseVertices.bytes + m.faces.bytes + m.lightFrames.bytes;
    memory.environment = m.rtvRank > 0 || m.hasEnvironment ? m.rtv.bytes + m.environment.bytes : 0;
    return memory;
}

void GdmRenderer::setRtv(const GdmRtv& rtv) {
    // Uncompressed: the transfer itself as the weights of rank 48, with the identity basis.
    const std::size_t width = std::size_t(kShCount) * 3;
    std::vector<float> identity(width * width, 0.0f);
    for (std::size_t n = 0; n < width; ++n) identity[n * width + n] = 1.0f;
    mImpl->storeRtv(rtv.dims, int(width), identity, rtv.transfer, rtv.distance, "the RTV");
}

void GdmRenderer::setRtv(const GdmRtvSvd& rtv) {
    mImpl->storeRtv(rtv.dims, rtv.rank, rtv.basis, rtv.weights, rtv.distance, "the RTV's SVD");
}

void GdmRenderer::setGlossyRtv(const GdmGlossyRtvSvd& glossy, double specular) {
    Impl& m = *mImpl;
    if (m.rtvRank == 0)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the (diffuse) RTV before the glossy one");
    if (!(std::isfinite(specular) && specular >= 0.0))
        throw Error(ErrorKind::InvalidInput,
                    "GdmRenderer: the glossy term's specular " + formatNumber(specular) + " is not >= 0");
    const GdmDims& d = glossy.dims;
    if (d.nx != m.dims->nx || d.ny != m.dims->ny || d.nz != m.dims->nz || d.ntheta < 2 ||
        glossy.viewCount != std::size_t(d.ntheta / 2) * std::size_t(d.nphi))
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: the glossy RTV is not on the GDM's voxel grid");
    const std::size_t voxels = d.voxelCount(), rank = std::size_t(std::max(glossy.rank, 0));
    if (rank < 1 || glossy.weights.size() != std::size_t(kShCount) * voxels * rank ||
        glossy.basis.size() != std::size_t(kShCount) * rank * glossy.viewCount)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: the glossy RTV's maps do not match its rank");
    m.rtvGlossy = glossy.weights;
    m.rtvGlossy.insert(m.rtvGlossy.end(), glossy.basis.begin(), glossy.basis.end());
    m.glossyRank = glossy.rank;
    m.glossyViewRows = d.ntheta / 2;
    m.glossyViews = d.nphi;
    m.glossySpecular = specular;
    m.uploadRtv();
}

void GdmRenderer::clearGlossyRtv() {
    Impl& m = *mImpl;
    if (m.glossyRank == 0) return;
    m.rtvGlossy.clear();
    m.glossyRank = 0;
    m.uploadRtv();
}

void GdmRenderer::setMacroTransfer(const MacroTransfer& transfer) {
    if (!mImpl->hasMesh)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the mesh before its macro transfer");
    if (transfer.matrices.size() != mImpl->meshVertexCount * std::size_t(kShCount * kShCount))
        throw Error(ErrorKind::InvalidInput,
                    "GdmRenderer: the macro transfer has " + std::to_string(transfer.vertexCount()) +
                        " vertices, the mesh " + std::to_string(mImpl->meshVertexCount));
    mImpl->macroTransfer = transfer.matrices;
    mImpl->hasEnvironment = false;
}

void GdmRenderer::setEnvironment(const ShColor& world) {
    Impl& m = *mImpl;
    if (m.macroTransfer.empty())
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the macro transfer before the environment");
    std::vector<float> data(m.prismCorners);
    const std::size_t width = std::size_t(kShCount) * 3;
    data.resize(m.prismCorners.size() + m.meshVertexCount * width);
    float* lighting = data.data() + m.prismCorners.size();
    for (std::size_t v = 0; v < m.meshVertexCount; ++v) {
        const ShColor local =
            applyMacroTransfer(m.macroTransfer.data() + v * std::size_t(kShCount * kShCount), world);
        for (std::size_t k = 0; k < std::size_t(kShCount); ++k)
            for (int c = 0; c < 3; ++c) lighting[v * width + k * 3 + std::size_t(c)] = float(local[k][c]);
    }
    m.environment.store(data);
    checkGl("GdmRenderer: uploading the environment lighting");
    m.hasEnvironment = true;
}

void GdmRenderer::clearEnvironment() {
    mImpl->hasEnvironment = false;
}

bool GdmRenderer::hasEnvironment() const {
    return mImpl->hasEnvironment && mImpl->rtvRank > 0;
}

void GdmRenderer::setBaseEntry(bool enabled) {
    mImpl->baseEntry = enabled;
}

void GdmRenderer::setLighting(const Lighting& lighting) {
    validate(lighting);
    mImpl->lighting = lighting;
}

Image GdmRenderer::renderShaded(const Camera& camera, glm::dvec3 light, int width, int height,
                                GdmDirectionLookup directions, GdmTechnique technique) {
    validateCamera(camera);
    validateGdmPicture(width, height);
    if (!mImpl->hasMesh) throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the GDM and the mesh first");
    if (!mImpl->hasOccupancy)
        throw Error(ErrorKind::InvalidInput, "GdmRenderer: shading needs the occupancy volume (setVolumes)");
    const BindingGuard guard;
    mImpl->target.ensure(width, height, GL_RGBA32F, "GdmRenderer");
    const std::vector<float> pixels = mImpl->draw(mImpl->entryArray, mImpl->entryDrawCount(), 3, true, camera,
                                                  light, width, height, directions, technique);
    Image image(width, height, 4);
    std::copy(pixels.begin(), pixels.end(), image.row(0));
    return image;
}

Image GdmRenderer::renderPrismIds(const Camera& camera, int width, int height, PrismFaces faces) {
    validateCamera(camera);
    validateGdmPicture(width, height);
    if (!mImpl->hasMesh) throw Error(ErrorKind::InvalidInput, "GdmRenderer: set the GDM and the mesh first");
    const BindingGuard guard;
    mImpl->target.ensure(width, height, GL_RGBA32F, "GdmRenderer");
    const bool base = faces == PrismFaces::Base;
    const std::vector<float> pixels =
        mImpl->draw(base ? mImpl->baseArray : mImpl->entryArray, base ? mImpl->baseCount : mImpl->entryCount,
                    2, !base, camera, glm::dvec3(0.0), width, height, GdmDirectionLookup::Nearest);
    Image ids(width, height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float* p = pixels.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4;
            ids.at(x, y) = p[3] > 0.5f ? p[0] : 0.0f;
        }
    return ids;
}

glm::dmat3 gdmPrismJacobian(const std::array<glm::dvec3, 3>& base, const std::array<glm::dvec3, 3>& top,
                            const std::array<glm::dvec2, 3>& tile, double height) {
    // [dP/du dP/dv] [du1 du2; dv1 dv2] = [e1 e2], the base's edges from corner 0 in world and in tiles.
    const glm::dvec3 e1 = base[1] - base[0], e2 = base[2] - base[0];
    const glm::dvec2 t1 = tile[1] - tile[0], t2 = tile[2] - tile[0];
    const double det = t1.x * t2.y - t2.x * t1.y;
    const glm::dvec3 extrusion = ((top[0] - base[0]) + (top[1] - base[1]) + (top[2] - base[2])) / 3.0;
    if (det == 0.0 || !(height > 0.0)) return glm::dmat3(0.0);
    const glm::dvec3 du = (e1 * t2.y - e2 * t1.y) / det;
    const glm::dvec3 dv = (e2 * t1.x - e1 * t2.x) / det;
    return glm::dmat3(du, dv, extrusion / height);
}

namespace {

template <class Source>
GdmSceneImages renderOnce(const Source& source, const Mesh& mesh, const PrismShellOptions& shell,
                          const Camera& camera, glm::dvec3 light, int width, int height,
                          GdmDirectionLookup directions, bool baseEntry) {
    validateCamera(camera);
    validateGdmPicture(width, height);
    GdmRenderer renderer;
    renderer.setGdm(source);
    renderer.setMesh(mesh, shell);
    renderer.setBaseEntry(baseEntry);
    return renderer.render(camera, light, width, height, directions);
}

}  // namespace

GdmSceneImages renderGdmScene(const Gdm& gdm, const Camera& camera, glm::dvec3 light, int width, int height,
                              GdmDirectionLookup directions) {
    return renderOnce(gdm, makeBuiltinMesh("quad"), {}, camera, light, width, height, directions, false);
}

GdmSceneImages renderGdmScene(const GdmSvd& svd, const Camera& camera, glm::dvec3 light, int width,
                              int height, GdmDirectionLookup directions) {
    return renderOnce(svd, makeBuiltinMesh("quad"), {}, camera, light, width, height, directions, false);
}

GdmSceneImages renderGdmMesh(const Gdm& gdm, const Mesh& mesh, const PrismShellOptions& shell,
                             const Camera& camera, glm::dvec3 light, int width, int height,
                             GdmDirectionLookup directions) {
    return renderOnce(gdm, mesh, shell, camera, light, width, height, directions, true);
}

GdmSceneImages renderGdmMesh(const GdmSvd& svd, const Mesh& mesh, const PrismShellOptions& shell,
                             const Camera& camera, glm::dvec3 light, int width, int height,
                             GdmDirectionLookup directions) {
    return renderOnce(svd, mesh, shell, camera, light, width, height, directions, true);
}

}  // namespace strata::gl
