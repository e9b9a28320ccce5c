#include "texture_upload.h"

#include "strata/image/quantize.h"
#include "strata/relief/texture_set.h"

#include <algorithm>

#include <cstddef>
#include <vector>

namespace strata::gl {

int mipLevels(int width, int height) {
    int levels = 1;
    for (int size = std::max(width, height); size > 1; size /= 2) ++levels;
    return levels;
}

void setAnisotropy(GLuint texture) {
    if (epoxy_gl_version() < 46 && !epoxy_has_gl_extension("GL_ARB_texture_filter_anisotropic") &&
        !epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic")) {
        return;
    }
    GLfloat maximum = 1.0f;
    glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &maximum);
    glTextureParameterf(texture, GL_TEXTURE_MAX_ANISOTROPY, std::min(16.0f, maximum));
}

namespace {

template <typename T>
GLuint makeTiledTexture(GLenum internalFormat, int width, int height, GLenum format, GLenum type,
                        std::span<const T> rows, int components) {
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

}  // namespace

GLuint makeTexture(GLenum internalFormat, int width, int height, GLenum format, GLenum type,
                   std::span<const std::uint8_t> rows, int components) {
    return makeTiledTexture(internalFormat, width, height, format, type, rows, components);
}

GLuint makeTexture(GLenum internalFormat, int width, int height, GLenum format, GLenum type,
                   std::span<const std::uint16_t> rows, int components) {
    return makeTiledTexture(internalFormat, width, height, format, type, rows, components);
}

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
    return makeTexture(GL_SRGB8_ALPHA8, colorWidth, colorHeight, GL_RGBA, GL_UNSIGNED_BYTE,
                       std::span<const std::uint8_t>(rgba), 4);
}

GLuint makePackedTexture(const ReliefTexture& texture) {
    const Image packed = packRelief(texture);
    std::vector<std::uint16_t> texels(packed.pixels().size());
    std::transform(packed.pixels().begin(), packed.pixels().end(), texels.begin(),
                   [](float v) { return toUnorm16(v); });
    return makeTexture(GL_RGBA16, packed.width(), packed.height(), GL_RGBA, GL_UNSIGNED_SHORT,
                       std::span<const std::uint16_t>(texels), 4);
}

}  // namespace strata::gl
