#include "strata/gl/relief_renderer.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/gl/gl_error.h"
#include "strata/gl/program.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/relief/cone_map.h"
#include "strata/relief/max_mip.h"
#include "strata/relief/texture_set.h"

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>

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

// Per vertex, the area-weighted mean over its triangles of |dP/du| and |dP/dv| (the columns of the
// triangle's uv -> position Jacobian). 1 where no triangle around the vertex has a usable uv mapping.
std::vector<glm::dvec2> uvLengths(const Mesh& mesh) {
    std::vector<glm::dvec2> sum(mesh.vertices.size(), glm::dvec2(0.0));
    std::vector<double> weight(mesh.vertices.size(), 0.0);
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const std::uint32_t ids[3] = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
        const glm::dvec3 p0(mesh.vertices[ids[0]].position);
        const glm::dvec3 e1 = glm::dvec3(mesh.vertices[ids[1]].position) - p0;
        const glm::dvec3 e2 = glm::dvec3(mesh.vertices[ids[2]].position) - p0;
        const glm::dvec2 t0(mesh.vertices[ids[0]].uv);
        const glm::dvec2 d1 = glm::dvec2(mesh.vertices[ids[1]].uv) - t0;
        const glm::dvec2 d2 = glm::dvec2(mesh.vertices[ids[2]].uv) - t0;
        const double det = d1.x * d2.y - d2.x * d1.y;
        const double area = 0.5 * glm::length(glm::cross(e1, e2));
        if (!(std::abs(det) > 1e-20) || !(area > 0.0)) continue;
        const glm::dvec3 dPdu = (e1 * d2.y - e2 * d1.y) / det;
        const glm::dvec3 dPdv = (e2 * d1.x - e1 * d2.x) / det;
        const glm::dvec2 lengths(glm::length(dPdu), glm::length(dPdv));
        if (!std::isfinite(lengths.x) || !std::isfinite(lengths.y)) continue;
        for (const std::uint32_t id : ids) {
            sum[id] += area * lengths;
            weight[id] += area;
        }
    }
    for (std::size_t v = 0; v < sum.size(); ++v)
        sum[v] = weight[v] > 0.0 ? sum[v] / weight[v] : glm::dvec2(1.0);
    return sum;
}

// 16x anisotropic filtering where the driver has it (core in 4.6, else ARB/EXT_texture_filter_anisotropic).
void setAnisotropy(GLuint texture) {
    if (epoxy_gl_version() < 46 && !epoxy_has_gl_extension("GL_ARB_texture_filter_anisotropic") &&
        !epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic")) {
        return;
    }
    GLfloat maximum = 1.0f;
    glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &maximum);
    glTextureParameterf(texture, GL_TEXTURE_MAX_ANISOTROPY, std::min(16.0f, maximum));
}

int mipLevels(int width, int height) {
    int levels = 1;
    for (int size = std::max(width, height); size > 1; size /= 2) ++levels;
    return levels;
}

// A tiling texture with full mipmaps, trilinear + anisotropic filtering, GL_REPEAT. `rows` holds the
// texels top row first (CONVENTIONS §1); they are uploaded bottom row first so that t = v.
template <typename T>
GLuint makeTexture(GLenum internalFormat, int width, int height, GLenum format, GLenum type,
                   const std::vector<T>& rows, int components) {
    GLuint texture = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, mipLevels(width, height), internalFormat, width, height);
    std::vector<T> flipped(rows.size());
    const std::size_t rowSize = static_cast<std::size_t>(width) * components;
    for (int y = 0; y < height; ++y) {
        std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(rowSize * y), rowSize,
                    flipped.begin() + static_cast<std::ptrdiff_t>(rowSize * (height - 1 - y)));
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture, 0, 0, 0, width, height, format, type, flipped.data());
    glGenerateTextureMipmap(texture);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    setAnisotropy(texture);
    return texture;
}

std::uint16_t toUnorm16(float value) {
    return static_cast<std::uint16_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 65535.0f));
}

std::uint8_t toUnorm8(float value) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f));
}

