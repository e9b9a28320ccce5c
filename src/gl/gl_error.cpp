#include "strata/gl/gl_error.h"

#include "strata/core/error.h"

#include <epoxy/gl.h>

#include <string>
#include <vector>

namespace strata::gl {

namespace {

// Messages of type error recorded by the debug callback on this thread (synchronous debug output calls
// back on the thread that made the failing call).
thread_local std::vector<std::string> tRecordedErrors;

const char* errorName(GLenum error) {
    switch (error) {
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        case GL_STACK_UNDERFLOW:
            return "GL_STACK_UNDERFLOW";
        case GL_STACK_OVERFLOW:
            return "GL_STACK_OVERFLOW";
        default:
            return "unknown GL error";
    }
}

// The shader compiler's messages are left out: a failed compile or link is reported by Program from its
// info log (file and line), and the same text here would fail the next checkGl of a debug context only.
void GLAPIENTRY recordMessage(GLenum source, GLenum type, GLuint /*id*/, GLenum /*severity*/, GLsizei length,
                              const GLchar* message, const void* /*user*/) {
    if (type != GL_DEBUG_TYPE_ERROR || source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    tRecordedErrors.emplace_back(
        message, length >= 0 ? static_cast<std::size_t>(length) : std::string(message).size());
}

}  // namespace

void checkGl(const char* what) {
    std::string errors;
    // glGetError returns one flag per call; an implementation may hold several.
    for (int i = 0; i < 16; ++i) {
        const GLenum error = glGetError();
        if (error == GL_NO_ERROR) break;
        errors += (errors.empty() ? "" : ", ");
        errors += errorName(error);
    }
    for (const std::string& message : tRecordedErrors) errors += (errors.empty() ? "" : "; ") + message;
    tRecordedErrors.clear();
    if (!errors.empty()) {
        throw Error(ErrorKind::Runtime, std::string("OpenGL error after ") + what + ": " + errors);
    }
}

bool installDebugOutput() {
    GLint flags = 0;
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    if ((flags & GL_CONTEXT_FLAG_DEBUG_BIT) == 0) return false;
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(recordMessage, nullptr);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
    return true;
}

}  // namespace strata::gl
