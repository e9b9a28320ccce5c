#include "strata/gl/gpu_material.h"

#include "texture_upload.h"

#include "strata/core/error.h"
#include "strata/gl/gl_error.h"
#include "strata/image/quantize.h"
#include "strata/relief/cone_map.h"
#include "strata/relief/max_mip.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace strata::gl {

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
        std::transform(levels[k].pixels().begin(), levels[k].pixels().end(), texels.begin(),
                       [](float v) { return toUnorm16(v); });
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
    for (float& d : result.pixels()) d = quantizeUnorm16(d);
    return result;
}

// The cone map texture (cone.glsl): RG16 per cell, packConeMap's frame and values.
GLuint makeConeMap(const Image& depth, double* maxRatio) {
    const PackedConeMap packed = packConeMap(depth);
    const int width = depth.width(), height = depth.height();
    std::vector<std::uint16_t> texels(packed.texels.pixels().size());
    std::transform(packed.texels.pixels().begin(), packed.texels.pixels().end(), texels.begin(),
                   [](float v) { return toUnorm16(v); });
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
    std::transform(ao.pixels().begin(), ao.pixels().end(), texels.begin(),
                   [](float v) { return toUnorm16(v); });
    const GLuint texture = makeTexture(GL_R16, ao.width(), ao.height(), GL_RED, GL_UNSIGNED_SHORT, texels, 1);
    if (mComposedAo != 0) glDeleteTextures(1, &mComposedAo);
    mComposedAo = texture;
    mAoDepthScale = aoDepthScale;
    checkGl("GpuMaterial::setComposedAo");
}

}  // namespace strata::gl
