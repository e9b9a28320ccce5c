#include "strata/gl/program.h"

#include "embedded_shaders.h"
#include "strata/core/error.h"

#include <algorithm>
#include <regex>
#include <set>
#include <sstream>
#include <utility>

namespace strata::gl {

ShaderLibrary::ShaderLibrary(std::map<std::string, std::string> files) : mFiles(std::move(files)) {}

const ShaderLibrary& ShaderLibrary::embedded() {
    static const ShaderLibrary library = [] {
        std::map<std::string, std::string> files;
        for (std::size_t i = 0; i < detail::kEmbeddedShaderFileCount; ++i) {
            files.emplace(detail::kEmbeddedShaderFiles[i].path,
                          std::string(detail::kEmbeddedShaderFiles[i].content));
        }
        return ShaderLibrary(std::move(files));
    }();
    return library;
}

namespace {

std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream stream(text);
    for (std::string line; std::getline(stream, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        lines.push_back(line);
    }
    return lines;
}

std::string folderOf(const std::string& path) {
    const std::size_t slash = path.rfind('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// "a/b/../c.glsl" -> "a/c.glsl"; "./" removed.
std::string normalisePath(const std::string& path) {
    std::vector<std::string> parts;
    std::istringstream stream(path);
    for (std::string part; std::getline(stream, part, '/');) {
        if (part.empty() || part == ".") continue;
        if (part == ".." && !parts.empty() && parts.back() != "..") {
            parts.pop_back();
        } else {
            parts.push_back(part);
        }
    }
    std::string result;
    for (const std::string& part : parts) result += (result.empty() ? "" : "/") + part;
    return result;
}

bool isVersionLine(const std::string& line) {
    static const std::regex pattern(R"(^\s*#\s*version\b.*)");
    return std::regex_match(line, pattern);
}

class Preprocessor {
public:
    explicit Preprocessor(const std::map<std::string, std::string>& library) : mFiles(library) {}

    // Appends `path` from line `firstLine` (1-based) on, resolving includes.
    void append(const std::string& path, std::size_t firstLine, std::vector<std::string>& stack) {
        static const std::regex includePattern(R"re(^\s*#\s*include\s+"([^"]+)"\s*(//.*)?$)re");
        const int index = fileIndex(path);
        const std::vector<std::string> lines = splitLines(mFiles.at(path));
        stack.push_back(path);
        for (std::size_t i = firstLine - 1; i < lines.size(); ++i) {
            const std::string& line = lines[i];
            std::smatch match;
            if (isVersionLine(line)) {
                fail(path, i + 1, "#version is allowed only on the first line of a stage file");
            }
            if (!std::regex_match(line, match, includePattern)) {
                out += line + "\n";
                continue;
            }
            const std::string name = match[1].str();
            std::string resolved = normalisePath(folderOf(path) + name);
            if (mFiles.count(resolved) == 0) resolved = normalisePath(name);
            if (mFiles.count(resolved) == 0) {
                fail(path, i + 1,
                     "#include \"" + name + "\" not found (looked in '" + folderOf(path) +
                         "' and the shader root)");
            }
            if (std::find(stack.begin(), stack.end(), resolved) != stack.end()) {
                fail(path, i + 1, "#include \"" + name + "\" is an include cycle");
            }
            if (mIncluded.insert(resolved).second) {
                out += "#line 1 " + std::to_string(fileIndex(resolved)) + "\n";
                append(resolved, 1, stack);
                out += "#line " + std::to_string(i + 2) + " " + std::to_string(index) + "\n";
            } else {
                out += "\n";  // already pasted (include once); keep the line count
            }
        }
        stack.pop_back();
    }

    int fileIndex(const std::string& path) {
        const auto it = std::find(files.begin(), files.end(), path);
        if (it != files.end()) return static_cast<int>(it - files.begin());
        files.push_back(path);
        return static_cast<int>(files.size() - 1);
    }

    [[noreturn]] static void fail(const std::string& path, std::size_t line, const std::string& what) {
        throw Error(ErrorKind::InvalidInput, "shader " + path + ":" + std::to_string(line) + ": " + what);
    }

    std::string out;
    std::vector<std::string> files;

private:
    const std::map<std::string, std::string>& mFiles;
    std::set<std::string> mIncluded;
};

}  // namespace

PreprocessedSource ShaderLibrary::preprocess(const std::string& path,
                                             const std::vector<std::string>& defines) const {
    const auto it = mFiles.find(path);
    if (it == mFiles.end()) {
        throw Error(ErrorKind::InvalidInput, "shader " + path + ": no such file in the shader library");
    }
    const std::vector<std::string> lines = splitLines(it->second);
    if (lines.empty() || !isVersionLine(lines[0])) {
        Preprocessor::fail(path, 1, "a stage file must start with its #version line");
    }
    Preprocessor preprocessor(mFiles);
    preprocessor.fileIndex(path);
    preprocessor.out = lines[0] + "\n";
    for (const std::string& define : defines) preprocessor.out += "#define " + define + "\n";
    preprocessor.out += "#line 2 0\n";
    std::vector<std::string> stack;
    preprocessor.append(path, 2, stack);
    return {std::move(preprocessor.out), std::move(preprocessor.files)};
}

}  // namespace strata::gl