float srgbToLinear(double c) {
    c = std::clamp(c, 0.0, 1.0);
    return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

float linearToSrgb(float c) {
    const double x = std::clamp(static_cast<double>(c), 0.0, 1.0);
    return static_cast<float>(x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055);
}

glm::mat4 toFloat(const glm::dmat4& m) {
    return glm::mat4(m);
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// GpuMesh

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

// ---------------------------------------------------------------------------------------------------------
// GpuMaterial

void GpuMaterial::release() {
    if (mRelief != 0) glDeleteTextures(1, &mRelief);
    if (mColor != 0) glDeleteTextures(1, &mColor);
    if (mComposedAo != 0) glDeleteTextures(1, &mComposedAo);
    if (mMaxMip != 0) glDeleteTextures(1, &mMaxMip);
    if (mCone != 0) glDeleteTextures(1, &mCone);
    for (const GpuLayer& layer : mLayers) {
        glDeleteTextures(1, &layer.texture);
        if (layer.color != 0) glDeleteTextures(1, &layer.color);
    }
    mRelief = mColor = mComposedAo = mMaxMip = mCone = 0;
    mConeDepth = Image();
    mLayers.clear();
}

GpuMaterial::~GpuMaterial() {
    release();
}

GpuMaterial::GpuMaterial(GpuMaterial&& other) noexcept {
    *this = std::move(other);
}

GpuMaterial& GpuMaterial::operator=(GpuMaterial&& other) noexcept {
    if (this != &other) {
        release();
        mRelief = std::exchange(other.mRelief, 0);
        mColor = std::exchange(other.mColor, 0);
        mComposedAo = std::exchange(other.mComposedAo, 0);
        mMaxMip = std::exchange(other.mMaxMip, 0);
        mMaxMipLevels = other.mMaxMipLevels;
        mConeDepth = std::exchange(other.mConeDepth, Image());
        mCone = std::exchange(other.mCone, 0);
        mConeMaxRatio = other.mConeMaxRatio;
        mDualDepth = other.mDualDepth;
        mLayers = std::exchange(other.mLayers, {});
        mNormalMode = other.mNormalMode;
        mLiveAo = other.mLiveAo;
        mColorLayer = other.mColorLayer;
        mDepthScale = other.mDepthScale;
        mAoDepthScale = other.mAoDepthScale;
        mHasAo = other.mHasAo;
        mHasColor = other.mHasColor;
        mWidth = other.mWidth;
        mHeight = other.mHeight;
    }
    return *this;
}

namespace {

// Colour: sRGB-encoded, decoded to linear by the texture unit (and filtered in linear). 1x1 white if empty.
GLuint makeColorTexture(const Image& color) {
    const int colorWidth = color.empty() ? 1 : color.width();
    const int colorHeight = color.empty() ? 1 : color.height();
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(colorWidth) * colorHeight * 4, 255);
    if (!color.empty()) {
        for (int y = 0; y < colorHeight; ++y) {
            for (int x = 0; x < colorWidth; ++x) {
                const std::size_t i = (static_cast<std::size_t>(y) * colorWidth + x) * 4;
                for (int c = 0; c < 3; ++c) rgba[i + c] = toUnorm8(color.at(x, y, c));
            }
        }
    }
    return makeTexture(GL_SRGB8_ALPHA8, colorWidth, colorHeight, GL_RGBA, GL_UNSIGNED_BYTE, rgba, 4);
}

// The packed texture (CONVENTIONS §5) as RGBA16 with mipmaps.
GLuint makePackedTexture(const ReliefTexture& texture) {
    const Image packed = packRelief(texture);
    std::vector<std::uint16_t> texels(packed.pixels().size());
    std::transform(packed.pixels().begin(), packed.pixels().end(), texels.begin(), toUnorm16);
    return makeTexture(GL_RGBA16, packed.width(), packed.height(), GL_RGBA, GL_UNSIGNED_SHORT, texels, 4);
}

bool isPowerOfTwo(int n) {
    return n > 0 && (n & (n - 1)) == 0;
}

// The maximum mipmap (strata/relief/max_mip.h, already in GL's row order) as R16 with explicit levels.
GLuint makeMaxMip(const Image& depth, int* levelCount) {
    const std::vector<Image> levels = maxMipPyramid(depth);
    GLuint texture = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, static_cast<GLsizei>(levels.size()), GL_R16, depth.width(), depth.height());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (std::size_t k = 0; k < levels.size(); ++k) {
        std::vector<std::uint16_t> texels(levels[k].pixels().size());
        std::transform(levels[k].pixels().begin(), levels[k].pixels().end(), texels.begin(), toUnorm16);
        glTextureSubImage2D(texture, static_cast<GLint>(k), 0, 0, levels[k].width(), levels[k].height(),
                            GL_RED, GL_UNSIGNED_SHORT, texels.data());
    }
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    *levelCount = static_cast<int>(levels.size());
    return texture;
}

// The depth as the packed texture holds it (16-bit unorm), so that the cone map describes the very
// height field the shader intersects.
Image uploadedDepth(const Image& depth) {
    Image result = depth;
    for (float& d : result.pixels()) d = static_cast<float>(toUnorm16(d)) / 65535.0f;
    return result;
}

// The cone map texture (cone.glsl): RG16 per cell, packConeMap's frame and values.
GLuint makeConeMap(const Image& depth, double* maxRatio) {
    const PackedConeMap packed = packConeMap(depth);
    const int width = depth.width(), height = depth.height();
    std::vector<std::uint16_t> texels(packed.texels.pixels().size());
    std::transform(packed.texels.pixels().begin(), packed.texels.pixels().end(), texels.begin(), toUnorm16);
    GLuint texture = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, GL_RG16, width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture, 0, 0, 0, width, height, GL_RG, GL_UNSIGNED_SHORT, texels.data());
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    *maxRatio = packed.maxRatio;
    return texture;
}

}  // namespace

GpuMaterial uploadMaterial(const ReliefTexture& texture, double aoDepthScale) {
    if (texture.depth.empty() || texture.depth.channels() != 1) {
        throw Error(ErrorKind::InvalidInput,
                    "uploadMaterial: the relief texture needs a 1-channel depth map");
    }
    if (texture.normal.empty() || texture.normal.channels() != 3) {
        throw Error(ErrorKind::InvalidInput,
                    "uploadMaterial: the relief texture needs a 3-channel normal map");
    }
    if (!texture.color.empty() && texture.color.channels() < 3) {
        throw Error(ErrorKind::InvalidInput, "uploadMaterial: the colour map has " +
                                                 std::to_string(texture.color.channels()) +
                                                 " channels, need 3");
    }
    if (!texture.ao.empty() && texture.ao.channels() != 1) {
        throw Error(ErrorKind::InvalidInput, "uploadMaterial: the AO map must have 1 channel");
    }
    if (!(aoDepthScale > 0.0 && std::isfinite(aoDepthScale))) {
        throw Error(ErrorKind::InvalidInput,
                    "uploadMaterial: AO depth scale must be positive, got " + formatNumber(aoDepthScale));
    }
    if (!(texture.depthScale > 0.0 && std::isfinite(texture.depthScale))) {
        throw Error(ErrorKind::InvalidInput,
                    "uploadMaterial: depth scale must be positive, got " + formatNumber(texture.depthScale));
    }
    GpuMaterial result;
    // CONVENTIONS §5 layout, 16 bits per channel (the packed file's precision).
    result.mRelief = makePackedTexture(texture);
    result.mWidth = texture.depth.width();
    result.mHeight = texture.depth.height();
    if (isPowerOfTwo(result.mWidth) && isPowerOfTwo(result.mHeight))
        result.mMaxMip = makeMaxMip(texture.depth, &result.mMaxMipLevels);

    result.mConeDepth = uploadedDepth(texture.depth);

    const Image& color = texture.color;
    result.mColor = makeColorTexture(color);
    result.mDepthScale = texture.depthScale;
    result.mAoDepthScale = aoDepthScale;
    result.mHasAo = !texture.ao.empty();
    result.mHasColor = !color.empty();
    checkGl("uploadMaterial");
    return result;
}

