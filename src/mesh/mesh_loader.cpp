#include "strata/mesh/mesh_loader.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/core/memory_budget.h"
#include "strata/mesh/tangent_space.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

namespace strata {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void invalid(const fs::path& path, const std::string& what) {
    throw Error(ErrorKind::InvalidInput, path.string() + ": " + what);
}

[[noreturn]] void noTexCoords(const fs::path& path) {
    invalid(path, "has no texture coordinates; relief mapping needs them");
}

// What a vertex brought from the file (kept per vertex: glTF primitives differ).
struct VertexSource {
    bool normal = false;
    bool tangent = false;
};

struct RawMesh {
    Mesh mesh;
    std::vector<VertexSource> source;  // one per vertex
    bool missingUvs = false;           // some face had no texture coordinates (allowed by !requireUvs)
};

void requireFinite(const fs::path& path, const std::vector<float>& values, const char* what) {
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (!std::isfinite(values[i])) {
            invalid(path, std::string("non-finite ") + what + " value (" + formatNumber(values[i]) +
                              ") at element " + std::to_string(i));
        }
    }
}

// --- OBJ ----------------------------------------------------------------------------------------------

// tinyobjloader reads a number it cannot parse ("nan", "inf", "1e999", "x") as 0 without a word, so the
// v, vt and vn lines are checked here first, with their line numbers. The same pass counts what
// tinyobjloader and the welding below will hold, for the memory budget, before either runs.
void prescanObj(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::Io, path.string() + ": cannot open the file");
    std::string line;
    std::uint64_t lineNumber = 0;
    std::uint64_t attributeFloats = 0;
    std::uint64_t corners = 0;
    while (std::getline(in, line)) {
        ++lineNumber;
        std::istringstream tokens(line);
        std::string keyword;
        tokens >> keyword;
        if (keyword == "f" || keyword == "l" || keyword == "p") {
            std::string token;
            while (tokens >> token) ++corners;
            continue;
        }
        if (keyword != "v" && keyword != "vt" && keyword != "vn") continue;
        std::string token;
        while (tokens >> token) {
            if (token[0] == '#') break;
            char* end = nullptr;
            const double value = std::strtod(token.c_str(), &end);
            const bool parsed = end != token.c_str() && *end == '\0';
            if (!parsed || !std::isfinite(value))
                invalid(path, "line " + std::to_string(lineNumber) + ": '" + keyword + "' value '" + token +
                                  "' is not a finite number");
            ++attributeFloats;
        }
    }
    // Floats as tinyobjloader stores them, then per face corner its index (12 bytes), a welded vertex
    // and its map entry (at most one each per corner) and the mesh index.
    const std::uint64_t bytes =
        attributeFloats * sizeof(float) + corners * (12 + sizeof(MeshVertex) + 64 + sizeof(std::uint32_t));
    reserveOrThrow(bytes, path.string() + ": an OBJ with " + std::to_string(attributeFloats) +
                              " attribute values and " + std::to_string(corners) + " face corners");
}

