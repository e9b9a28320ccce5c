// strata::gl::HeadlessContext: an OpenGL 4.5 core context without a window, through EGL.
//
// The renderer needs only "a current GL 4.5 core context"; this is the one the CLI and the tests make. The
// viewer makes its own (GLFW) and uses the same renderer, so nothing else in strata::gl depends on this.
//
// Display, in order of preference (none of them vendor-specific):
//   1. EGL_MESA_platform_surfaceless (Mesa: llvmpipe without a GPU, or a Mesa GPU driver),
//   2. EGL_EXT_platform_device, the first device (NVIDIA and others without a display server),
//   3. eglGetDisplay(EGL_DEFAULT_DISPLAY).
// The context is configless (EGL_KHR_no_config_context; otherwise the first OpenGL-capable config) and made
// current with no surface (EGL_KHR_surfaceless_context): render into framebuffer objects.
// A debug context (by default in debug builds, NDEBUG undefined) gets a GL_KHR_debug callback that records
// every message of type error; checkGl() (gl_error.h) then throws them with the driver's words.
#pragma once

#include <memory>
#include <string>

namespace strata::gl {

// Whether to ask for a debug context.
enum class GlDebug {
    BuildDefault,  // in debug builds only
    On,
    Off,
};

class HeadlessContext {
public:
    // Creates the context and makes it current on the calling thread. Throws Error(Unsupported) when there
    // is no usable EGL display, no OpenGL API, or no 4.5 core context, with the EGL error and a hint.
    static std::unique_ptr<HeadlessContext> create(GlDebug debug = GlDebug::BuildDefault);

    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    // Makes the context current on the calling thread again (after another context was made current).
    // Throws Error(Runtime) if EGL refuses.
    void makeCurrent();

    // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)", "4.5 (Core Profile) Mesa 22.3.6".
    const std::string& rendererName() const { return mRenderer; }
    const std::string& versionString() const { return mVersion; }
    // Which EGL platform was used ("surfaceless", "device", "default").
    const std::string& platformName() const { return mPlatform; }
    // Whether this is a debug context with the error-recording callback installed.
    bool isDebug() const { return mDebug; }

private:
    HeadlessContext() = default;

    void* mDisplay = nullptr;  // EGLDisplay
    void* mContext = nullptr;  // EGLContext
    std::string mRenderer;
    std::string mVersion;
    std::string mPlatform;
    bool mDebug = false;
};

}  // namespace strata::gl