unsigned GpuMaterial::coneTexture() const {
    if (mCone == 0 && !mConeDepth.empty()) {
        mCone = makeConeMap(mConeDepth, &mConeMaxRatio);
        checkGl("cone map");
        mConeDepth = Image();  // no longer needed: the texture holds all that the cone technique reads
    }
    return mCone;
}

namespace {

[[noreturn]] void invalidLive(const std::string& message) {
    throw Error(ErrorKind::InvalidInput, "uploadLiveMaterial: " + message);
}

std::string liveLayerName(std::span<const CompositionLayer> layers, std::size_t i) {
    const std::string index = "layers[" + std::to_string(i) + "]";
    return layers[i].label.empty() ? index : layers[i].label;
}

}  // namespace

GpuMaterial uploadLiveMaterial(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                               std::optional<MetaAoMode> ao, const AoParams& aoParams) {
    return uploadLiveMaterial(layers, compose, ao, aoParams, {});
}

GpuMaterial uploadLiveMaterial(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                               std::optional<MetaAoMode> ao, const AoParams& aoParams,
                               std::span<const Image> layerAo) {
    if (layers.size() > static_cast<std::size_t>(kMaxLiveLayers)) {
        invalidLive(std::to_string(layers.size()) + " layers; the live path takes at most " +
                    std::to_string(kMaxLiveLayers) + " (bake the material instead)");
    }
    // Validates the depth weights, tilings and depth scale like compose(), and gives each layer's AO bake.
    const std::vector<std::optional<AoParams>> layerAoParams =
        metaReliefLayerAoParams(layers, compose, aoParams);
    if (!layerAo.empty() && layerAo.size() != layers.size())
        invalidLive(std::to_string(layerAo.size()) + " layer AO maps for " + std::to_string(layers.size()) +
                    " layers");
    double sumNormal = 0.0;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const CompositionLayer& layer = layers[i];
        if (!std::isfinite(layer.weightNormal) || layer.weightNormal < 0.0)
            invalidLive(liveLayerName(layers, i) + ": weight_normal must be a finite number >= 0, got " +
                        formatNumber(layer.weightNormal));
        if (layer.texture.depth.empty() || layer.texture.depth.channels() != 1)
            invalidLive(liveLayerName(layers, i) + ": needs a 1-channel depth map");
        if (compose.normals == NormalMode::Paper &&
            (layer.texture.normal.channels() != 3 ||
             layer.texture.normal.width() != layer.texture.depth.width() ||
             layer.texture.normal.height() != layer.texture.depth.height()))
            invalidLive(liveLayerName(layers, i) +
                        ": paper normals need a 3-channel normal map of the depth map's size");
        sumNormal += layer.weightNormal;
    }
    if (compose.normals == NormalMode::Paper && !(sumNormal > 0.0))
        invalidLive("the normal weights (weight_normal) of the layers sum to 0: at least one must be > 0");
    if (compose.colorFrom >= static_cast<int>(layers.size()) ||
        (compose.colorFrom >= 0 && layers[static_cast<std::size_t>(compose.colorFrom)].texture.color.empty()))
        invalidLive("color_from = " + std::to_string(compose.colorFrom) +
                    " names no layer with a colour map");

    GpuMaterial result;
    result.mNormalMode = compose.normals;
    result.mLiveAo = ao;
    result.mColorLayer = compose.colorFrom;
    result.mDepthScale = compose.depthScale;
    result.mAoDepthScale = compose.depthScale;
    result.mHasAo = ao.has_value();
    result.mHasColor = compose.colorFrom >= 0;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const CompositionLayer& layer = layers[i];
        ReliefTexture packed;
        packed.depth = layer.texture.depth;
        packed.depthScale = compose.depthScale;
        GpuLayer gpu;
        // Consistent normals need each layer's depth gradient g: stored as normals derived at a scale S_L
        // of the layer's own, n = normalize(S_L g, 1), from which the shader recovers g = n.xy / (n.z S_L).
        // S_L makes the steepest |S_L g| 1/4: there a unit normal is within 3 % of linear in g, so filtering
        // the normals filters the gradient (as the baked composition does) instead of bending it, and 16 bits
        // still resolve g to 1e-4 of its range. Paper normals are the layer's own map.
        if (compose.normals == NormalMode::Consistent) {
            const Image gradient = depthGradient(layer.texture.depth);
            double steepest = 0.0;
            for (int y = 0; y < gradient.height(); ++y)
                for (int x = 0; x < gradient.width(); ++x)
                    steepest = std::max(steepest, std::hypot(static_cast<double>(gradient.at(x, y, 0)),
                                                             static_cast<double>(gradient.at(x, y, 1))));
            gpu.normalScale = steepest > 0.0 ? 0.25 / steepest : 1.0;
            // normalize(S_L g, 1), as normalsFromDepth at S_L, from the gradient already at hand.
            const auto scale = static_cast<float>(gpu.normalScale);
            packed.normal = Image(gradient.width(), gradient.height(), 3);
            for (int y = 0; y < gradient.height(); ++y)
                for (int x = 0; x < gradient.width(); ++x) {
                    const glm::vec3 n = glm::normalize(
                        glm::vec3(scale * gradient.at(x, y, 0), scale * gradient.at(x, y, 1), 1.0f));
                    for (int c = 0; c < 3; ++c) packed.normal.at(x, y, c) = n[c];
                }
        } else {
            packed.normal = layer.texture.normal;
        }
        if ((ao == MetaAoMode::Multiply || ao == MetaAoMode::Min) && layerAoParams[i]) {
            if (layerAo.empty()) {
                packed.ao = bakeAo(layer.texture.depth, *layerAoParams[i]);
            } else {
                const Image& map = layerAo[i];
                if (map.channels() != 1 || map.width() != layer.texture.depth.width() ||
                    map.height() != layer.texture.depth.height())
                    invalidLive(liveLayerName(layers, i) +
                                ": its AO map is not a 1-channel map of its depth's size");
                packed.ao = map;
            }
            gpu.aoDepthScale = layerAoParams[i]->depthScale;
        }
        gpu.texture = makePackedTexture(packed);
        if (static_cast<int>(i) == compose.colorFrom) gpu.color = makeColorTexture(layer.texture.color);
        gpu.tiling = layer.tiling;
        gpu.weightDepth = layer.weightDepth;
        gpu.weightNormal = layer.weightNormal;
        gpu.width = layer.texture.depth.width();
        gpu.height = layer.texture.depth.height();
        const auto [lowest, highest] =
            std::minmax_element(layer.texture.depth.pixels().begin(), layer.texture.depth.pixels().end());
        gpu.depthMin = toUnorm16(*lowest) / 65535.0;
        gpu.depthMax = toUnorm16(*highest) / 65535.0;
        result.mLayers.push_back(gpu);
    }
    result.mColor = compose.colorFrom >= 0 ? 0 : makeColorTexture(Image());
    result.mWidth = result.mLayers.front().width;
    result.mHeight = result.mLayers.front().height;
    checkGl("uploadLiveMaterial");
    return result;
}

