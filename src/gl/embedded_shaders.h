// The shader sources compiled into strata::gl; the table is generated at build time by
// cmake/StrataShaders.cmake from every .glsl under shaders/ and shaders/shared/*.h.
#pragma once

#include <cstddef>
#include <string_view>

namespace strata::gl::detail {

struct EmbeddedShaderFile {
    const char* path;          // relative to shaders/, '/'-separated, e.g. "relief/relief.frag.glsl"
    std::string_view content;  // the file's bytes
};

extern const EmbeddedShaderFile kEmbeddedShaderFiles[];
extern const std::size_t kEmbeddedShaderFileCount;

}  // namespace strata::gl::detail
