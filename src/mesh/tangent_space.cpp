#include "strata/mesh/tangent_space.h"

#include "strata/core/check.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace strata {
namespace {

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

constexpr std::uint32_t kUnset = 0xffffffffu;

// The reference's test for zero: |x| <= FLT_MIN.
bool notZero(float x) {
    return std::abs(x) > std::numeric_limits<float>::min();
}

// Position, normal and uv: the reference welds corners whose nine floats are equal (+0 == -0).
struct WeldKey {
    std::array<std::uint32_t, 8> bits;
    bool operator==(const WeldKey&) const = default;
};

struct WeldKeyHash {
    std::size_t operator()(const WeldKey& key) const {
        std::size_t h = 0;
        for (std::uint32_t b : key.bits) h = h * 0x9E3779B97F4A7C15ull + b;
        return h;
    }
};

WeldKey weldKeyOf(const MeshVertex& v) {
    const std::array<float, 8> values = {v.position.x, v.position.y, v.position.z, v.normal.x,
                                         v.normal.y,   v.normal.z,   v.uv.x,       v.uv.y};
    WeldKey key{};
    for (std::size_t k = 0; k < values.size(); ++k) {
        const float value = values[k] + 0.0f;  // -0 + 0 = +0
        std::memcpy(&key.bits[k], &value, sizeof value);
    }
    return key;
}

struct TriangleInfo {
    glm::dvec3 tangent{0.0};                                        // unit dP/du (zero if dP/du vanishes)
    std::array<std::uint32_t, 3> neighbor{kUnset, kUnset, kUnset};  // across edge (i, i + 1)
    std::array<std::uint32_t, 3> group{kUnset, kUnset, kUnset};     // per corner
    bool orientPreserving = false;                                  // uv area > 0
    bool groupWithAny = true;
};

struct Group {
    std::uint32_t vertex;  // the welded vertex
    bool orientPreserving;
    glm::dvec3 tangent;
};

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
    const std::size_t vertexCount = mesh.vertices.size();
    for (MeshVertex& v : mesh.vertices) {
        // The frame is built around the normal: it must be there and unit (loaders normalise).
        STRATA_CHECK(std::abs(glm::length(v.normal) - 1.0f) < 1e-3f);
    }
    const std::size_t triangleCount = mesh.indices.size() / 3;
    const std::size_t cornerCount = triangleCount * 3;

    // 1. Weld: corners whose vertices have identical position, normal and uv (float ==) are one vertex.
    std::vector<std::uint32_t> welded(cornerCount);
    {
        std::unordered_map<WeldKey, std::uint32_t, WeldKeyHash> firstOf;
        firstOf.reserve(vertexCount);
        std::vector<std::uint32_t> weldOfVertex(vertexCount);
        for (std::size_t i = 0; i < vertexCount; ++i)
            weldOfVertex[i] =
                firstOf.emplace(weldKeyOf(mesh.vertices[i]), static_cast<std::uint32_t>(i)).first->second;
        for (std::size_t c = 0; c < cornerCount; ++c) welded[c] = weldOfVertex[mesh.indices[c]];
    }
    const auto position = [&](std::size_t corner) -> const glm::vec3& {
        return mesh.vertices[welded[corner]].position;
    };
    const auto normal = [&](std::size_t corner) -> const glm::vec3& {
        return mesh.vertices[welded[corner]].normal;
    };
    const auto uv = [&](std::size_t corner) -> const glm::vec2& { return mesh.vertices[welded[corner]].uv; };

