#include "strata/mesh/tangent_space.h"

#include "strata/core/check.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace strata {
namespace {

// Same threshold as mesh_repair.cpp: a uv triangle flatter than float rounding has no texture direction.
constexpr double kDegenerateRatio = 1e-7;

struct PositionKey {
    std::array<std::uint32_t, 3> bits;
    bool operator==(const PositionKey&) const = default;
};

struct PositionKeyHash {
    std::size_t operator()(const PositionKey& key) const {
        std::size_t h = 0;
        for (std::uint32_t b : key.bits) h = h * 0x9E3779B97F4A7C15ull + b;
        return h;
    }
};

PositionKey keyOf(const glm::vec3& p) {
    // +0 and -0 are the same point.
    const glm::vec3 q = p + glm::vec3(0.0f);
    PositionKey key{};
    std::memcpy(key.bits.data(), &q.x, sizeof(float) * 3);
    return key;
}

// A unit vector orthogonal to the unit vector n: n crossed with the axis least aligned with it.
glm::dvec3 anyOrthogonal(const glm::dvec3& n) {
    const glm::dvec3 a = glm::abs(n);
    const glm::dvec3 axis = a.x <= a.y && a.x <= a.z ? glm::dvec3(1, 0, 0)
                            : a.y <= a.z             ? glm::dvec3(0, 1, 0)
                                                     : glm::dvec3(0, 0, 1);
    return glm::normalize(glm::cross(n, axis));
}

glm::dvec3 projectNormalized(const glm::dvec3& v, const glm::dvec3& n) {
    const glm::dvec3 p = v - n * glm::dot(n, v);
    const double len = glm::length(p);
    return len > 0.0 ? p / len : glm::dvec3(0.0);
}

double cornerAngle(const glm::dvec3& a, const glm::dvec3& b) {
    const double la = glm::length(a), lb = glm::length(b);
    if (la == 0.0 || lb == 0.0) return 0.0;
    return std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
}

}  // namespace

std::size_t computeSmoothNormals(Mesh& mesh) {
    std::unordered_map<PositionKey, glm::dvec3, PositionKeyHash> sums;
    sums.reserve(mesh.vertices.size());
    for (const MeshVertex& v : mesh.vertices) sums.emplace(keyOf(v.position), glm::dvec3(0.0));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const glm::vec3& p0 = mesh.vertices[mesh.indices[t]].position;
        const glm::vec3& p1 = mesh.vertices[mesh.indices[t + 1]].position;
        const glm::vec3& p2 = mesh.vertices[mesh.indices[t + 2]].position;
        // Twice the area times the unit normal: the area weighting comes for free.
        const glm::dvec3 n = glm::cross(glm::dvec3(p1 - p0), glm::dvec3(p2 - p0));
        for (int k = 0; k < 3; ++k) sums[keyOf(mesh.vertices[mesh.indices[t + k]].position)] += n;
    }
    std::size_t repaired = 0;
    for (MeshVertex& v : mesh.vertices) {
        const glm::dvec3 sum = sums[keyOf(v.position)];
        const double len = glm::length(sum);
        if (len > 0.0 && std::isfinite(len)) {
            v.normal = glm::vec3(sum / len);
        } else {
            v.normal = glm::vec3(0.0f, 0.0f, 1.0f);
            ++repaired;
        }
    }
    return repaired;
}

std::size_t computeTangents(Mesh& mesh) {
    const std::size_t n = mesh.vertices.size();
    std::vector<glm::dvec3> normals(n);
    for (std::size_t i = 0; i < n; ++i) {
        normals[i] = glm::dvec3(mesh.vertices[i].normal);
        // The frame is built around the normal: it must be there and unit (loaders normalise).
        STRATA_CHECK(std::abs(glm::length(normals[i]) - 1.0) < 1e-3);
        normals[i] = glm::normalize(normals[i]);
    }
    std::vector<glm::dvec3> tangentSum(n, glm::dvec3(0.0)), bitangentSum(n, glm::dvec3(0.0));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t idx[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        glm::dvec3 p[3];
        glm::dvec2 uv[3];
        for (int k = 0; k < 3; ++k) {
            p[k] = glm::dvec3(mesh.vertices[idx[k]].position);
            uv[k] = glm::dvec2(mesh.vertices[idx[k]].uv);
        }
        const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
        const glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
        const double det = d1.x * d2.y - d2.x * d1.y;
        if (std::abs(det) <= kDegenerateRatio * glm::length(d1) * glm::length(d2) || det == 0.0) continue;
        // Solve [e1 e2] = [T B] [d1 d2]: T = dP/du, B = dP/dv of the triangle's linear map.
        const glm::dvec3 tangent = (e1 * d2.y - e2 * d1.y) / det;
        const glm::dvec3 bitangent = (e2 * d1.x - e1 * d2.x) / det;
        for (int k = 0; k < 3; ++k) {
            const double angle = cornerAngle(p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            const glm::dvec3& nv = normals[idx[k]];
            tangentSum[idx[k]] += angle * projectNormalized(tangent, nv);
            bitangentSum[idx[k]] += angle * projectNormalized(bitangent, nv);
        }
    }
    std::size_t repaired = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3& nv = normals[i];
        glm::dvec3 tangent = tangentSum[i] - nv * glm::dot(nv, tangentSum[i]);
        const double len = glm::length(tangent);
        double w = 1.0;
        // Sums are of unit vectors times angles (radians): below 1e-9 nothing usable is left.
        if (len > 1e-9) {
            tangent /= len;
            w = glm::dot(glm::cross(nv, tangent), bitangentSum[i]) < 0.0 ? -1.0 : 1.0;
        } else {
            tangent = anyOrthogonal(nv);
            ++repaired;
        }
        mesh.vertices[i].tangent = glm::vec4(glm::vec3(tangent), static_cast<float>(w));
    }
    return repaired;
}

}  // namespace strata