RawMesh readObj(const fs::path& path, bool requireUvs) {
    prescanObj(path);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = path.parent_path().string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path.string(), config)) {
        std::string message = reader.Error();
        while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back())))
            message.pop_back();
        invalid(path, "cannot parse OBJ: " + (message.empty() ? std::string("unknown error") : message));
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    requireFinite(path, attrib.vertices, "position");
    requireFinite(path, attrib.normals, "normal");
    requireFinite(path, attrib.texcoords, "texture coordinate");
    const auto positionCount = static_cast<int>(attrib.vertices.size() / 3);
    const auto normalCount = static_cast<int>(attrib.normals.size() / 3);
    const auto uvCount = static_cast<int>(attrib.texcoords.size() / 2);

    RawMesh raw;
    raw.mesh.name = path.string();
    bool allNormals = true;
    std::map<std::tuple<int, int, int>, std::uint32_t> unwelded;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        std::size_t offset = 0;
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            const std::size_t corners = shape.mesh.num_face_vertices[f];
            if (corners != 3)
                invalid(path, "face with " + std::to_string(corners) + " corners after triangulation");
            for (std::size_t k = 0; k < 3; ++k) {
                const tinyobj::index_t& index = shape.mesh.indices[offset + k];
                if (index.texcoord_index < 0) {
                    if (requireUvs) noTexCoords(path);
                    raw.missingUvs = true;
                }
                if (index.vertex_index < 0 || index.vertex_index >= positionCount ||
                    index.texcoord_index >= uvCount || index.normal_index >= normalCount) {
                    invalid(path, "face " + std::to_string(f) + " of '" + shape.name +
                                      "' has an index out of range");
                }
                if (index.normal_index < 0) allNormals = false;
                const auto key =
                    std::make_tuple(index.vertex_index, index.texcoord_index, index.normal_index);
                auto [it, inserted] =
                    unwelded.emplace(key, static_cast<std::uint32_t>(raw.mesh.vertices.size()));
                if (inserted) {
                    MeshVertex v;
                    const auto vi = static_cast<std::size_t>(index.vertex_index);
                    const auto ti = static_cast<std::size_t>(index.texcoord_index);
                    v.position = {attrib.vertices[3 * vi], attrib.vertices[3 * vi + 1],
                                  attrib.vertices[3 * vi + 2]};
                    if (index.texcoord_index >= 0)
                        v.uv = {attrib.texcoords[2 * ti], attrib.texcoords[2 * ti + 1]};
                    if (index.normal_index >= 0) {
                        const auto ni = static_cast<std::size_t>(index.normal_index);
                        v.normal = {attrib.normals[3 * ni], attrib.normals[3 * ni + 1],
                                    attrib.normals[3 * ni + 2]};
                    }
                    raw.mesh.vertices.push_back(v);
                }
                raw.mesh.indices.push_back(it->second);
            }
            offset += corners;
        }
    }
    // A file that mixes faces with and without normals gets computed normals everywhere: one rule per file.
    raw.source.assign(raw.mesh.vertices.size(), VertexSource{allNormals, false});
    return raw;
}

// --- glTF ---------------------------------------------------------------------------------------------

// Images are not needed for geometry: accept them without decoding.
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
               void*) {
    return true;
}

// Element `index` of one of the model's lists; tinygltf does not check the indices that refer to them, and a
// bad one is bad input, not std::out_of_range (found by fuzz_gltf, docs/fuzzing.md).
template <class T>
const T& element(const fs::path& path, const std::vector<T>& list, int index, const std::string& what) {
    if (index < 0 || static_cast<std::size_t>(index) >= list.size())
        invalid(path, what + " " + std::to_string(index) + " does not exist");
    return list[static_cast<std::size_t>(index)];
}

