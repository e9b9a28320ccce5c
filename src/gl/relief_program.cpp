#include "relief_program.h"

#include "strata/core/check.h"

#include <algorithm>

namespace strata::gl {

ProgramVariant canonical(ProgramVariant variant) {
    if (variant.plain) {
        variant.technique = Technique::Texture;
        variant.shadows = false;
        variant.depthCorrection = false;
        variant.ao = AoMode::Off;
        variant.live = false;
        return variant;
    }
    const bool displaced = variant.technique == Technique::Relief ||
                           variant.technique == Technique::Parallax ||
                           variant.technique == Technique::MaxMip || variant.technique == Technique::Cone ||
                           variant.technique == Technique::DualDepth;
    if (variant.output != RenderOutput::Shaded && variant.output != RenderOutput::Shadow)
        variant.shadows = false;
    if (!displaced) variant.depthCorrection = false;
    // Texture mapping reads no AO; a dual-depth texture has none (its B channel is the front depth).
    if (variant.output != RenderOutput::Shaded || variant.technique == Technique::Texture ||
        variant.technique == Technique::DualDepth)
        variant.ao = AoMode::Off;
    // Live layers matter where the program reads the relief: a search, the shadow test, or normal mapping.
    const bool readsRelief =
        displaced || variant.shadows ||
        (variant.technique == Technique::Normal && variant.output == RenderOutput::Shaded);
    // The maximum mipmap and the cone map are built from one baked depth texture (uploadMaterial).
    if (!readsRelief || variant.technique == Technique::MaxMip || variant.technique == Technique::Cone ||
        variant.technique == Technique::DualDepth)
        variant.live = false;
    return variant;
}

std::vector<ProgramVariant> allVariants() {
    std::vector<ProgramVariant> variants;
    for (const bool plain : {false, true}) {
        for (const Technique technique : kAllTechniques) {
            for (const RenderOutput output :
                 {RenderOutput::Shaded, RenderOutput::Uv, RenderOutput::Shadow, RenderOutput::Depth}) {
                for (const bool shadows : {false, true}) {
                    for (const bool depthCorrection : {false, true}) {
                        for (const AoMode ao : {AoMode::Off, AoMode::Baked, AoMode::Paper}) {
                            for (const bool live : {false, true}) {
                                const ProgramVariant variant =
                                    canonical({technique, output, plain, shadows, depthCorrection, ao, live});
                                if (std::find(variants.begin(), variants.end(), variant) == variants.end()) {
                                    variants.push_back(variant);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    return variants;
}

std::string variantName(const ProgramVariant& variant) {
    std::string name = variant.plain ? "plain" : toString(variant.technique);
    name += std::string("-") + toString(variant.output);
    if (variant.shadows) name += "-shadows";
    if (variant.depthCorrection) name += "-depthcorrect";
    if (variant.ao == AoMode::Baked) name += "-ao";
    if (variant.ao == AoMode::Paper) name += "-aopaper";
    if (variant.live) name += "-live";
    return name;
}

std::vector<std::string> variantDefines(const ProgramVariant& variant) {
    std::vector<std::string> defines;
    if (variant.plain) {
        defines.emplace_back("STRATA_PLAIN");
    } else {
        switch (variant.technique) {
            case Technique::Texture:
                defines.emplace_back("STRATA_TECHNIQUE_TEXTURE");
                break;
            case Technique::Normal:
                defines.emplace_back("STRATA_TECHNIQUE_NORMAL");
                break;
            case Technique::Parallax:
                defines.emplace_back("STRATA_TECHNIQUE_PARALLAX");
                break;
            case Technique::Relief:
                defines.emplace_back("STRATA_TECHNIQUE_RELIEF");
                break;
            case Technique::MaxMip:
                defines.emplace_back("STRATA_TECHNIQUE_MAXMIP");
                break;
            case Technique::Cone:
                defines.emplace_back("STRATA_TECHNIQUE_CONE");
                break;
            case Technique::DualDepth:
                defines.emplace_back("STRATA_TECHNIQUE_DUAL_DEPTH");
                break;
        }
    }
    switch (variant.output) {
        case RenderOutput::Shaded:
            defines.emplace_back("STRATA_OUTPUT_SHADED");
            break;
        case RenderOutput::Uv:
            defines.emplace_back("STRATA_OUTPUT_UV");
            break;
        case RenderOutput::Shadow:
            defines.emplace_back("STRATA_OUTPUT_SHADOW");
            break;
        case RenderOutput::Depth:
            defines.emplace_back("STRATA_OUTPUT_DEPTH");
            break;
        case RenderOutput::Uvw:
        case RenderOutput::Mask:
            STRATA_CHECK(!"a GDM output reaches the relief program (validate refuses it)");
            break;
    }
    if (variant.shadows) defines.emplace_back("STRATA_SHADOWS");
    if (variant.depthCorrection) defines.emplace_back("STRATA_DEPTH_CORRECTION");
    if (variant.ao != AoMode::Off) defines.emplace_back("STRATA_AO");
    if (variant.ao == AoMode::Paper) defines.emplace_back("STRATA_AO_PAPER");
    if (variant.live) defines.emplace_back("STRATA_META_LIVE");
    return defines;
}

PreprocessedSource variantSource(const ProgramVariant& variant, ShaderStage stage) {
    const ProgramVariant v = canonical(variant);
    return ShaderLibrary::embedded().preprocess(
        stage == ShaderStage::Vertex ? kSurfaceVertexShader : kSurfaceFragmentShader, variantDefines(v));
}

Program buildVariantProgram(const ProgramVariant& variant) {
    const ProgramVariant v = canonical(variant);
    return buildProgram(ShaderLibrary::embedded(), kSurfaceVertexShader, kSurfaceFragmentShader,
                        variantDefines(v), variantName(v));
}

}  // namespace strata::gl