GpuMaterial uploadDualDepth(const DualDepthTexture& texture) {
    const int width = texture.front.width();
    const int height = texture.front.height();
    const auto sameSize = [&](const Image& image, int channels) {
        return image.channels() == channels && image.width() == width && image.height() == height;
    };
    if (texture.front.empty() || !sameSize(texture.front, 1) || !sameSize(texture.back, 1) ||
        !sameSize(texture.normal, 3)) {
        throw Error(
            ErrorKind::InvalidInput,
            "uploadDualDepth: front and back must be 1-channel maps and normal a 3-channel map, all of "
            "one size");
    }
    if (!(std::isfinite(texture.depthScale) && texture.depthScale > 0.0)) {
        throw Error(ErrorKind::InvalidInput,
                    "uploadDualDepth: depth scale must be > 0, got " + formatNumber(texture.depthScale));
    }
    std::vector<std::uint16_t> texels(static_cast<std::size_t>(width) * height * 4);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::uint16_t* texel = texels.data() + (static_cast<std::size_t>(y) * width + x) * 4;
            texel[0] = toUnorm16(texture.normal.at(x, y, 0) * 0.5f + 0.5f);
            texel[1] = toUnorm16(texture.normal.at(x, y, 1) * 0.5f + 0.5f);
            texel[2] = toUnorm16(texture.front.at(x, y));
            texel[3] = toUnorm16(texture.back.at(x, y));
        }
    }
    GpuMaterial result;
    result.mRelief = makeTexture(GL_RGBA16, width, height, GL_RGBA, GL_UNSIGNED_SHORT, texels, 4);
    result.mColor = makeColorTexture(Image());
    result.mDepthScale = texture.depthScale;
    result.mAoDepthScale = texture.depthScale;
    result.mWidth = width;
    result.mHeight = height;
    result.mDualDepth = true;
    checkGl("uploadDualDepth");
    return result;
}

void GpuMaterial::setLayer(int index, double tiling, double weightDepth, double weightNormal) {
    const std::string name = "GpuMaterial::setLayer: layers[" + std::to_string(index) + "]";
    if (index < 0 || index >= static_cast<int>(mLayers.size()))
        throw Error(ErrorKind::InvalidInput,
                    name + ": no such layer (" + std::to_string(mLayers.size()) + ")");
    if (!(std::isfinite(tiling) && tiling > 0.0))
        throw Error(ErrorKind::InvalidInput, name + ": tiling must be > 0, got " + formatNumber(tiling));
    if (!(std::isfinite(weightDepth) && weightDepth >= 0.0 && std::isfinite(weightNormal) &&
          weightNormal >= 0.0))
        throw Error(ErrorKind::InvalidInput, name + ": weights must be finite and >= 0, got " +
                                                 formatNumber(weightDepth) + ", " +
                                                 formatNumber(weightNormal));
    GpuLayer changed = mLayers[static_cast<std::size_t>(index)];
    changed.tiling = tiling;
    changed.weightDepth = weightDepth;
    changed.weightNormal = weightNormal;
    double sumDepth = 0.0, sumNormal = 0.0;
    for (std::size_t i = 0; i < mLayers.size(); ++i) {
        const GpuLayer& layer = static_cast<int>(i) == index ? changed : mLayers[i];
        sumDepth += layer.weightDepth;
        sumNormal += layer.weightNormal;
    }
    if (!(sumDepth > 0.0)) throw Error(ErrorKind::InvalidInput, name + ": the depth weights would sum to 0");
    if (mNormalMode == NormalMode::Paper && !(sumNormal > 0.0))
        throw Error(ErrorKind::InvalidInput, name + ": the normal weights would sum to 0");
    mLayers[static_cast<std::size_t>(index)] = changed;
}

void GpuMaterial::setComposedAo(const Image& ao, double aoDepthScale) {
    if (ao.empty() || ao.channels() != 1)
        throw Error(ErrorKind::InvalidInput, "GpuMaterial::setComposedAo: the AO map must have 1 channel");
    if (!(std::isfinite(aoDepthScale) && aoDepthScale > 0.0))
        throw Error(ErrorKind::InvalidInput, "GpuMaterial::setComposedAo: AO depth scale must be > 0, got " +
                                                 formatNumber(aoDepthScale));
    std::vector<std::uint16_t> texels(ao.pixels().size());
    std::transform(ao.pixels().begin(), ao.pixels().end(), texels.begin(), toUnorm16);
    const GLuint texture = makeTexture(GL_R16, ao.width(), ao.height(), GL_RED, GL_UNSIGNED_SHORT, texels, 1);
    if (mComposedAo != 0) glDeleteTextures(1, &mComposedAo);
    mComposedAo = texture;
    mAoDepthScale = aoDepthScale;
    checkGl("GpuMaterial::setComposedAo");
}

// ---------------------------------------------------------------------------------------------------------
// ReliefRenderer

namespace {

// The framebuffer for one picture size and format, kept between renders (single-sample: render()
// supersamples, see there).
struct Target {
    int width = 0;
    int height = 0;
    GLenum format = 0;
    GLuint framebuffer = 0;
    GLuint color = 0;  // renderbuffer
    GLuint depth = 0;  // renderbuffer