// Reads accessor `index` as `components` floats per element (normalised integers mapped as glTF says).
// `expectedCount`: the primitive's vertex count (its POSITION's), checked before anything is allocated.
std::vector<float> readAccessor(const fs::path& path, const tinygltf::Model& model, int index, int components,
                                const char* what, std::size_t expectedCount = SIZE_MAX) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
        invalid(path, std::string(what) + " accessor " + std::to_string(index) + " does not exist");
    }
    const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
    if (accessor.sparse.isSparse) {
        throw Error(ErrorKind::Unsupported,
                    path.string() + ": sparse accessors (" + what + ") are not supported");
    }
    if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type)) != components) {
        invalid(path, std::string(what) + " accessor " + std::to_string(index) + " has the wrong type");
    }
    const std::size_t count = accessor.count;
    if (expectedCount != SIZE_MAX && count != expectedCount)
        invalid(path, "a primitive's attributes have different counts");
    // Positions without a buffer view would all be 0: every triangle degenerate, refused later anyway, so
    // refused here before a count that costs nothing to write in JSON costs memory.
    if (accessor.bufferView < 0 && std::strcmp(what, "POSITION") == 0)
        invalid(path, "POSITION accessor " + std::to_string(index) + " of " + std::to_string(count) +
                          " elements has no buffer view (every position would be 0)");
    // The floats read here and a vertex per element later, against the budget before either exists:
    // an accessor without a buffer view (all zeros) can declare any count in a few bytes of JSON.
    reserveOrThrow(saturatingMultiply(count, static_cast<std::uint64_t>(components) * sizeof(float) +
                                                 sizeof(MeshVertex) + sizeof(VertexSource)),
                   path.string() + ": " + what + " accessor " + std::to_string(index) + " of " +
                       std::to_string(count) + " elements");
    if (accessor.bufferView < 0)
        return std::vector<float>(count * static_cast<std::size_t>(components), 0.0f);  // zeros (the spec)
    const tinygltf::BufferView& view = element(path, model.bufferViews, accessor.bufferView, "buffer view");
    const tinygltf::Buffer& buffer = element(path, model.buffers, view.buffer, "buffer");
    const int componentSize =
        tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(accessor.componentType));
    if (componentSize <= 0) invalid(path, std::string(what) + " accessor has an invalid component type");
    const std::size_t elementSize = static_cast<std::size_t>(componentSize * components);
    const std::size_t stride = view.byteStride ? view.byteStride : elementSize;
    const std::size_t start = view.byteOffset + accessor.byteOffset;
    // Saturating: a hostile count must not wrap around into range.
    const std::uint64_t span = count > 0 ? saturatingMultiply(stride, count - 1) + elementSize : 0;
    if (count > 0 &&
        (span > buffer.data.size() || start > buffer.data.size() - span ||
         accessor.byteOffset > view.byteLength || span > view.byteLength - accessor.byteOffset)) {
        invalid(path, std::string(what) + " accessor " + std::to_string(index) + " runs past its buffer");
    }
    std::vector<float> out(count * static_cast<std::size_t>(components), 0.0f);
    for (std::size_t e = 0; e < count; ++e) {
        const unsigned char* element = buffer.data.data() + start + e * stride;
        for (int c = 0; c < components; ++c) {
            const unsigned char* p = element + c * componentSize;
            float value = 0.0f;
            switch (accessor.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT:
                    std::memcpy(&value, p, 4);
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                    value = static_cast<float>(*p) / 255.0f;
                    break;
                case TINYGLTF_COMPONENT_TYPE_BYTE:
                    value = std::max(static_cast<float>(static_cast<signed char>(*p)) / 127.0f, -1.0f);
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    std::uint16_t v;
                    std::memcpy(&v, p, 2);
                    value = static_cast<float>(v) / 65535.0f;
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_SHORT: {
                    std::int16_t v;
                    std::memcpy(&v, p, 2);
                    value = std::max(static_cast<float>(v) / 32767.0f, -1.0f);
                    break;
                }
                default:
                    throw Error(ErrorKind::Unsupported, path.string() + ": " + what +
                                                            " accessor has an unsupported component type " +
                                                            std::to_string(accessor.componentType));
            }
            out[e * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)] = value;
        }
    }
    requireFinite(path, out, what);
    return out;
}

std::vector<std::uint32_t> readIndices(const fs::path& path, const tinygltf::Model& model, int index) {
    const tinygltf::Accessor& accessor = element(path, model.accessors, index, "index accessor");
    if (accessor.type != TINYGLTF_TYPE_SCALAR || accessor.bufferView < 0 || accessor.sparse.isSparse) {
        invalid(path, "index accessor " + std::to_string(index) + " is not a plain scalar accessor");
    }
    const tinygltf::BufferView& view = element(path, model.bufferViews, accessor.bufferView, "buffer view");
    const tinygltf::Buffer& buffer = element(path, model.buffers, view.buffer, "buffer");
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(accessor.componentType));
    if (size != 1 && size != 2 && size != 4) invalid(path, "index accessor has an invalid component type");
    const std::size_t stride = view.byteStride ? view.byteStride : static_cast<std::size_t>(size);
    const std::size_t start = view.byteOffset + accessor.byteOffset;
    // Saturating: a hostile count must not wrap around into range.
    const std::uint64_t span =
        accessor.count > 0 ? saturatingMultiply(stride, accessor.count - 1) + static_cast<std::size_t>(size)
                           : 0;
    if (accessor.count > 0 && (span > buffer.data.size() || start > buffer.data.size() - span)) {
        invalid(path, "index accessor " + std::to_string(index) + " runs past its buffer");
    }
    reserveOrThrow(saturatingMultiply(accessor.count, 2 * sizeof(std::uint32_t)),
                   path.string() + ": index accessor " + std::to_string(index) + " of " +
                       std::to_string(accessor.count) + " elements");
    std::vector<std::uint32_t> out(accessor.count);
    for (std::size_t e = 0; e < accessor.count; ++e) {
        const unsigned char* p = buffer.data.data() + start + e * stride;
        if (size == 1) {
            out[e] = *p;
        } else if (size == 2) {
            std::uint16_t v;
            std::memcpy(&v, p, 2);
            out[e] = v;
        } else {
            std::memcpy(&out[e], p, 4);
        }
    }
    return out;
}

