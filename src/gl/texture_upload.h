// Texture uploads that every renderer in strata::gl shares (internal to the module): tiling 2-D textures with
// full mipmaps and anisotropic filtering, in the row order and channel layouts of CONVENTIONS §1 and §5.
//
// 8- and 16-bit values are quantised by strata/image/quantize.h (toUnorm8, toUnorm16: correctly rounded).
//
// Everything here needs a current OpenGL 4.5 core context; the caller owns the returned texture names
// (glDeleteTextures) and checks for GL errors (checkGl) after its pass.
#pragma once

#include "strata/image/image.h"
#include "strata/relief/relief_texture.h"

#include <epoxy/gl.h>

#include <cstdint>
#include <span>

namespace strata::gl {

// The mip chain length of a width x height texture down to 1 x 1: 1 + floor(log2(max(width, height))).
int mipLevels(int width, int height);

// 16x anisotropic filtering (or the driver's maximum, if lower) where the driver has it (core in 4.6, else
// ARB/EXT_texture_filter_anisotropic); nothing otherwise.
void setAnisotropy(GLuint texture);

// A tiling GL_TEXTURE_2D with full mipmaps (glGenerateTextureMipmap), trilinear + anisotropic filtering and
// GL_REPEAT. `rows` holds width * height * components values, top row first (CONVENTIONS §1); they are
// uploaded bottom row first, so that t = v. `format` / `type` describe `rows` (e.g. GL_RGBA,
// GL_UNSIGNED_SHORT); internalFormat is the texture's (e.g. GL_RGBA16, GL_SRGB8_ALPHA8).
GLuint makeTexture(GLenum internalFormat, int width, int height, GLenum format, GLenum type,
                   std::span<const std::uint8_t> rows, int components);
GLuint makeTexture(GLenum internalFormat, int width, int height, GLenum format, GLenum type,
                   std::span<const std::uint16_t> rows, int components);

// A colour map (3 or more channels, sRGB-encoded [0, 1]; channels past 3 are ignored) as SRGB8_ALPHA8 with
// alpha 1, so that sampling returns linear colour, filtered in linear. A 1x1 white texture for an empty
// image.
GLuint makeColorTexture(const Image& color);

// The packed relief texture (packRelief, CONVENTIONS §5: R, G = n.xy * 0.5 + 0.5, B = AO, A = d) as RGBA16.
GLuint makePackedTexture(const ReliefTexture& texture);

}  // namespace strata::gl