    // 2. Degenerate triangles (two corners at the same position) go last, the others keep their order.
    std::vector<std::uint32_t> good, degenerate;
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const glm::vec3 &p0 = position(3 * t), &p1 = position(3 * t + 1), &p2 = position(3 * t + 2);
        (p0 == p1 || p0 == p2 || p1 == p2 ? degenerate : good).push_back(static_cast<std::uint32_t>(t));
    }

    // 3. Per good triangle, in float as the reference: the unit tangent dP/du and the uv orientation. A
    // triangle whose uv area or dP/du or dP/dv is zero (|x| <= FLT_MIN) "groups with anything".
    std::vector<TriangleInfo> info(triangleCount);
    for (std::uint32_t t : good) {
        const std::size_t c = 3 * std::size_t{t};
        const glm::vec3 d1 = position(c + 1) - position(c), d2 = position(c + 2) - position(c);
        const glm::vec2 t21 = uv(c + 1) - uv(c), t31 = uv(c + 2) - uv(c);
        const float signedArea = t21.x * t31.y - t21.y * t31.x;
        const glm::vec3 os = t31.y * d1 - t21.y * d2;
        const glm::vec3 ot = -t31.x * d1 + t21.x * d2;
        TriangleInfo& ti = info[t];
        ti.orientPreserving = signedArea > 0.0f;
        if (notZero(signedArea)) {
            const float lenOs2 = glm::dot(os, os), lenOt2 = glm::dot(ot, ot);
            const float sign = ti.orientPreserving ? 1.0f : -1.0f;
            if (notZero(lenOs2)) ti.tangent = glm::dvec3(os) * (double(sign) / std::sqrt(double(lenOs2)));
            ti.groupWithAny = !(notZero(lenOs2) && notZero(lenOt2));
        }
    }

    // 4. Neighbours across edges of welded vertices: a half-edge (a, b) pairs with the first unpaired (b, a)
    // after it, in triangle order.
    {
        std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> halfEdges;  // corner indices
        halfEdges.reserve(3 * good.size());
        for (std::uint32_t t : good) {
            for (std::uint32_t i = 0; i < 3; ++i) {
                const std::uint32_t a = welded[3 * t + i], b = welded[3 * t + (i + 1) % 3];
                halfEdges[(std::uint64_t{std::max(a, b)} << 32) | std::min(a, b)].push_back(3 * t + i);
            }
        }
        const auto edgeOf = [&](std::uint32_t corner) {
            const std::uint32_t t = corner / 3, i = corner % 3;
            return std::pair(welded[3 * t + i], welded[3 * t + (i + 1) % 3]);
        };
        for (const auto& [key, list] : halfEdges) {
            // `list` is in triangle order, then corner order (as filled above).
            for (std::size_t x = 0; x < list.size(); ++x) {
                TriangleInfo& a = info[list[x] / 3];
                if (a.neighbor[list[x] % 3] != kUnset) continue;
                const auto [a0, a1] = edgeOf(list[x]);
                for (std::size_t y = x + 1; y < list.size(); ++y) {
                    TriangleInfo& b = info[list[y] / 3];
                    if (b.neighbor[list[y] % 3] != kUnset) continue;
                    const auto [b0, b1] = edgeOf(list[y]);
                    if (a0 == b1 && a1 == b0) {
                        a.neighbor[list[x] % 3] = list[y] / 3;
                        b.neighbor[list[y] % 3] = list[x] / 3;
                        break;
                    }
                }
            }
        }
    }

    // 5. Groups: the triangles around a welded vertex reachable across shared edges with the same uv
    // orientation (a group-with-anything triangle takes the orientation of the first group that reaches it).
    std::vector<Group> groups;
    std::vector<std::uint32_t> stack;
    for (std::uint32_t t : good) {
        for (std::uint32_t i = 0; i < 3; ++i) {
            if (info[t].groupWithAny || info[t].group[i] != kUnset) continue;
            const auto id = static_cast<std::uint32_t>(groups.size());
            groups.push_back({welded[3 * t + i], info[t].orientPreserving, glm::dvec3(0.0)});
            info[t].group[i] = id;
            // Depth first, left neighbour's side before the right's, as the reference's recursion.
            stack.assign({info[t].neighbor[i == 0 ? 2 : i - 1], info[t].neighbor[i]});
            while (!stack.empty()) {
                const std::uint32_t u = stack.back();
                stack.pop_back();
                if (u == kUnset) continue;
                TriangleInfo& ui = info[u];
                std::uint32_t k = 0;
                while (k < 3 && welded[3 * u + k] != groups[id].vertex) ++k;
                STRATA_CHECK(k < 3);
                if (ui.group[k] != kUnset) continue;
                if (ui.groupWithAny && ui.group[0] == kUnset && ui.group[1] == kUnset &&
                    ui.group[2] == kUnset)
                    ui.orientPreserving = groups[id].orientPreserving;
                if (ui.orientPreserving != groups[id].orientPreserving) continue;
                ui.group[k] = id;
                stack.push_back(ui.neighbor[k == 0 ? 2 : k - 1]);
                stack.push_back(ui.neighbor[k]);
            }
        }
    }

    // 6. Each group's tangent: the sum over its corners of the triangle tangent projected into the plane of
    // the normal, weighted by the corner's angle measured in that plane; normalised.
    for (std::uint32_t t : good) {
        const TriangleInfo& ti = info[t];
        if (ti.groupWithAny) continue;
        for (std::uint32_t i = 0; i < 3; ++i) {
            if (ti.group[i] == kUnset) continue;
            const std::size_t c = 3 * std::size_t{t};
            const glm::dvec3 n(normal(c + i));
            const glm::dvec3 p(position(c + i));
            const glm::dvec3 e1 = projectNormalized(glm::dvec3(position(c + (i + 1) % 3)) - p, n);
            const glm::dvec3 e2 = projectNormalized(glm::dvec3(position(c + (i + 2) % 3)) - p, n);
            const double angle = std::acos(std::clamp(glm::dot(e1, e2), -1.0, 1.0));
            groups[ti.group[i]].tangent += angle * projectNormalized(ti.tangent, n);
        }
    }

    // 7. Per corner, its group; a degenerate triangle's corner takes the group of the first good corner at
    // the same welded vertex.
    std::vector<std::uint32_t> cornerGroup(cornerCount, kUnset);
    for (std::uint32_t t : good)
        for (std::uint32_t i = 0; i < 3; ++i) cornerGroup[3 * t + i] = info[t].group[i];
    if (!degenerate.empty()) {
        std::unordered_map<std::uint32_t, std::uint32_t> firstGood;
        for (std::uint32_t t : good)
            for (std::uint32_t i = 0; i < 3; ++i) firstGood.emplace(welded[3 * t + i], 3 * t + i);
        for (std::uint32_t t : degenerate) {
            for (std::uint32_t i = 0; i < 3; ++i) {
                const auto it = firstGood.find(welded[3 * t + i]);
                if (it != firstGood.end()) cornerGroup[3 * t + i] = cornerGroup[it->second];
            }
        }
    }

    // 8. Back to vertices: a vertex whose corners lie in several groups is split, one copy per group (the
    // first keeps the index). Corners without a group (the reference leaves them at (1, 0, 0), -1) take the
    // vertex's first group; a vertex with none, or whose group tangent vanished, is repaired.
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> copies(vertexCount);  // (group, index)
    for (std::size_t c = 0; c < cornerCount; ++c) {
        const std::uint32_t g = cornerGroup[c];
        if (g == kUnset) continue;
        auto& list = copies[mesh.indices[c]];
        const auto it = std::find_if(list.begin(), list.end(), [g](const auto& e) { return e.first == g; });
        std::uint32_t index = 0;
        if (it != list.end()) {
            index = it->second;
        } else if (list.empty()) {
            index = mesh.indices[c];
            list.emplace_back(g, index);
        } else {
            index = static_cast<std::uint32_t>(mesh.vertices.size());
            mesh.vertices.push_back(mesh.vertices[mesh.indices[c]]);
            list.emplace_back(g, index);
        }
        mesh.indices[c] = index;
    }
    std::size_t repaired = 0;
    const auto assign = [&](std::uint32_t index, std::uint32_t g) {
        MeshVertex& v = mesh.vertices[index];
        const glm::dvec3 n = glm::normalize(glm::dvec3(v.normal));
        // Sums of unit vectors times angles (radians): below 1e-9 nothing usable is left.
        const glm::dvec3 sum = g == kUnset ? glm::dvec3(0.0) : groups[g].tangent;
        const glm::dvec3 inPlane = sum - n * glm::dot(n, sum);
        const double len = glm::length(inPlane);
        if (len > 1e-9) {
            v.tangent = glm::vec4(glm::vec3(inPlane / len), groups[g].orientPreserving ? 1.0f : -1.0f);
        } else {
            v.tangent = glm::vec4(glm::vec3(anyOrthogonal(n)), 1.0f);
            ++repaired;
        }
    };
    for (std::size_t i = 0; i < vertexCount; ++i) {
        if (copies[i].empty()) {
            assign(static_cast<std::uint32_t>(i), kUnset);
            continue;
        }
        for (const auto& [g, index] : copies[i]) assign(index, g);
    }
    return repaired;
}

}  // namespace strata
