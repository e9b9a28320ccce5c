#include "strata/gl/program.h"

#include "strata/core/error.h"
#include "strata/gl/gl_error.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace strata::gl {

Program::~Program() {
    if (mId != 0) glDeleteProgram(mId);
}

Program::Program(Program&& other) noexcept
    : mId(std::exchange(other.mId, 0)), mLocations(std::move(other.mLocations)) {}

Program& Program::operator=(Program&& other) noexcept {
    if (this != &other) {
        if (mId != 0) glDeleteProgram(mId);
        mId = std::exchange(other.mId, 0);
        mLocations = std::move(other.mLocations);
    }
    return *this;
}

int Program::uniformLocation(const std::string& name) const {
    const auto it = mLocations.find(name);
    if (it != mLocations.end()) return it->second;
    const int location = glGetUniformLocation(mId, name.c_str());
    mLocations.emplace(name, location);
    return location;
}

namespace {

// Rewrites the source-string numbers of a driver log into file names. Formats: Mesa "0:12(5): error: ...",
// NVIDIA "0(12) : error C0000: ...", AMD and glslang "ERROR: 0:12: ...".
std::string mapLog(const std::string& log, const std::vector<std::string>& files) {
    static const std::regex mesa(R"(^(\s*)(\d+):(\d+)\((\d+)\))");
    static const std::regex nvidia(R"(^(\s*)(\d+)\((\d+)\))");
    static const std::regex amd(R"(^(\s*\w+: )(\d+):(\d+):)");
    const auto name = [&](const std::string& index) {
        const std::size_t i = std::stoul(index);
        return i < files.size() ? files[i] : "source " + index;
    };
    std::string result;
    std::istringstream stream(log);
    for (std::string line; std::getline(stream, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::smatch match;
        if (std::regex_search(line, match, mesa)) {
            result += match[1].str() + name(match[2]) + ":" + match[3].str() + "(" + match[4].str() + ")" +
                      match.suffix().str();
        } else if (std::regex_search(line, match, nvidia)) {
            result += match[1].str() + name(match[2]) + ":" + match[3].str() + match.suffix().str();
        } else if (std::regex_search(line, match, amd)) {
            result += match[1].str() + name(match[2]) + ":" + match[3].str() + ":" + match.suffix().str();
        } else {
            result += line;
        }
        result += "\n";
    }
    return result;
}

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    return log;
}

GLuint compileStage(GLenum stage, const PreprocessedSource& source, const std::string& path,
                    const std::string& label) {
    const GLuint shader = glCreateShader(stage);
    const char* text = source.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = mapLog(shaderLog(shader), source.files);
        glDeleteShader(shader);
        throw Error(ErrorKind::Runtime, "compiling " + path + " (program " + label + ") failed:\n" + log);
    }
    return shader;
}

}  // namespace

Program buildProgram(const ShaderLibrary& library, const std::string& vertexPath,
                     const std::string& fragmentPath, const std::vector<std::string>& defines,
                     const std::string& label) {
    const PreprocessedSource vertexSource = library.preprocess(vertexPath, defines);
    const PreprocessedSource fragmentSource = library.preprocess(fragmentPath, defines);
    checkGl(("before building program " + label).c_str());
    const GLuint vertex = compileStage(GL_VERTEX_SHADER, vertexSource, vertexPath, label);
    GLuint fragment = 0;
    try {
        fragment = compileStage(GL_FRAGMENT_SHADER, fragmentSource, fragmentPath, label);
    } catch (...) {
        glDeleteShader(vertex);
        throw;
    }
    Program program(glCreateProgram());
    glAttachShader(program.id(), vertex);
    glAttachShader(program.id(), fragment);
    glLinkProgram(program.id());
    glDetachShader(program.id(), vertex);
    glDetachShader(program.id(), fragment);
    glDeleteShader(vertex);
    glDeleteShader(fragment);
    GLint ok = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint length = 0;
        glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &length);
        std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program.id(), length, nullptr, log.data());
        log.resize(std::strlen(log.c_str()));
        throw Error(ErrorKind::Runtime, "linking " + vertexPath + " + " + fragmentPath + " (program " +
                                            label + ") failed:\n" + mapLog(log, fragmentSource.files));
    }
    checkGl(("building program " + label).c_str());
    return program;
}

}  // namespace strata::gl
