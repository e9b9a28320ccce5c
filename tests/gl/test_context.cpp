// Headless contexts and GL error reporting (strata/gl/context.h, gl_error.h).
#include "gl_test_support.h"

#include "strata/core/error.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <string>

namespace strata::gl {
namespace {

using test::GlTest;

class ContextGl : public GlTest {};

// The message checkGl throws, or "" if it does not throw.
std::string checkGlMessage(const char* what) {
    try {
        checkGl(what);
    } catch (const Error& error) {
        return error.what();
    }
    return {};
}

// Binding a name that glGenTextures never returned is GL_INVALID_OPERATION in a core profile.
void causeInvalidOperation() {
    glBindTexture(GL_TEXTURE_2D, 0x7fff1234u);
}

TEST_F(ContextGl, ReportsTheRendererAndVersion) {
    const HeadlessContext* context = test::sharedGlContext();
    EXPECT_FALSE(context->rendererName().empty());
    EXPECT_EQ(context->versionString().rfind("4.", 0), 0u) << context->versionString();
    EXPECT_GE(epoxy_gl_version(), 45);
}

TEST_F(ContextGl, CheckGlThrowsTheErrorAndWhereItHappened) {
    EXPECT_EQ(checkGlMessage("nothing"), "");
    causeInvalidOperation();
    const std::string message = checkGlMessage("binding a texture");
    EXPECT_NE(message.find("GL_INVALID_OPERATION"), std::string::npos) << message;
    EXPECT_NE(message.find("after binding a texture"), std::string::npos) << message;
    // The error was drained: the next check is clean.
    EXPECT_EQ(checkGlMessage("after the drain"), "");
}

// A debug context records the driver's own message for the failing call, and checkGl adds it.
TEST_F(ContextGl, DebugContextAddsTheDriversMessage) {
    HeadlessContext* shared = test::sharedGlContext();
    {
        const auto debug = HeadlessContext::create(GlDebug::On);
        ASSERT_TRUE(debug->isDebug()) << "no GL_KHR_debug output on " << debug->rendererName();
        GLint flags = 0;
        glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
        EXPECT_NE(flags & GL_CONTEXT_FLAG_DEBUG_BIT, 0);
        causeInvalidOperation();
        const std::string message = checkGlMessage("binding a texture");
        EXPECT_NE(message.find("GL_INVALID_OPERATION"), std::string::npos) << message;
        // The recorded text follows the error names after "; " and names the call.
        const std::size_t recorded = message.find("; ");
        ASSERT_NE(recorded, std::string::npos) << message;
        EXPECT_NE(message.find("BindTexture", recorded), std::string::npos) << message;
        EXPECT_EQ(checkGlMessage("after the drain"), "");
    }
    {
        const auto plain = HeadlessContext::create(GlDebug::Off);
        EXPECT_FALSE(plain->isDebug());
    }
    // Destroying a current context leaves none current: the suite's context again for the next tests.
    shared->makeCurrent();
}

}  // namespace
}  // namespace strata::gl
