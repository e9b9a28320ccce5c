// Programs: include resolution, #line mapping of driver errors, every variant in GL and in glslangValidator,
// and the shared GLSL/C++ step count.
#include "gl/relief_program.h"  // internal: the relief renderer's variants
#include "gl_test_support.h"
#include "shared/relief_search.h"
#include "shared/relief_uniforms.h"
#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/gl/program.h"
#include "strata/gl/relief_renderer.h"
#include "strata/scene/render_settings.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace strata::gl {
namespace {

using test::GlTest;

std::string errorMessage(const auto& call) {
    try {
        call();
    } catch (const Error& error) {
        return error.what();
    }
    return "(no error)";
}

TEST(ShaderLibrary, ResolvesIncludesOnceWithLineDirectives) {
    const ShaderLibrary library(
        {{"main.frag.glsl", "#version 450 core\n#include \"lib/a.glsl\"\nvoid main() {}\n"},
         {"lib/a.glsl", "#include \"b.glsl\"\nfloat a;\n#include \"b.glsl\"\n"},
         {"lib/b.glsl", "float b;\n"}});
    const PreprocessedSource source = library.preprocess("main.frag.glsl", {"FLAG", "VALUE 2"});
    // #version first, then the defines, then every file switch marked with #line <next line> <file>.
    EXPECT_EQ(source.text,
              "#version 450 core\n#define FLAG\n#define VALUE 2\n#line 2 0\n"
              "#line 1 1\n#line 1 2\nfloat b;\n#line 2 1\nfloat a;\n\n#line 3 0\nvoid main() {}\n");
    ASSERT_EQ(source.files.size(), 3u);
    EXPECT_EQ(source.files[1], "lib/a.glsl");
    EXPECT_EQ(source.files[2], "lib/b.glsl");
}

TEST(ShaderLibrary, ReportsMissingIncludesAndCycles) {
    const ShaderLibrary library({{"m.vert.glsl", "#version 450 core\n\n#include \"nope.glsl\"\n"},
                                 {"c.vert.glsl", "#version 450 core\n#include \"x.glsl\"\n"},
                                 {"x.glsl", "#include \"x.glsl\"\n"},
                                 {"noversion.vert.glsl", "void main() {}\n"}});
    EXPECT_NE(errorMessage([&] { library.preprocess("m.vert.glsl", {}); }).find("m.vert.glsl:3"),
              std::string::npos);
    EXPECT_NE(errorMessage([&] { library.preprocess("c.vert.glsl", {}); }).find("cycle"), std::string::npos);
    EXPECT_NE(errorMessage([&] { library.preprocess("noversion.vert.glsl", {}); }).find("#version"),
              std::string::npos);
    EXPECT_NE(errorMessage([&] { library.preprocess("absent.glsl", {}); }).find("absent.glsl"),
              std::string::npos);
}

TEST(ShaderLibrary, EmbedsTheShaderTree) {
    const ShaderLibrary& library = ShaderLibrary::embedded();
    EXPECT_TRUE(library.contains(kSurfaceVertexShader));
    EXPECT_TRUE(library.contains(kSurfaceFragmentShader));
    EXPECT_TRUE(library.contains("relief/relief_search.glsl"));
    EXPECT_TRUE(library.contains("shared/ao_rescale.h"));
    EXPECT_TRUE(library.contains("shared/relief_search.h"));
    EXPECT_TRUE(library.contains("shared/prelude.h"));
    EXPECT_TRUE(library.contains("shared/bilinear_cell.h"));
    EXPECT_TRUE(library.contains("shared/maxmip.h"));
    EXPECT_TRUE(library.contains("shared/cone.h"));
}

// Every shared GLSL/C++ header (shaders/shared/*.h) is pasted into some variant, so that PassGlslangValidator
// and EveryVariantCompilesAndLinks compile it as GLSL; C++ compiles it in the libraries and tests.
TEST(ProgramVariants, EverySharedHeaderIsIncludedByAProgram) {
    std::set<std::string> included;
    for (const ProgramVariant& variant : allVariants()) {
        for (const ShaderStage stage : {ShaderStage::Vertex, ShaderStage::Fragment}) {
            for (const std::string& file : variantSource(variant, stage).files) included.insert(file);
        }
    }
    // The GDM renderer's program (gdm_renderer.cpp) has no variants.
    for (const char* stage : {"gdm/gdm.vert.glsl", "gdm/gdm.frag.glsl"})
        for (const std::string& file : ShaderLibrary::embedded().preprocess(stage, {}).files)
            included.insert(file);
    int shared = 0;
    for (const auto& [path, text] : ShaderLibrary::embedded().files()) {
        if (path.rfind("shared/", 0) != 0) continue;
        ++shared;
        EXPECT_EQ(included.count(path), 1u) << path << " is in no variant";
    }
    EXPECT_GE(shared, 7);  // prelude, ao_rescale, relief_search, bilinear_cell, maxmip, cone, gdm_lookup
}

TEST(ProgramVariants, AreDistinctAndCanonical) {
    const std::vector<ProgramVariant> variants = allVariants();
    // Baked: shaded, x shadows for every technique: texture 2 (no AO: it reads no relief texture for
    // shading), normal 6 (x AO modes), parallax 12 and relief 12 (x AO modes x depth correction); uv and
    // depth 6 each (texture, normal, and parallax and relief x depth correction); shadow 12 (the same 6 x
    // shadows); plain 4 (one per output): 60. Live doubles every variant that reads the relief (a search,
    // the shadow test, or normal mapping's shaded normal): 1 + 6 + 12 + 12 shaded, 2 + 2 uv and depth,
    // 1 + 1 + 4 + 4 shadow: 49 more. maxmip and cone (baked only) as relief: 12 shaded, 2 + 2 uv and depth,
    // 4 shadow, 20 each. dual-depth (no AO, not live): 4 shaded (depth correction x shadows), 2 + 2 uv and
    // depth, 4 shadow.
    EXPECT_EQ(variants.size(), 161u);
    std::set<std::string> names;
    for (const ProgramVariant& variant : variants) {
        EXPECT_EQ(canonical(variant), variant);
        EXPECT_TRUE(names.insert(variantName(variant)).second) << variantName(variant);
    }
}

// The shared step count (shaders/shared/relief_search.h, float) against adaptiveLinearSteps (double).
TEST(ProgramVariants, SharedStepCountMatchesRenderSettings) {
    for (const int n : {1, 5, 10, 32, 64, 100, 1024}) {
        for (int i = 0; i <= 1000; ++i) {
            const double c = i / 1000.0;
            const int expected = adaptiveLinearSteps(n, c);
            const int actual = shared::reliefLinearSteps(n, static_cast<float>(c));
            // Float and double may round a value within float precision of k + 0.5 differently: one step.
            EXPECT_LE(std::abs(actual - expected), 1) << "n " << n << " cos " << c;
            // Away from such ties they agree exactly.
            const double x = n / std::max(c, 0.25) + 0.5;
            if (std::abs(x - std::round(x)) > 1e-4) {
                EXPECT_EQ(actual, expected) << "n " << n << " cos " << c;
            }
        }
    }
}

// glslangValidator (the reference GLSL front end) on both stages of every variant: one test listing every
// failure with its log.
TEST(ProgramVariants, PassGlslangValidator) {
    const std::string validator = STRATA_GLSLANG_VALIDATOR;
    if (validator.empty()) {
        FAIL() << "glslangValidator not found (glslang-tools); run scripts/install-deps.sh";
    }
    const std::filesystem::path dir = test::failureDirectory("glslang_variants");
    std::filesystem::create_directories(dir);
    // One run over all files (glslangValidator takes the stage from the extension and compiles each file
    // on its own); its log names the file of every error.
    std::string command = "'" + validator + "'";
    int checked = 0;
    for (const ProgramVariant& variant : allVariants()) {
        for (const ShaderStage stage : {ShaderStage::Vertex, ShaderStage::Fragment}) {
            const std::filesystem::path file =
                dir / (variantName(variant) + (stage == ShaderStage::Vertex ? ".vert" : ".frag"));
            std::ofstream(file) << variantSource(variant, stage).text;
            command += " '" + file.string() + "'";
            ++checked;
        }
    }
    const std::filesystem::path log = dir / "glslang.log";
    const int status = std::system((command + " > '" + log.string() + "' 2>&1").c_str());
    const std::string failures = status == 0 ? std::string() : readTextFile(log);
    EXPECT_EQ(checked, 322);
    EXPECT_TRUE(failures.empty()) << failures;
}

class ProgramGl : public GlTest {};

TEST_F(ProgramGl, EveryVariantCompilesAndLinks) {
    ReliefRenderer renderer;
    for (const ProgramVariant& variant : allVariants()) {
        EXPECT_NO_THROW(renderer.prepare(variant)) << variantName(variant);
    }
}

// The driver lays the per-draw block out as the C++ struct says (shaders/shared/relief_uniforms.h): its
// static_asserts check the C++ side against std140's rules, this checks the GLSL side against the same
// numbers. Exact: byte offsets.
TEST_F(ProgramGl, UniformBlockLayoutIsTheSharedStruct) {
    using shared::ReliefUniforms;
    ProgramVariant variant;
    variant.live = true;
    variant.shadows = true;
    variant.ao = AoMode::Paper;
    const Program program = buildVariantProgram(variant);
    const GLuint block = glGetProgramResourceIndex(program.id(), GL_UNIFORM_BLOCK, "ReliefUniforms");
    ASSERT_NE(block, GL_INVALID_INDEX);
    const GLenum sizeProperty = GL_BUFFER_DATA_SIZE;
    GLint size = 0;
    glGetProgramResourceiv(program.id(), GL_UNIFORM_BLOCK, block, 1, &sizeProperty, 1, nullptr, &size);
    EXPECT_EQ(static_cast<std::size_t>(size), sizeof(ReliefUniforms));
#define STRATA_MEMBER(name, glslName) \
    { glslName, offsetof(ReliefUniforms, name) }
    const struct {
        const char* name;
        std::size_t offset;
    } members[] = {STRATA_MEMBER(uModel, "uModel"),
                   STRATA_MEMBER(uViewProjection, "uViewProjection"),
                   STRATA_MEMBER(uNormalMatrix, "uNormalMatrix"),
                   STRATA_MEMBER(uEye, "uEye"),
                   STRATA_MEMBER(uMirror, "uMirror"),
                   STRATA_MEMBER(uLightPosition, "uLightPosition"),
                   STRATA_MEMBER(uTiling, "uTiling"),
                   STRATA_MEMBER(uLightColor, "uLightColor"),
                   STRATA_MEMBER(uDepthScale, "uDepthScale"),
                   STRATA_MEMBER(uPlainColor, "uPlainColor"),
                   STRATA_MEMBER(uNormalScale, "uNormalScale"),
                   STRATA_MEMBER(uLinearSteps, "uLinearSteps"),
                   STRATA_MEMBER(uBinarySteps, "uBinarySteps"),
                   STRATA_MEMBER(uAmbient, "uAmbient"),
                   STRATA_MEMBER(uSpecular, "uSpecular"),
                   STRATA_MEMBER(uShininess, "uShininess"),
                   STRATA_MEMBER(uAoScale, "uAoScale"),
                   STRATA_MEMBER(uEncodeSrgb, "uEncodeSrgb"),
                   STRATA_MEMBER(uColorTiling, "uColorTiling"),
                   STRATA_MEMBER(uMaxMipLevels, "uMaxMipLevels"),
                   STRATA_MEMBER(uConeMaxRatio, "uConeMaxRatio"),
                   STRATA_MEMBER(uLayerCount, "uLayerCount"),
                   STRATA_MEMBER(uMetaConsistent, "uMetaConsistent"),
                   STRATA_MEMBER(uMetaAo, "uMetaAo"),
                   STRATA_MEMBER(uLayerTiling, "uLayerTiling[0]"),
                   STRATA_MEMBER(uLayerDepthWeight, "uLayerDepthWeight[0]"),
                   STRATA_MEMBER(uLayerRestLow, "uLayerRestLow[0]"),
                   STRATA_MEMBER(uLayerRestHigh, "uLayerRestHigh[0]"),
                   STRATA_MEMBER(uLayerNormalWeight, "uLayerNormalWeight[0]"),
                   STRATA_MEMBER(uLayerAoScale, "uLayerAoScale[0]"),
                   STRATA_MEMBER(uLayerNormalScale, "uLayerNormalScale[0]")};
#undef STRATA_MEMBER
    for (const auto& member : members) {
        const GLuint index = glGetProgramResourceIndex(program.id(), GL_UNIFORM, member.name);
        ASSERT_NE(index, GL_INVALID_INDEX) << member.name;
        const GLenum properties[] = {GL_BLOCK_INDEX, GL_OFFSET, GL_ARRAY_STRIDE, GL_MATRIX_STRIDE};
        GLint values[4] = {};
        glGetProgramResourceiv(program.id(), GL_UNIFORM, index, 4, properties, 4, nullptr, values);
        EXPECT_EQ(values[0], static_cast<GLint>(block)) << member.name;
        EXPECT_EQ(static_cast<std::size_t>(values[1]), member.offset) << member.name;
        const bool array = std::string(member.name).find('[') != std::string::npos;
        EXPECT_EQ(values[2], array ? 16 : 0) << member.name;  // std140: a float array element per 16 bytes
    }
    const GLuint normalMatrix = glGetProgramResourceIndex(program.id(), GL_UNIFORM, "uNormalMatrix");
    const GLenum matrixStride = GL_MATRIX_STRIDE;
    GLint stride = 0;
    glGetProgramResourceiv(program.id(), GL_UNIFORM, normalMatrix, 1, &matrixStride, 1, nullptr, &stride);
    EXPECT_EQ(stride, 16);  // a mat3's columns, 16 bytes apart (glm::mat3x4 in C++)
}

TEST_F(ProgramGl, CompileErrorNamesFileAndLine) {
    const ShaderLibrary library(
        {{"t.vert.glsl", "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n"},
         {"t.frag.glsl",
          "#version 450 core\n#include \"inc/broken.glsl\"\nout vec4 c;\nvoid main() { c = f(); }\n"},
         {"inc/broken.glsl", "// line 1\n// line 2\nvec4 f() { return undefinedThing; }\n"}});
    const std::string message =
        errorMessage([&] { buildProgram(library, "t.vert.glsl", "t.frag.glsl", {}, "broken"); });
    // The error is on line 3 of the included file, whatever the driver's message format.
    EXPECT_TRUE(std::regex_search(message, std::regex(R"(inc/broken\.glsl:3\b)"))) << message;
    EXPECT_NE(message.find("t.frag.glsl"), std::string::npos) << message;
    EXPECT_NE(message.find("undefinedThing"), std::string::npos) << message;
}

TEST_F(ProgramGl, LinkErrorIsReported) {
    const ShaderLibrary library(
        {{"t.vert.glsl",
          "#version 450 core\nout float x;\nvoid main() { x = 1.0; gl_Position = vec4(0.0); }\n"},
         {"t.frag.glsl",
          "#version 450 core\nin vec2 x;\nout vec4 c;\nvoid main() { c = vec4(x, 0.0, 1.0); }\n"}});
    const std::string message =
        errorMessage([&] { buildProgram(library, "t.vert.glsl", "t.frag.glsl", {}, "mismatch"); });
    EXPECT_NE(message.find("linking"), std::string::npos) << message;
}

}  // namespace
}  // namespace strata::gl
