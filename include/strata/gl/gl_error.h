// OpenGL error checking for strata::gl (CODE_STYLE: a failure from outside the code, here the driver, is
// a strata::Error that says what and where).
#pragma once

namespace strata::gl {

// Throws Error(Runtime) "OpenGL error GL_INVALID_OPERATION after <what>" if glGetError reports anything
// (all queued errors are drained and listed), or if the debug callback (installDebugOutput) recorded a
// message of type error since the last call. `what` names the call or pass, e.g. "uploadMaterial:
// glTextureStorage2D". Needs a current context. Cheap: call it after every pass.
void checkGl(const char* what);

// Installs a GL_KHR_debug callback on the current context that records every message of type
// GL_DEBUG_TYPE_ERROR (and prints nothing); checkGl() throws the recorded messages. Synchronous output, so
// the message belongs to the call that caused it. No effect (returns false) where the context has no
// debug output. HeadlessContext::create() calls it for a debug context; the viewer may call it too.
bool installDebugOutput();

}  // namespace strata::gl