glm::dmat4 localMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());  // column-major, as glTF
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3) m = glm::translate(m, glm::make_vec3(node.translation.data()));
    if (node.rotation.size() == 4) {
        const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1],
                           node.rotation[2]);  // w, x, y, z
        m *= glm::mat4_cast(q);
    }
    if (node.scale.size() == 3) m = glm::scale(m, glm::make_vec3(node.scale.data()));
    return m;
}

void appendPrimitive(const fs::path& path, const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                     const glm::dmat4& world, bool requireUvs, RawMesh& raw, MeshRepairReport& report) {
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        ++report.skippedPrimitives;
        return;
    }
    const auto attribute = [&](const char* name) {
        const auto it = primitive.attributes.find(name);
        return it == primitive.attributes.end() ? -1 : it->second;
    };
    if (attribute("POSITION") < 0) invalid(path, "a primitive has no POSITION");
    const bool hasUvs = attribute("TEXCOORD_0") >= 0;
    if (!hasUvs && requireUvs) noTexCoords(path);
    const std::vector<float> positions = readAccessor(path, model, attribute("POSITION"), 3, "POSITION");
    const std::size_t count = positions.size() / 3;
    const std::vector<float> uvs =
        hasUvs ? readAccessor(path, model, attribute("TEXCOORD_0"), 2, "TEXCOORD_0", count)
               : std::vector<float>(2 * count, 0.0f);
    raw.missingUvs = raw.missingUvs || !hasUvs;
    const bool hasNormals = attribute("NORMAL") >= 0;
    const bool hasTangents = attribute("TANGENT") >= 0;
    const std::vector<float> normals =
        hasNormals ? readAccessor(path, model, attribute("NORMAL"), 3, "NORMAL", count)
                   : std::vector<float>();
    const std::vector<float> tangents =
        hasTangents ? readAccessor(path, model, attribute("TANGENT"), 4, "TANGENT", count)
                    : std::vector<float>();
    if (uvs.size() / 2 != count || (hasNormals && normals.size() / 3 != count) ||
        (hasTangents && tangents.size() / 4 != count)) {
        invalid(path, "a primitive's attributes have different counts");
    }

    const glm::dmat3 linear(world);
    const glm::dmat3 normalMatrix = glm::inverseTranspose(linear);
    const bool mirrored = glm::determinant(linear) < 0.0;
    const auto base = static_cast<std::uint32_t>(raw.mesh.vertices.size());
    for (std::size_t i = 0; i < count; ++i) {
        MeshVertex v;
        v.position =
            glm::vec3(world * glm::dvec4(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2], 1.0));
        v.uv = {uvs[2 * i], 1.0f - uvs[2 * i + 1]};  // glTF's v runs down the image, Strata's up
        if (hasNormals) {
            const glm::dvec3 n =
                normalMatrix * glm::dvec3(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
            const double len = glm::length(n);
            v.normal = len > 0.0 ? glm::vec3(n / len) : glm::vec3(0.0f);  // zero: repaired later
        }
        if (hasTangents) {
            const glm::dvec3 t =
                linear * glm::dvec3(tangents[4 * i], tangents[4 * i + 1], tangents[4 * i + 2]);
            const float w = (tangents[4 * i + 3] < 0.0f) != mirrored ? -1.0f : 1.0f;
            v.tangent = glm::vec4(glm::vec3(t), w);
        }
        raw.mesh.vertices.push_back(v);
    }
    raw.source.resize(raw.mesh.vertices.size(), VertexSource{hasNormals, hasTangents});

    std::vector<std::uint32_t> indices;
    if (primitive.indices >= 0) {
        indices = readIndices(path, model, primitive.indices);
    } else {
        indices.resize(count);
        for (std::size_t i = 0; i < count; ++i) indices[i] = static_cast<std::uint32_t>(i);
    }
    for (std::uint32_t index : indices) {
        if (index >= count)
            invalid(path, "index " + std::to_string(index) + " is out of range in a primitive");
    }
    std::vector<std::uint32_t> triangles;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        triangles.assign(indices.begin(), indices.end() - static_cast<std::ptrdiff_t>(indices.size() % 3));
    } else {
        for (std::size_t k = 2; k < indices.size(); ++k) {
            if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
                triangles.insert(triangles.end(), {indices[0], indices[k - 1], indices[k]});
            } else if (k % 2 == 0) {
                triangles.insert(triangles.end(), {indices[k - 2], indices[k - 1], indices[k]});
            } else {
                triangles.insert(triangles.end(), {indices[k - 1], indices[k - 2], indices[k]});
            }
        }
    }
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        // A mirroring transform turns counter-clockwise into clockwise: swap two corners back.
        raw.mesh.indices.push_back(base + triangles[t]);
        raw.mesh.indices.push_back(base + triangles[t + (mirrored ? 2 : 1)]);
        raw.mesh.indices.push_back(base + triangles[t + (mirrored ? 1 : 2)]);
    }
}

