#include "render_target.h"

#include "strata/core/error.h"
#include "strata/gl/gl_error.h"

#include <cstdio>
#include <string>

namespace strata::gl {

namespace {

GLuint makeRenderbuffer(GLenum format, int width, int height) {
    GLuint renderbuffer = 0;
    glCreateRenderbuffers(1, &renderbuffer);
    glNamedRenderbufferStorage(renderbuffer, format, width, height);
    return renderbuffer;
}

void checkComplete(GLuint framebuffer, const std::string& owner, const char* what) {
    const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        char code[16];
        std::snprintf(code, sizeof(code), "%04x", status);
        throw Error(ErrorKind::Runtime,
                    owner + ": " + what + " framebuffer incomplete (status 0x" + code + ")");
    }
}

}  // namespace

void RenderTarget::ensure(int width, int height, GLenum colorFormat, const char* owner) {
    if (mFramebuffer != 0 && mWidth == width && mHeight == height && mFormat == colorFormat) return;
    release();
    mWidth = width;
    mHeight = height;
    mFormat = colorFormat;
    mColor = makeRenderbuffer(colorFormat, width, height);
    mDepth = makeRenderbuffer(GL_DEPTH_COMPONENT32F, width, height);
    glCreateFramebuffers(1, &mFramebuffer);
    glNamedFramebufferRenderbuffer(mFramebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, mColor);
    glNamedFramebufferRenderbuffer(mFramebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, mDepth);
    checkComplete(mFramebuffer, owner, "render");
    checkGl((std::string(owner) + ": creating framebuffers").c_str());
}

void RenderTarget::release() {
    if (mFramebuffer != 0) glDeleteFramebuffers(1, &mFramebuffer);
    const GLuint renderbuffers[] = {mColor, mDepth};
    if (mColor != 0 || mDepth != 0) glDeleteRenderbuffers(2, renderbuffers);
    mWidth = mHeight = 0;
    mFormat = 0;
    mFramebuffer = mColor = mDepth = 0;
}

BindingGuard::BindingGuard() {
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &mDraw);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &mRead);
    glGetIntegerv(GL_VIEWPORT, mViewport.data());
}

BindingGuard::~BindingGuard() {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(mDraw));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(mRead));
    glViewport(mViewport[0], mViewport[1], mViewport[2], mViewport[3]);
}

}  // namespace strata::gl
