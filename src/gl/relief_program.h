// The relief renderer's programs (internal to strata::gl): which flags select one program of
// shaders/relief/relief.{vert,frag}.glsl, and how they are built from the embedded shader library
// (strata/gl/program.h).
//
// Variants. One program per ProgramVariant: the flags become `#define`s placed right after the `#version`
// line (variantDefines lists them). allVariants() enumerates every distinct variant (flags that do not
// matter for a combination are normalised away by canonical()), for the GL compile test and the
// glslangValidator test (tests/gl/test_program.cpp).
#pragma once

#include "strata/gl/program.h"
#include "strata/scene/render_settings.h"

#include <compare>
#include <string>
#include <vector>

namespace strata::gl {

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