void appendNode(const fs::path& path, const tinygltf::Model& model, int nodeIndex, const glm::dmat4& parent,
                bool requireUvs, std::set<int>& visiting, RawMesh& raw, MeshRepairReport& report) {
    if (nodeIndex < 0 || static_cast<std::size_t>(nodeIndex) >= model.nodes.size()) {
        invalid(path, "node " + std::to_string(nodeIndex) + " does not exist");
    }
    if (!visiting.insert(nodeIndex).second)
        invalid(path, "node " + std::to_string(nodeIndex) + " is its own ancestor");
    const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(nodeIndex)];
    const glm::dmat4 world = parent * localMatrix(node);
    if (node.mesh >= 0) {
        for (const tinygltf::Primitive& primitive :
             element(path, model.meshes, node.mesh, "mesh").primitives) {
            appendPrimitive(path, model, primitive, world, requireUvs, raw, report);
        }
    }
    for (int child : node.children) appendNode(path, model, child, world, requireUvs, visiting, raw, report);
    visiting.erase(nodeIndex);
}

RawMesh readGltf(const fs::path& path, bool binary, bool requireUvs, MeshRepairReport& report) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skipImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                           : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
    if (!ok) {
        while (!err.empty() && std::isspace(static_cast<unsigned char>(err.back()))) err.pop_back();
        invalid(path, "cannot parse glTF: " + (err.empty() ? std::string("unknown error") : err));
    }
    RawMesh raw;
    raw.mesh.name = path.string();
    if (model.scenes.empty()) {
        for (const tinygltf::Mesh& mesh : model.meshes) {
            for (const tinygltf::Primitive& primitive : mesh.primitives) {
                appendPrimitive(path, model, primitive, glm::dmat4(1.0), requireUvs, raw, report);
            }
        }
    } else {
        const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (static_cast<std::size_t>(sceneIndex) >= model.scenes.size()) {
            invalid(path, "default scene " + std::to_string(sceneIndex) + " does not exist");
        }
        std::set<int> visiting;
        for (int node : model.scenes[static_cast<std::size_t>(sceneIndex)].nodes) {
            appendNode(path, model, node, glm::dmat4(1.0), requireUvs, visiting, raw, report);
        }
    }
    return raw;
}

// --- OFF ----------------------------------------------------------------------------------------------