    void release() {
        glDeleteFramebuffers(1, &framebuffer);
        const GLuint renderbuffers[] = {color, depth};
        glDeleteRenderbuffers(2, renderbuffers);
        *this = Target();
    }
};

GLuint makeRenderbuffer(GLenum format, int width, int height) {
    GLuint renderbuffer = 0;
    glCreateRenderbuffers(1, &renderbuffer);
    glNamedRenderbufferStorage(renderbuffer, format, width, height);
    return renderbuffer;
}

void checkComplete(GLuint framebuffer, const char* what) {
    const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        throw Error(
            ErrorKind::Runtime, std::string("ReliefRenderer: ") + what +
                                    " framebuffer incomplete (status 0x" +
                                    [status] {
                                        char buffer[16];
                                        std::snprintf(buffer, sizeof(buffer), "%04x", status);
                                        return std::string(buffer);
                                    }() +
                                    ")");
    }
}

// Saves and restores the framebuffer bindings and viewport around render(), so a viewer can call it.
class BindingGuard {
public:
    BindingGuard() {
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &mDraw);
        glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &mRead);
        glGetIntegerv(GL_VIEWPORT, mViewport.data());
    }
    ~BindingGuard() {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(mDraw));
        glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(mRead));
        glViewport(mViewport[0], mViewport[1], mViewport[2], mViewport[3]);
    }
    BindingGuard(const BindingGuard&) = delete;
    BindingGuard& operator=(const BindingGuard&) = delete;

private:
    GLint mDraw = 0;
    GLint mRead = 0;
    std::array<GLint, 4> mViewport{};
};

}  // namespace

struct ReliefRenderer::Impl {
    std::map<ProgramVariant, Program> programs;
    GLuint flatRelief = 0;  // 1x1 packed texel of a flat relief (n = +z, AO 1, d 0), for plain objects
    GLuint white = 0;       // 1x1 white colour
    // For the debug outputs: the base level's bilinear, wrap-around height field of CONVENTIONS §1 and
    // nothing else. The shader reads it with textureLod(..., 0), but an explicit LOD does not switch off
    // anisotropic filtering everywhere (llvmpipe keeps filtering along a footprint of its own and moved
    // uv hits by several texels), so these outputs bind a sampler object without mipmaps or anisotropy.
    GLuint baseLevelSampler = 0;
    // For the shaded output's searches: trilinear mip mapping (paper Sec. 5) without anisotropy. The final
    // colour, normal and AO fetches keep the textures' own 16x anisotropic filtering (units 1 and 2). An
    // anisotropic fetch in every search step costs up to 16 trilinear probes each; on llvmpipe, which does
    // them in software, that made the teapot 10-30x slower (35 s instead of 1 s at 320x180), and on a GPU it
    // only blurs a height field whose crossing the binary search locates anyway.
    GLuint searchSampler = 0;
    Target target;

