// Shared by the suites that need OpenGL (gl, viewer): one headless context for the whole test process, and a
// fixture that skips cleanly (GTEST_SKIP) where no OpenGL 4.5 core context can be made, and fails a test that
// leaves a GL error behind.
#pragma once

#include "strata/gl/context.h"
#include "strata/gl/gl_error.h"
#include "strata/mesh/mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

namespace strata::test {

// The process's context, made on first use on the calling thread; null (with `whyNot` set) if none can be
// made.
inline gl::HeadlessContext* sharedGlContext(std::string* whyNot = nullptr) {
    static std::string failure;
    static std::unique_ptr<gl::HeadlessContext> context = [] {
        try {
            return gl::HeadlessContext::create();
        } catch (const std::exception& error) {
            failure = error.what();
            return std::unique_ptr<gl::HeadlessContext>();
        }
    }();
    if (whyNot != nullptr) *whyNot = failure;
    return context.get();
}

class GlTest : public ::testing::Test {
protected:
    void SetUp() override {
        std::string whyNot;
        if (sharedGlContext(&whyNot) == nullptr) GTEST_SKIP() << "no OpenGL 4.5 core context: " << whyNot;
    }
    void TearDown() override {
        if (sharedGlContext() != nullptr) {
            EXPECT_NO_THROW(gl::checkGl("the end of the test"));
        }
    }
};

// Where failing tests write their pictures: a folder in the build tree, beside the test executable.
inline std::filesystem::path failureDirectory(const std::string& name) {
    std::error_code error;
    const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
    const std::filesystem::path base = error ? std::filesystem::current_path() : executable.parent_path();
    return base / "gl_test_failures" / name;
}

}  // namespace strata::test