// Object File Format (Geomview): "OFF" (optionally with the counts on the same line), then "V F E", V lines
// "x y z [...]" and F lines "n i0 .. i(n-1) [colour]"; '#' starts a comment. Polygons become fans. The
// variants that add per-vertex fields (COFF, NOFF, STOFF, 4OFF, nOFF, binary OFF) are refused by name
// rather than misread.
RawMesh readOff(const fs::path& path, bool requireUvs) {
    if (requireUvs) noTexCoords(path);
    std::ifstream in(path, std::ios::binary);
    std::vector<std::string> lines;
    std::vector<std::size_t> lineNumbers;
    std::string line;
    for (std::size_t number = 1; std::getline(in, line); ++number) {
        const std::size_t hash = line.find('#');
        if (hash != std::string::npos) line.erase(hash);
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        lines.push_back(line);
        lineNumbers.push_back(number);
    }
    std::size_t next = 0;
    auto where = [&](std::size_t i) {
        return "line " + std::to_string(i < lineNumbers.size() ? lineNumbers[i] : 0);
    };
    if (lines.empty()) invalid(path, "cannot parse OFF: the file is empty");
    std::istringstream header(lines[next]);
    std::string keyword;
    header >> keyword;
    if (keyword != "OFF") {
        if (keyword.size() > 3 && keyword.substr(keyword.size() - 3) == "OFF")
            throw Error(ErrorKind::Unsupported, path.string() + ": the OFF variant '" + keyword +
                                                    "' is not supported (plain OFF is)");
        invalid(path, "cannot parse OFF: the first line is not \"OFF\"");
    }
    long long vertexCount = -1, faceCount = -1, edgeCount = 0;
    if (!(header >> vertexCount)) {
        if (++next >= lines.size()) invalid(path, "cannot parse OFF: no counts line");
        header = std::istringstream(lines[next]);
        header >> vertexCount;
    }
    if (!(header >> faceCount) || vertexCount < 0 || faceCount < 0)
        invalid(path, "cannot parse OFF: " + where(next) + ": expected the counts \"vertices faces edges\"");
    (void)(header >> edgeCount);
    ++next;
    // Refuse counts the file cannot hold before allocating for them.
    if (static_cast<unsigned long long>(vertexCount) + static_cast<unsigned long long>(faceCount) >
        lines.size() - next)
        invalid(path, "cannot parse OFF: the counts say " + std::to_string(vertexCount) + " vertices and " +
                          std::to_string(faceCount) + " faces, but the file has " +
                          std::to_string(lines.size() - next) + " lines after them");

    RawMesh raw;
    raw.mesh.name = path.string();
    raw.missingUvs = true;
    raw.mesh.vertices.resize(static_cast<std::size_t>(vertexCount));
    std::vector<float> positions(3 * static_cast<std::size_t>(vertexCount));
    for (std::size_t v = 0; v < static_cast<std::size_t>(vertexCount); ++v, ++next) {
        std::istringstream fields(lines[next]);
        double x = 0, y = 0, z = 0;
        if (!(fields >> x >> y >> z))
            invalid(path, "cannot parse OFF: " + where(next) + ": expected \"x y z\"");
        raw.mesh.vertices[v].position = glm::vec3(glm::dvec3(x, y, z));
        positions[3 * v] = float(x);
        positions[3 * v + 1] = float(y);
        positions[3 * v + 2] = float(z);
    }
    requireFinite(path, positions, "position");
    for (long long f = 0; f < faceCount; ++f, ++next) {
        std::istringstream fields(lines[next]);
        long long corners = 0;
        if (!(fields >> corners) || corners < 3)
            invalid(path, "cannot parse OFF: " + where(next) + ": a face needs a corner count of at least 3");
        std::vector<std::uint32_t> polygon;
        for (long long k = 0; k < corners; ++k) {
            long long index = -1;
            if (!(fields >> index))
                invalid(path, "cannot parse OFF: " + where(next) + ": the face has fewer than " +
                                  std::to_string(corners) + " indices");
            if (index < 0 || index >= vertexCount)
                invalid(path, "face " + std::to_string(f) + " has an index out of range (" +
                                  std::to_string(index) + ")");
            polygon.push_back(static_cast<std::uint32_t>(index));
        }
        for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
            raw.mesh.indices.push_back(polygon[0]);
            raw.mesh.indices.push_back(polygon[k]);
            raw.mesh.indices.push_back(polygon[k + 1]);
        }
    }
    raw.source.assign(raw.mesh.vertices.size(), VertexSource{false, false});
    return raw;
}