    Impl() {
        const std::vector<std::uint16_t> flat = {32768, 32768, 65535, 0};
        flatRelief = makeTexture(GL_RGBA16, 1, 1, GL_RGBA, GL_UNSIGNED_SHORT, flat, 4);
        const std::vector<std::uint8_t> whiteTexel = {255, 255, 255, 255};
        white = makeTexture(GL_SRGB8_ALPHA8, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, whiteTexel, 4);
        glCreateSamplers(1, &baseLevelSampler);
        glSamplerParameteri(baseLevelSampler, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glSamplerParameteri(baseLevelSampler, GL_TEXTURE_WRAP_T, GL_REPEAT);
        glSamplerParameteri(baseLevelSampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glSamplerParameteri(baseLevelSampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glCreateSamplers(1, &searchSampler);
        glSamplerParameteri(searchSampler, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glSamplerParameteri(searchSampler, GL_TEXTURE_WRAP_T, GL_REPEAT);
        glSamplerParameteri(searchSampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glSamplerParameteri(searchSampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        checkGl("ReliefRenderer: creating default textures");
    }

    ~Impl() {
        target.release();
        glDeleteTextures(1, &flatRelief);
        glDeleteTextures(1, &white);
        glDeleteSamplers(1, &baseLevelSampler);
        glDeleteSamplers(1, &searchSampler);
    }

    const Program& program(const ProgramVariant& variant) {
        const ProgramVariant key = canonical(variant);
        auto it = programs.find(key);
        if (it == programs.end()) it = programs.emplace(key, buildVariantProgram(key)).first;
        return it->second;
    }

    void ensureTarget(int width, int height, GLenum format) {
        if (target.framebuffer != 0 && target.width == width && target.height == height &&
            target.format == format) {
            return;
        }
        target.release();
        target.width = width;
        target.height = height;
        target.format = format;
        target.color = makeRenderbuffer(format, width, height);
        target.depth = makeRenderbuffer(GL_DEPTH_COMPONENT32F, width, height);
        glCreateFramebuffers(1, &target.framebuffer);
        glNamedFramebufferRenderbuffer(target.framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                       target.color);
        glNamedFramebufferRenderbuffer(target.framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                       target.depth);
        checkComplete(target.framebuffer, "render");
        checkGl("ReliefRenderer: creating framebuffers");
    }

    void drawScene(const RenderRequest& request, int width, int height, bool encodeSrgb,
                   const glm::vec4& clearColor);
    static void setLiveUniforms(const Program& program, const GpuMaterial& material, double depthScale,
                                const ReliefSettings& relief);
};

namespace {

void validateRequest(const RenderRequest& request) {
    validate(request.relief);
    validate(request.lighting);
    validate(request.picture);
    validateCamera(request.camera);
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        if (request.objects[i].mesh == nullptr) {
            throw Error(ErrorKind::InvalidInput,
                        "render request: object " + std::to_string(i) + " has no mesh");
        }
        const GpuMaterial* material = request.objects[i].material;
        const bool dualTechnique = request.relief.technique == Technique::DualDepth;
        if (material != nullptr && material->isDualDepth() != dualTechnique) {
            throw Error(
                ErrorKind::InvalidInput,
                "render request: object " + std::to_string(i) +
                    (dualTechnique ? ": technique dual-depth needs a dual-depth texture (strata dual-depth)"
                                   : ": a dual-depth texture draws only with technique dual-depth"));
        }
        if (request.relief.technique == Technique::Cone && material != nullptr && material->isLive()) {
            throw Error(ErrorKind::InvalidInput, "render request: object " + std::to_string(i) +
                                                     ": cone needs a baked material (--meta baked)");
        }
        if (request.relief.technique == Technique::MaxMip && material != nullptr) {
            if (material->isLive()) {
                throw Error(ErrorKind::InvalidInput, "render request: object " + std::to_string(i) +
                                                         ": maxmip needs a baked material (--meta baked)");
            }
            if (material->maxMipTexture() == 0) {
                throw Error(ErrorKind::InvalidInput, "render request: object " + std::to_string(i) +
                                                         ": maxmip needs a depth map whose "
                                                         "sides are powers of two, got " +
                                                         std::to_string(material->width()) + "x" +
                                                         std::to_string(material->height()));
            }
        }
    }
}

// Near and far planes from the scene's bounds (each object's box grown by the deepest relief it can show,
// in object space), measured along the view direction, with a small margin. A camera inside the scene gets
// near = far / 10^4.
std::pair<double, double> clipPlanes(const RenderRequest& request) {
    const CameraFrame frame = cameraFrame(request.camera);
    double nearest = std::numeric_limits<double>::infinity();
    double farthest = -std::numeric_limits<double>::infinity();
    for (const SceneObject& object : request.objects) {
        const Bounds& bounds = object.mesh->bounds();
        double grow = 0.0;
        if (object.material != nullptr) {
            const double scale = request.relief.depthScale.value_or(object.material->depthScale());
            grow = scale * object.mesh->maxUvLength() / request.relief.tiling;
        }
        const glm::dvec3 lo = glm::dvec3(bounds.min) - grow;
        const glm::dvec3 hi = glm::dvec3(bounds.max) + grow;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                               (corner & 4) ? hi.z : lo.z);
            const glm::dvec3 world = glm::dvec3(object.model * glm::dvec4(p, 1.0));
            const double distance = glm::dot(world - request.camera.eye, frame.forward);
            nearest = std::min(nearest, distance);
            farthest = std::max(farthest, distance);
        }
    }
    if (!(farthest > 0.0)) return {0.01, 1.0};  // nothing in front of the camera
    // The relief repeats under neighbouring tiles, so a grazing ray can show relief well beyond the mesh's
    // bounds (at 75 degrees S = 0.1 is 0.37 tiles away from the entry): the far plane is twice the farthest
    // bound. With a 32-bit float depth buffer this costs next to nothing in precision.
    const double margin = 0.01 * (farthest - std::min(nearest, farthest)) + 1e-6 * farthest;
    const double farPlane = 2.0 * farthest + margin;
    const double nearPlane = std::max(nearest - margin, farPlane * 1e-4);
    return {nearPlane, farPlane};
}

// The order the shader sees a live material's layers in: the layer that can move Eq. 2's sum most first
// (largest w_d,i (max d_i - min d_i)), so that the searches' first read most often settles whether a point
// is above the relief (relief_search.glsl, reliefBelow). The sums do not depend on the order, and the shader
// indexes its sampler array with constants only (a dynamic index is much slower on llvmpipe).
std::vector<std::size_t> shaderLayerOrder(const std::vector<GpuLayer>& layers) {
    std::vector<std::size_t> order(layers.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    const auto range = [&](std::size_t i) {
        return layers[i].weightDepth * (layers[i].depthMax - layers[i].depthMin);
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return range(a) > range(b); });
    return order;
}

}  // namespace

// The live meta-relief's uniforms (relief_search.glsl, relief.frag.glsl metaShade), per layer in
// shaderLayerOrder: weights normalised as Eq. 1 and 2 do, each layer's AO rescale S_i now / S_i baked,
// S_i = S (w_d,i / W) t_i, and the bounds on what the later layers add to Eq. 2 (with 1e-6 of slack for the
// float rounding of the shader's sums).
void ReliefRenderer::Impl::setLiveUniforms(const Program& program, const GpuMaterial& material,
                                           double depthScale, const ReliefSettings& relief) {
    const GLuint id = program.id();
    const auto location = [&](const char* name) { return program.uniformLocation(name); };
    const std::vector<GpuLayer>& layers = material.layers();
    const std::vector<std::size_t> order = shaderLayerOrder(layers);
    double sumDepth = 0.0, sumNormal = 0.0;
    for (const GpuLayer& layer : layers) {
        sumDepth += layer.weightDepth;
        sumNormal += layer.weightNormal;
    }
    std::array<float, kMaxLiveLayers> tiling{}, depthWeight{}, normalWeight{}, aoScale{}, normalScale{};
    std::array<float, kMaxLiveLayers> restLow{}, restHigh{};
    double low = 0.0, high = 0.0;
    for (std::size_t i = layers.size(); i-- > 0;) {
        restLow[i] = static_cast<float>(low - 1e-6);
        restHigh[i] = static_cast<float>(high + 1e-6);
        const GpuLayer& layer = layers[order[i]];
        low += layer.weightDepth / sumDepth * layer.depthMin;
        high += layer.weightDepth / sumDepth * layer.depthMax;
    }
    glProgramUniform1fv(id, location("uLayerRestLow"), kMaxLiveLayers, restLow.data());
    glProgramUniform1fv(id, location("uLayerRestHigh"), kMaxLiveLayers, restHigh.data());
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const GpuLayer& layer = layers[order[i]];
        tiling[i] = static_cast<float>(layer.tiling);
        normalScale[i] = static_cast<float>(layer.normalScale);
        depthWeight[i] = static_cast<float>(layer.weightDepth / sumDepth);
        normalWeight[i] = sumNormal > 0.0 ? static_cast<float>(layer.weightNormal / sumNormal) : 0.0f;
        const double now = depthScale * (layer.weightDepth / sumDepth) * layer.tiling;
        aoScale[i] = layer.aoDepthScale > 0.0 && relief.aoRescale != AoRescale::Off
                         ? static_cast<float>(now / layer.aoDepthScale)
                         : 1.0f;
    }
    glProgramUniform1i(id, location("uLayerCount"), static_cast<GLint>(layers.size()));
    glProgramUniform1fv(id, location("uLayerTiling"), kMaxLiveLayers, tiling.data());
    glProgramUniform1fv(id, location("uLayerDepthWeight"), kMaxLiveLayers, depthWeight.data());
    glProgramUniform1fv(id, location("uLayerNormalWeight"), kMaxLiveLayers, normalWeight.data());
    glProgramUniform1fv(id, location("uLayerAoScale"), kMaxLiveLayers, aoScale.data());
    glProgramUniform1i(id, location("uMetaConsistent"), material.normalMode() == NormalMode::Consistent);
    glProgramUniform1fv(id, location("uLayerNormalScale"), kMaxLiveLayers, normalScale.data());
    int aoMode = 0;
    if (material.liveAo() == MetaAoMode::Multiply) aoMode = 1;
    if (material.liveAo() == MetaAoMode::Min) aoMode = 2;
    if (material.liveAo() == MetaAoMode::Exact && material.composedAoTexture() != 0) aoMode = 3;
    glProgramUniform1i(id, location("uMetaAo"), aoMode);
}

void ReliefRenderer::Impl::drawScene(const RenderRequest& request, int width, int height, bool encodeSrgb,
                                     const glm::vec4& clearColor) {
    const auto [nearPlane, farPlane] = clipPlanes(request);
    const glm::dmat4 viewProjection =
        projectionMatrix(request.camera, static_cast<double>(width) / height, nearPlane, farPlane) *
        viewMatrix(request.camera);
    const glm::mat4 viewProjectionF = toFloat(viewProjection);

    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_FRAMEBUFFER_SRGB);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    // Relief mapping is defined for the front side of a surface (the view ray must go into it).
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glClearColor(clearColor.r, clearColor.g, clearColor.b, clearColor.a);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    const ReliefSettings& relief = request.relief;
    const Lighting& lighting = request.lighting;
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        const SceneObject& object = request.objects[i];
        const GpuMaterial* material = object.material;
        ProgramVariant variant;
        variant.technique = relief.technique;
        variant.output = request.picture.output;
        variant.plain = material == nullptr;
        variant.shadows = relief.selfShadow;
        variant.depthCorrection = relief.depthCorrection;
        if (material != nullptr && relief.ao && material->hasAo()) {
            variant.ao = relief.aoRescale == AoRescale::Paper ? AoMode::Paper : AoMode::Baked;
        }
        variant.live = material != nullptr && material->isLive();
        const Program& prog = program(variant);
        const GLuint id = prog.id();
        const auto location = [&](const char* name) { return prog.uniformLocation(name); };

        const double depthScale =
            material != nullptr ? relief.depthScale.value_or(material->depthScale()) : 0.0;
        const glm::dmat3 linear(object.model);
        const double determinant = glm::determinant(linear);
        const glm::mat3 normalMatrix(glm::transpose(glm::inverse(linear)));
        glProgramUniformMatrix4fv(id, location("uModel"), 1, GL_FALSE, glm::value_ptr(toFloat(object.model)));
        glProgramUniformMatrix3fv(id, location("uNormalMatrix"), 1, GL_FALSE, glm::value_ptr(normalMatrix));
        glProgramUniform1f(id, location("uMirror"), determinant < 0.0 ? -1.0f : 1.0f);
        glProgramUniformMatrix4fv(id, location("uViewProjection"), 1, GL_FALSE,
                                  glm::value_ptr(viewProjectionF));
        glProgramUniform1f(id, location("uTiling"), static_cast<float>(relief.tiling));
        glProgramUniform3fv(id, location("uEye"), 1, glm::value_ptr(glm::vec3(request.camera.eye)));
        glProgramUniform1f(id, location("uDepthScale"), static_cast<float>(depthScale));
        glProgramUniform1f(
            id, location("uNormalScale"),
            material != nullptr ? static_cast<float>(depthScale / material->depthScale()) : 1.0f);
        glProgramUniform1i(id, location("uLinearSteps"), relief.linearSteps);
        glProgramUniform1i(id, location("uBinarySteps"), relief.binarySteps);
        glProgramUniform3fv(id, location("uLightPosition"), 1,
                            glm::value_ptr(glm::vec3(lighting.lightPosition)));
        glProgramUniform3fv(id, location("uLightColor"), 1, glm::value_ptr(glm::vec3(lighting.lightColor)));
        glProgramUniform1f(id, location("uAmbient"), static_cast<float>(lighting.ambient));
        glProgramUniform1f(id, location("uSpecular"), static_cast<float>(lighting.specular));
        glProgramUniform1f(id, location("uShininess"), static_cast<float>(lighting.shininess));
        glProgramUniform1f(
            id, location("uAoScale"),
            material != nullptr ? static_cast<float>(depthScale / material->aoDepthScale()) : 1.0f);
        glProgramUniform3f(id, location("uPlainColor"), srgbToLinear(object.color.r),
                           srgbToLinear(object.color.g), srgbToLinear(object.color.b));
        glProgramUniform1i(id, location("uEncodeSrgb"), encodeSrgb ? 1 : 0);

        glProgramUniform1f(id, location("uColorTiling"), 1.0f);
        const GLuint sampler =
            request.picture.output == RenderOutput::Shaded ? searchSampler : baseLevelSampler;
        glUseProgram(id);
        if (variant.live) {
            setLiveUniforms(prog, *material, depthScale, relief);
            glBindTextureUnit(0, flatRelief);
            glBindTextureUnit(2, flatRelief);
            const std::vector<GpuLayer>& layers = material->layers();
            const int colorLayer = material->colorLayer();
            glBindTextureUnit(1,
                              colorLayer >= 0 ? layers[static_cast<std::size_t>(colorLayer)].color : white);
            if (colorLayer >= 0) {
                glProgramUniform1f(id, location("uColorTiling"),
                                   static_cast<float>(layers[static_cast<std::size_t>(colorLayer)].tiling));
            }
            // Searches and shading read the layers through one sampler (trilinear, or the base level for the
            // debug outputs): a second set of units with anisotropic filtering would need 16 more.
            const std::vector<std::size_t> order = shaderLayerOrder(layers);
            for (int unit = 0; unit < kMaxLiveLayers; ++unit) {
                const bool used = unit < static_cast<int>(layers.size());
                glBindTextureUnit(3 + unit,
                                  used ? layers[order[static_cast<std::size_t>(unit)]].texture : flatRelief);
                glBindSampler(3 + unit, sampler);
            }
            glBindTextureUnit(
                11, material->composedAoTexture() != 0 ? material->composedAoTexture() : flatRelief);
        } else {
            glBindTextureUnit(0, material != nullptr ? material->reliefTexture() : flatRelief);
            glBindTextureUnit(1, material != nullptr ? material->colorTexture() : white);
            glBindTextureUnit(2, material != nullptr ? material->reliefTexture() : flatRelief);
        }
        if (material != nullptr && relief.technique == Technique::MaxMip) {
            glBindTextureUnit(12, material->maxMipTexture());
            glProgramUniform1i(id, location("uMaxMipLevels"), material->maxMipLevels());
        }
        if (material != nullptr && relief.technique == Technique::Cone) {
            glBindTextureUnit(13, material->coneTexture());
            glProgramUniform1f(id, location("uConeMaxRatio"), static_cast<float>(material->coneMaxRatio()));
        }
        glBindSampler(0, sampler);
        // A mirroring model turns counter-clockwise triangles clockwise on screen.
        glFrontFace(determinant < 0.0 ? GL_CW : GL_CCW);
        glBindVertexArray(object.mesh->vertexArray());
        glDrawElements(GL_TRIANGLES, object.mesh->indexCount(), GL_UNSIGNED_INT, nullptr);
        checkGl(("ReliefRenderer: drawing object " + std::to_string(i) + " (" +
                 variantName(canonical(variant)) + ")")
                    .c_str());
    }
    glBindVertexArray(0);
    glBindSampler(0, 0);
    for (int unit = 0; unit < kMaxLiveLayers; ++unit) glBindSampler(3 + unit, 0);
    glUseProgram(0);
    glFrontFace(GL_CCW);
}

