#include "strata/gdm/macro_transfer.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"
#include "strata/environment/sh_rotation.h"

#include "periodic_scene.h"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace strata {

namespace {

// The mesh as one Embree scene, for occlusion rays.
struct MeshScene {
    detail::DeviceHandle device;
    detail::SceneHandle scene;
};

MeshScene buildMeshScene(const Mesh& mesh, const std::string& what, detail::EmbreeErrors& errors) {
    MeshScene result;
    result.device.reset(rtcNewDevice(nullptr));
    if (!result.device)
        throw Error(ErrorKind::Runtime, what + ": Embree could not start (error " +
                                            std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(result.device.get(), detail::onEmbreeError, &errors);
    result.scene.reset(rtcNewScene(result.device.get()));
    if (!result.scene) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    rtcSetSceneFlags(result.scene.get(), RTC_SCENE_FLAG_ROBUST);
    detail::GeometryHandle geometry(rtcNewGeometry(result.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
    if (!geometry) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    // Embree reads 16 bytes at the last vertex: one float of padding.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0,
                                                                 RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                                 mesh.vertices.size() + 1));
    auto* indices = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), mesh.indices.size() / 3));
    if (!vertices || !indices) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        for (int c = 0; c < 3; ++c) vertices[3 * v + std::size_t(c)] = mesh.vertices[v].position[c];
    for (int c = 0; c < 3; ++c) vertices[3 * mesh.vertices.size() + std::size_t(c)] = 0.0f;
    for (std::size_t k = 0; k < mesh.indices.size(); ++k) indices[k] = mesh.indices[k];
    rtcCommitGeometry(geometry.get());
    rtcAttachGeometry(result.scene.get(), geometry.get());
    rtcCommitScene(result.scene.get());
    if (rtcGetDeviceError(result.device.get()) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return result;
}

void validateMesh(const Mesh& mesh, const MacroTransferOptions& options, const std::string& what) {
    if (mesh.vertices.empty() || mesh.indices.empty())
        throw Error(ErrorKind::InvalidInput, what + ": the mesh is empty");
    if (mesh.indices.size() % 3 != 0)
        throw Error(ErrorKind::InvalidInput,
                    what + ": " + std::to_string(mesh.indices.size()) + " indices are not whole triangles");
    for (const std::uint32_t index : mesh.indices)
        if (index >= mesh.vertices.size())
            throw Error(ErrorKind::InvalidInput, what + ": index " + std::to_string(index) +
                                                     " is out of range (" +
                                                     std::to_string(mesh.vertices.size()) + " vertices)");
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const MeshVertex& vertex = mesh.vertices[v];
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(vertex.position[c]) || !std::isfinite(vertex.normal[c]) ||
                !std::isfinite(vertex.tangent[c]))
                throw Error(ErrorKind::InvalidInput,
                            what + ": vertex " + std::to_string(v) +
                                " has a position, normal or tangent that is not finite");
        if (glm::length(vertex.normal) < 1e-6f)
            throw Error(ErrorKind::InvalidInput, what + ": vertex " + std::to_string(v) + " has no normal");
    }
    if (!(std::isfinite(options.shellThickness) && options.shellThickness >= 0.0))
        throw Error(ErrorKind::InvalidInput, what + ": shell thickness must be finite and >= 0, got " +
                                                 formatNumber(options.shellThickness));
    if (!(std::isfinite(options.offset) && options.offset > 0.0))
        throw Error(ErrorKind::InvalidInput,
                    what + ": offset must be > 0, got " + formatNumber(options.offset));
}

// The vertex's frame: rows T, B, N (world to local), N the unit normal, T its tangent made orthogonal to N
// (any perpendicular where the tangent is parallel to N or missing), B = N x T.
glm::dmat3 worldToLocal(const MeshVertex& vertex) {
    const glm::dvec3 n = glm::normalize(glm::dvec3(vertex.normal));
    glm::dvec3 t = glm::dvec3(vertex.tangent) - glm::dot(glm::dvec3(vertex.tangent), n) * n;
    if (glm::length(t) < 1e-9)
        t = std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0)) : glm::cross(n, glm::dvec3(0, 1, 0));
    t = glm::normalize(t);
    const glm::dvec3 b = glm::cross(n, t);
    // glm is column-major: the transpose of the matrix whose columns are T, B, N.
    return glm::transpose(glm::dmat3(t, b, n));
}

}  // namespace

