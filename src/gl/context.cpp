#include "strata/gl/context.h"

#include "strata/core/error.h"
#include "strata/gl/gl_error.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace strata::gl {

namespace {

std::string eglErrorName(EGLint error) {
    switch (error) {
        case EGL_SUCCESS:
            return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED:
            return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS:
            return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC:
            return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE:
            return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG:
            return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT:
            return "EGL_BAD_CONTEXT";
        case EGL_BAD_DISPLAY:
            return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH:
            return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER:
            return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE:
            return "EGL_BAD_SURFACE";
        default: {
            char buffer[32];
            std::snprintf(buffer, sizeof(buffer), "EGL error 0x%04x", static_cast<unsigned>(error));
            return buffer;
        }
    }
}

constexpr const char* kHint =
    " (a headless OpenGL 4.5 core context needs EGL with EGL_MESA_platform_surfaceless or "
    "EGL_EXT_platform_device, e.g. Mesa's libegl-mesa0 and libgl1-mesa-dri, which run on llvmpipe without a "
    "GPU; scripts/install-deps.sh installs them)";

[[noreturn]] void unsupported(const std::string& what) {
    throw Error(ErrorKind::Unsupported,
                "HeadlessContext: " + what + ": " + eglErrorName(eglGetError()) + kHint);
}

bool hasExtension(const char* list, const char* name) {
    if (list == nullptr) return false;
    const std::size_t length = std::strlen(name);
    for (const char* p = std::strstr(list, name); p != nullptr; p = std::strstr(p + length, name)) {
        if ((p == list || p[-1] == ' ') && (p[length] == ' ' || p[length] == '\0')) return true;
    }
    return false;
}

// The display to use, preferring platforms that need no window system; `platform` names it.
EGLDisplay openDisplay(std::string& platform) {
    // Client extensions (EGL 1.5 / EGL_EXT_client_extensions); null if unsupported.
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const bool platformBase = hasExtension(client, "EGL_EXT_platform_base");
    if (platformBase && hasExtension(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr)) {
            platform = "surfaceless";
            return display;
        }
    }
    if (platformBase && hasExtension(client, "EGL_EXT_platform_device") &&
        hasExtension(client, "EGL_EXT_device_enumeration")) {
        EGLDeviceEXT devices[8];
        EGLint count = 0;
        if (eglQueryDevicesEXT(8, devices, &count) && count > 0) {
            EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
            if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr)) {
                platform = "device";
                return display;
            }
        }
    }
    EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (display == EGL_NO_DISPLAY) unsupported("no EGL display");
    if (!eglInitialize(display, nullptr, nullptr)) unsupported("eglInitialize failed");
    platform = "default";
    return display;
}

}  // namespace

std::unique_ptr<HeadlessContext> HeadlessContext::create(GlDebug debugMode) {
    std::unique_ptr<HeadlessContext> result(new HeadlessContext());
    EGLDisplay display = openDisplay(result->mPlatform);
    result->mDisplay = display;  // the destructor terminates it from here on

    if (!eglBindAPI(EGL_OPENGL_API)) unsupported("eglBindAPI(EGL_OPENGL_API) failed: no desktop OpenGL");
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasExtension(extensions, "EGL_KHR_surfaceless_context")) {
        throw Error(
            ErrorKind::Unsupported,
            std::string("HeadlessContext: the EGL display has no EGL_KHR_surfaceless_context") + kHint);
    }
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
        const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLint count = 0;
        if (!eglChooseConfig(display, configAttributes, &config, 1, &count) || count < 1) {
            unsupported("no EGL config supports OpenGL");
        }
    }
#ifdef NDEBUG
    constexpr bool kDebugBuild = false;
#else
    constexpr bool kDebugBuild = true;
#endif
    const bool debug = debugMode == GlDebug::On || (debugMode == GlDebug::BuildDefault && kDebugBuild);
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        4,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        5,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_CONTEXT_OPENGL_DEBUG,
                                        debug ? EGL_TRUE : EGL_FALSE,
                                        EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
    if (context == EGL_NO_CONTEXT) unsupported("eglCreateContext for OpenGL 4.5 core failed");
    result->mContext = context;
    result->makeCurrent();

    const auto glString = [](GLenum name) {
        const GLubyte* text = glGetString(name);
        return text != nullptr ? std::string(reinterpret_cast<const char*>(text)) : std::string();
    };
    result->mRenderer = glString(GL_RENDERER);
    result->mVersion = glString(GL_VERSION);
    if (epoxy_gl_version() < 45) {
        throw Error(ErrorKind::Unsupported, "HeadlessContext: got OpenGL '" + result->mVersion + "' on '" +
                                                result->mRenderer + "', need 4.5 core" + kHint);
    }
    result->mDebug = debug && installDebugOutput();
    checkGl("HeadlessContext::create");
    return result;
}

HeadlessContext::~HeadlessContext() {
    if (mDisplay == nullptr) return;
    EGLDisplay display = static_cast<EGLDisplay>(mDisplay);
    if (mContext != nullptr) {
        if (eglGetCurrentContext() == static_cast<EGLContext>(mContext)) {
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        }
        eglDestroyContext(display, static_cast<EGLContext>(mContext));
    }
    // No eglTerminate: an EGL display is one per platform and process, shared by every context made on
    // it (another HeadlessContext, the viewer's), and terminating it would pull it from under them.
}

void HeadlessContext::makeCurrent() {
    if (!eglMakeCurrent(static_cast<EGLDisplay>(mDisplay), EGL_NO_SURFACE, EGL_NO_SURFACE,
                        static_cast<EGLContext>(mContext))) {
        throw Error(ErrorKind::Runtime,
                    "HeadlessContext: eglMakeCurrent failed: " + eglErrorName(eglGetError()));
    }
}

}  // namespace strata::gl
