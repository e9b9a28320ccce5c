// GLSL programs from the shader sources under shaders/ (embedded into the binary at build time by
// cmake/StrataShaders.cmake, so nothing at run time reads the source tree).
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
// Variants. One program per ProgramVariant: the renderer's flags become `#define`s placed right after the
// `#version` line (variantDefines lists them). allVariants() enumerates every distinct variant (flags that
// do not matter for a combination are normalised away by canonical()), for the GL compile test and the
// glslangValidator test.
#pragma once

#include "strata/scene/render_settings.h"

#include <compare>
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

// How a surface's ambient term uses the material's AO channel.
enum class AoMode {
    Off,    // no AO (relief.ao off, or the material has none)
    Baked,  // the map as baked (AoRescale::Off, or Exact: the caller re-baked it at the render's S)
    Paper,  // rescaled per fragment with aoRescalePaper(ao, S_render / S_ao) (AoRescale::Paper)
};

// The flags that select one program of shaders/relief/relief.{vert,frag}.glsl.
struct ProgramVariant {
    Technique technique = Technique::Relief;
    RenderOutput output = RenderOutput::Shaded;
    bool plain = false;            // no material: Blinn-Phong of a uniform colour (the technique is ignored)
    bool shadows = false;          // self-shadowing, the light-ray test (shaded and shadow outputs)
    bool depthCorrection = false;  // gl_FragDepth at the relief point (relief, parallax)
    AoMode ao = AoMode::Off;       // shaded output only
    bool live = false;             // a live meta-relief's layers instead of one packed texture

    auto operator<=>(const ProgramVariant&) const = default;
};

// The variant with every flag that does not affect its program reset to its default.
ProgramVariant canonical(ProgramVariant variant);
// Every distinct canonical variant, in a stable order.
std::vector<ProgramVariant> allVariants();
// e.g. "relief-shaded-shadows-depthcorrect-aopaper"; unique per canonical variant, usable as a file name.
std::string variantName(const ProgramVariant& variant);
// The #defines of a variant (STRATA_TECHNIQUE_RELIEF, STRATA_OUTPUT_UV, STRATA_SHADOWS, ...).
std::vector<std::string> variantDefines(const ProgramVariant& variant);
// The stage files of the surface programs.
inline constexpr const char* kSurfaceVertexShader = "relief/relief.vert.glsl";
inline constexpr const char* kSurfaceFragmentShader = "relief/relief.frag.glsl";
// The full preprocessed source of one stage of a variant (from the embedded library), e.g. to dump it or
// feed it to glslangValidator.
PreprocessedSource variantSource(const ProgramVariant& variant, ShaderStage stage);
// Compiles and links the variant's program (buildProgram on the embedded library).
Program buildVariantProgram(const ProgramVariant& variant);

}  // namespace strata::gl
