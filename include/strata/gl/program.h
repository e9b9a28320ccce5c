// The shader library, for every renderer in strata::gl: GLSL programs from the shader sources under
// shaders/ (embedded into the binary at build time by cmake/StrataShaders.cmake, so nothing at run time
// reads the source tree).
//
// Sources. A ShaderLibrary maps paths ("relief/relief.frag.glsl", "shared/ao_rescale.h") to text. A stage
// file starts with its `#version` line. `#include "name"` on a line of its own is resolved at load, first
// relative to the including file's folder, then to the library root; each file is pasted once per stage
// (like #pragma once; the include is not conditional on surrounding #if blocks). The shared GLSL/C++
// headers (shaders/shared/*.h) are included this way.
//
// Line numbers. The preprocessed text numbers every file as a GLSL source string (index into
// PreprocessedSource::files: 0 is the stage file) and marks each switch with `#line <line> <index>`, so the
// driver's log says "<index>:<line>"; buildProgram rewrites that to "<file>:<line>" before throwing.
//
// Variants. A renderer builds one program per set of flags, passed as `defines` (placed right after the
// `#version` line); the relief renderer's variants are src/gl/relief_program.h.
#pragma once

#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace strata::gl {

enum class ShaderStage { Vertex, Fragment };

struct PreprocessedSource {
    std::string text;                // complete GLSL, `#version` first
    std::vector<std::string> files;  // GLSL source-string number -> library path
};

class ShaderLibrary {
public:
    ShaderLibrary() = default;
    // path -> source text. Paths use '/', relative to the library root.
    explicit ShaderLibrary(std::map<std::string, std::string> files);

    // The shaders compiled into strata::gl (every .glsl under shaders/ and shaders/shared/*.h).
    static const ShaderLibrary& embedded();

    bool contains(const std::string& path) const { return mFiles.count(path) != 0; }
    const std::map<std::string, std::string>& files() const { return mFiles; }

    // The stage file at `path` with includes resolved, `defines` ("NAME" or "NAME VALUE") inserted after
    // its `#version` line, and #line directives. Throws Error(InvalidInput) naming the file and line for a
    // missing file, a missing or misplaced #version, an include that cannot be found, or an include cycle.
    PreprocessedSource preprocess(const std::string& path, const std::vector<std::string>& defines) const;

private:
    std::map<std::string, std::string> mFiles;
};

// A linked program (move-only; deleting it needs the context it was made in to be current).
class Program {
public:
    Program() = default;
    explicit Program(unsigned id) : mId(id) {}
    ~Program();
    Program(Program&& other) noexcept;
    Program& operator=(Program&& other) noexcept;
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;

    unsigned id() const { return mId; }
    // Location of a uniform, cached; -1 if the program has none of that name (or it was optimised away;
    // glUniform* ignores -1).
    int uniformLocation(const std::string& name) const;

private:
    unsigned mId = 0;
    mutable std::unordered_map<std::string, int> mLocations;
};

// Compiles and links the vertex and fragment stage files of `library` with `defines`. Throws
// Error(InvalidInput) from preprocess, and Error(Runtime) when compiling or linking fails: the message names
// `label`, the stage file, and carries the driver's log with source-string numbers replaced by file names
// ("relief/relief.frag.glsl:42(7): error: ..."). Needs a current GL 4.5 core context. This is also the
// test entry point: a test builds a ShaderLibrary of its own (e.g. a broken shader).
Program buildProgram(const ShaderLibrary& library, const std::string& vertexPath,
                     const std::string& fragmentPath, const std::vector<std::string>& defines,
                     const std::string& label);

}  // namespace strata::gl