ReliefRenderer::ReliefRenderer() : mImpl(std::make_unique<Impl>()) {}

ReliefRenderer::~ReliefRenderer() = default;

void ReliefRenderer::prepare(const ProgramVariant& variant) {
    mImpl->program(variant);
}

namespace {

// k of the k x k supersampling grid for `samples` per pixel, limited so that the supersampled picture fits
// the driver's renderbuffer size.
int supersamplingFactor(const PictureSettings& picture) {
    int factor = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(picture.samples)))));
    GLint maxSize = 4096;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    while (factor > 1 && std::max(picture.width, picture.height) * factor > maxSize) --factor;
    return factor;
}

}  // namespace

Image ReliefRenderer::render(const RenderRequest& request) {
    validateRequest(request);
    const PictureSettings& picture = request.picture;
    const bool shaded = picture.output == RenderOutput::Shaded;
    // Shaded: supersampled on a k x k grid per pixel (k = round(sqrt(samples))), in linear half-float colour,
    // box-filtered in linear and encoded to sRGB here. Supersampling rather than MSAA, because MSAA shades
    // once per pixel: it smooths the polygons' edges but not what relief mapping draws inside them (the
    // relief's own silhouettes, shadow edges, fine texture).
    // Debug outputs: 32-bit float (uv needs 16 bits of precision), one sample (CONVENTIONS §7).
    const int factor = shaded ? supersamplingFactor(picture) : 1;
    const int outWidth = picture.width;
    const int outHeight = picture.height;
    const int width = outWidth * factor;
    const int height = outHeight * factor;
    BindingGuard guard;
    mImpl->ensureTarget(width, height, shaded ? GL_RGBA16F : GL_RGBA32F);
    const Target& target = mImpl->target;

    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    const glm::vec4 clear =
        shaded ? glm::vec4(srgbToLinear(picture.background.r), srgbToLinear(picture.background.g),
                           srgbToLinear(picture.background.b), 1.0f)
               : glm::vec4(0.0f);
    mImpl->drawScene(request, width, height, false, clear);

    std::vector<float> pixels(static_cast<std::size_t>(width) * height * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.framebuffer);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, pixels.data());
    checkGl("ReliefRenderer::render: read-back");

    const int channels = shaded || picture.output == RenderOutput::Uv ? 3 : 1;
    const float weight = 1.0f / static_cast<float>(factor * factor);
    Image image = Image::uninitialized(outWidth, outHeight, channels);
    for (int y = 0; y < outHeight; ++y) {
        float* row = image.row(y);
        for (int x = 0; x < outWidth; ++x) {
            for (int c = 0; c < channels; ++c) {
                float sum = 0.0f;
                for (int j = 0; j < factor; ++j) {
                    // GL's row 0 is the bottom one; the picture's row 0 is the top (CONVENTIONS §7).
                    const float* source =
                        pixels.data() + static_cast<std::size_t>(height - 1 - (y * factor + j)) * width * 4;
                    for (int i = 0; i < factor; ++i) sum += source[(x * factor + i) * 4 + c];
                }
                row[x * channels + c] = shaded ? linearToSrgb(sum * weight) : sum;
            }
        }
    }
    return image;
}

void ReliefRenderer::draw(const RenderRequest& request, int viewportWidth, int viewportHeight) {
    if (viewportWidth < 1 || viewportHeight < 1) {
        throw Error(ErrorKind::InvalidInput, "ReliefRenderer::draw: viewport " +
                                                 std::to_string(viewportWidth) + "x" +
                                                 std::to_string(viewportHeight) + " is empty");
    }
    RenderRequest shadedRequest = request;
    shadedRequest.picture.output = RenderOutput::Shaded;
    shadedRequest.picture.width = viewportWidth;
    shadedRequest.picture.height = viewportHeight;
    validateRequest(shadedRequest);
    const glm::dvec3& background = request.picture.background;
    // Values are written sRGB-encoded by the shader, so the clear colour is the encoded background as is.
    mImpl->drawScene(shadedRequest, viewportWidth, viewportHeight, true,
                     glm::vec4(glm::vec3(background), 1.0f));
}

}  // namespace strata::gl
