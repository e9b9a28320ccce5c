// Offscreen framebuffers for renderers that read their pictures back (internal to strata::gl), and a guard
// that leaves the caller's framebuffer bindings and viewport as they were.
//
// Needs a current OpenGL 4.5 core context; release() (or the owner's destructor) must run while the context
// that made the target is current.
#pragma once

#include <epoxy/gl.h>

#include <array>

namespace strata::gl {

// One single-sample framebuffer: a colour renderbuffer of a given format and a 32-bit float depth
// renderbuffer, kept between pictures of the same size and format.
class RenderTarget {
public:
    RenderTarget() = default;
    ~RenderTarget() { release(); }
    RenderTarget(const RenderTarget&) = delete;
    RenderTarget& operator=(const RenderTarget&) = delete;

    // (Re)creates the framebuffer unless it already has this size and colour format. `owner` names the
    // caller in errors: Error(Runtime) "<owner>: render framebuffer incomplete (status 0x....)", or a GL
    // error (checkGl "<owner>: creating framebuffers").
    void ensure(int width, int height, GLenum colorFormat, const char* owner);
    void release();

    GLuint framebuffer() const { return mFramebuffer; }

private:
    int mWidth = 0;
    int mHeight = 0;
    GLenum mFormat = 0;
    GLuint mFramebuffer = 0;
    GLuint mColor = 0;  // renderbuffer
    GLuint mDepth = 0;  // renderbuffer
};

// Saves the draw and read framebuffer bindings and the viewport, and restores them when it goes out of
// scope, so that a renderer can draw offscreen in the middle of a viewer's frame.
class BindingGuard {
public:
    BindingGuard();
    ~BindingGuard();
    BindingGuard(const BindingGuard&) = delete;
    BindingGuard& operator=(const BindingGuard&) = delete;

private:
    GLint mDraw = 0;
    GLint mRead = 0;
    std::array<GLint, 4> mViewport{};
};

}  // namespace strata::gl