// Planar uvs for a file without texture coordinates (requireUvs = false): the positions projected onto the
// plane of the bounds' two largest extents, scaled by the larger into [0, 1]. Only enough of a texture space
// for the repairs and tangents to be well defined; not one to map a relief with.
void assignPlanarUvs(Mesh& mesh) {
    const Bounds bounds = meshBounds(mesh);
    const glm::vec3 extent = bounds.max - bounds.min;
    int drop = 0;  // the axis of the smallest extent
    for (int a = 1; a < 3; ++a)
        if (extent[a] < extent[drop]) drop = a;
    const int u = (drop + 1) % 3, v = (drop + 2) % 3;
    const float scale = std::max(extent[u], extent[v]);
    for (MeshVertex& vertex : mesh.vertices) {
        const glm::vec3 p = vertex.position - bounds.min;
        vertex.uv = scale > 0.0f ? glm::vec2(p[u], p[v]) / scale : glm::vec2(0.0f);
    }
}

}  // namespace

Mesh loadMesh(const fs::path& path, const MeshLoadOptions& options) {
    MeshRepairReport report;
    return loadMesh(path, options, report);
}

Mesh loadMesh(const fs::path& path, const MeshLoadOptions& options, MeshRepairReport& report) {
    report = {};
    const std::string ext = lowerCaseExtension(path);
    if (ext != ".obj" && ext != ".gltf" && ext != ".glb" && ext != ".off") {
        throw Error(ErrorKind::Unsupported, path.string() + ": unsupported mesh format '" + ext +
                                                "' (Strata reads .obj, .gltf, .glb and .off)");
    }
    checkReadableFile(path);
    if (!std::ifstream(path, std::ios::binary).good()) {
        throw Error(ErrorKind::Io, path.string() + ": cannot be read");
    }

    RawMesh raw = ext == ".obj"   ? readObj(path, options.requireUvs)
                  : ext == ".off" ? readOff(path, options.requireUvs)
                                  : readGltf(path, ext == ".glb", options.requireUvs, report);
    // One rule per file: if any face had no uvs, every vertex gets planar ones.
    // (A non-finite position makes them non-finite too; repairMesh names the position first.)
    if (raw.missingUvs) assignPlanarUvs(raw.mesh);
    const MeshRepairReport skipped = report;
    std::vector<std::uint32_t> remap;
    report = repairMesh(raw.mesh, &remap);
    report.skippedPrimitives = skipped.skippedPrimitives;
    std::vector<VertexSource> source(raw.mesh.vertices.size());
    for (std::size_t i = 0; i < remap.size(); ++i) {
        if (remap[i] != kRemovedVertex) source[remap[i]] = raw.source[i];
    }
    Mesh& mesh = raw.mesh;

    // Normals: computed where the file has none (or the caller says so), repaired where they are zero.
    const bool allNormals =
        std::all_of(source.begin(), source.end(), [](const VertexSource& s) { return s.normal; });
    if (!allNormals || options.recomputeNormals) {
        Mesh smooth = mesh;
        computeSmoothNormals(smooth);
        for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
            if (!source[i].normal || options.recomputeNormals)
                mesh.vertices[i].normal = smooth.vertices[i].normal;
        }
        report.normalsComputed = true;
    }
    std::vector<std::size_t> zeroNormals;
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const float len = glm::length(mesh.vertices[i].normal);
        if (len > 0.0f) {
            mesh.vertices[i].normal /= len;
        } else {
            zeroNormals.push_back(i);
        }
    }
    if (!zeroNormals.empty()) {
        Mesh smooth = mesh;
        computeSmoothNormals(smooth);
        for (std::size_t i : zeroNormals) mesh.vertices[i].normal = smooth.vertices[i].normal;
        report.normalsRepaired = zeroNormals.size();
    }

    // Tangents: the file's where every vertex has a usable one, else all computed (one rule per mesh).
    bool useFileTangents =
        !options.recomputeTangents &&
        std::all_of(source.begin(), source.end(), [](const VertexSource& s) { return s.tangent; });
    if (useFileTangents) {
        for (MeshVertex& v : mesh.vertices) {
            const glm::vec3 t = glm::vec3(v.tangent) - v.normal * glm::dot(v.normal, glm::vec3(v.tangent));
            const float len = glm::length(t);
            // A tangent (nearly) parallel to the normal says nothing about the texture direction.
            if (!(len > 1e-4f)) {
                useFileTangents = false;
                break;
            }
            v.tangent = glm::vec4(t / len, v.tangent.w);
        }
    }
    if (!useFileTangents) {
        report.tangentsRepaired = computeTangents(mesh);
        report.tangentsComputed = true;
    }
    return mesh;
}

}  // namespace strata