MacroTransfer bakeMacroTransfer(const Mesh& mesh, const MacroTransferOptions& options) {
    const std::string what = "macro transfer of " + (mesh.name.empty() ? std::string("the mesh") : mesh.name);
    validateMesh(mesh, options, what);
    const Bounds bounds = meshBounds(mesh);
    const double lift = options.offset * glm::length(glm::dvec3(bounds.max - bounds.min));
    detail::EmbreeErrors errors;
    MeshScene scene;
    if (options.occlusion) scene = buildMeshScene(mesh, what, errors);

    // M = D(R) G, with D(R) the SH rotation into the vertex's frame (Y(R w) = D(R) Y(w): rotations keep
    // bands) and G the visibility-weighted Gram matrix sum_q w_q V_q Y(w_q) Y(w_q)^T. The rule is exact for
    // products of band-3 functions, so over the whole sphere G is the identity: G = I - the sum over the
    // occluded directions alone, which costs only where the mesh is in the way.
    const SphereQuadrature& quadrature = shQuadrature();
    const std::size_t nodes = quadrature.directions.size();
    std::vector<ShVector> basis(nodes);
    for (std::size_t q = 0; q < nodes; ++q) basis[q] = shEvaluate(quadrature.directions[q]);

    MacroTransfer transfer;
    constexpr int kN = kShCount;
    constexpr std::size_t kEntries = std::size_t(kN) * std::size_t(kN);
    transfer.matrices.assign(mesh.vertices.size() * kEntries, 0.0f);
    parallelFor(0, int(mesh.vertices.size()), [&](int index) {
        const MeshVertex& vertex = mesh.vertices[std::size_t(index)];
        double gram[kEntries] = {};
        for (int i = 0; i < kN; ++i) gram[i * kN + i] = 1.0;
        if (options.occlusion) {
            const glm::dvec3 normal = glm::normalize(glm::dvec3(vertex.normal));
            const glm::dvec3 origin = glm::dvec3(vertex.position) + (options.shellThickness + lift) * normal;
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            for (std::size_t q = 0; q < nodes; ++q) {
                const glm::dvec3& w = quadrature.directions[q];
                if (!options.lowerHemisphere && glm::dot(w, normal) <= 0.0) continue;
                RTCRay ray{};
                ray.org_x = float(origin.x);
                ray.org_y = float(origin.y);
                ray.org_z = float(origin.z);
                ray.dir_x = float(w.x);
                ray.dir_y = float(w.y);
                ray.dir_z = float(w.z);
                ray.tnear = 0.0f;
                ray.tfar = std::numeric_limits<float>::infinity();
                ray.mask = 0xFFFFFFFFu;
                ray.flags = 0;
                rtcOccluded1(scene.scene.get(), &context, &ray);
                if (ray.tfar >= 0.0f) continue;  // Embree marks an occluded ray with tfar = -inf
                const ShVector& y = basis[q];
                const double weight = quadrature.weights[q];
                for (int i = 0; i < kN; ++i) {
                    const double wi = weight * y[std::size_t(i)];
                    for (int j = i; j < kN; ++j) gram[i * kN + j] -= wi * y[std::size_t(j)];
                }
            }
            for (int i = 0; i < kN; ++i)
                for (int j = 0; j < i; ++j) gram[i * kN + j] = gram[j * kN + i];
        }
        // Row i of M: sum over band(i)'s orders m' of D(R)[i][m'] G[m'][j].
        const ShRotation rotation(worldToLocal(vertex));
        float* matrix = transfer.matrices.data() + std::size_t(index) * kEntries;
        for (int l = 0; l < kShBands; ++l)
            for (int m = -l; m <= l; ++m)
                for (int j = 0; j < kN; ++j) {
                    double sum = 0.0;
                    for (int n = -l; n <= l; ++n)
                        sum += rotation.entry(l, m, n) * gram[shIndex(l, n) * kN + j];
                    matrix[shIndex(l, m) * kN + j] = float(sum);
                }
    });
    if (!errors.first.empty()) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return transfer;
}

ShColor applyMacroTransfer(const float* matrix, const ShColor& world) {
    ShColor local{};
    for (int i = 0; i < kShCount; ++i) {
        glm::dvec3 sum(0.0);
        for (int j = 0; j < kShCount; ++j) sum += double(matrix[i * kShCount + j]) * world[std::size_t(j)];
        local[std::size_t(i)] = sum;
    }
    return local;
}

}  // namespace strata
