#include "strata/scene/render_settings.h"

#include "strata/core/error.h"
#include "strata/relief/relief_texture.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <iterator>
#include <string>

namespace strata {

const char* toString(Technique technique) {
    switch (technique) {
        case Technique::Texture:
            return "texture";
        case Technique::Normal:
            return "normal";
        case Technique::Parallax:
            return "parallax";
        case Technique::Relief:
            return "relief";
        case Technique::MaxMip:
            return "maxmip";
        case Technique::Cone:
            return "cone";
        case Technique::DualDepth:
            return "dual-depth";
    }
    return "?";
}

const char* toString(RenderOutput output) {
    switch (output) {
        case RenderOutput::Shaded:
            return "shaded";
        case RenderOutput::Uv:
            return "uv";
        case RenderOutput::Shadow:
            return "shadow";
        case RenderOutput::Depth:
            return "depth";
        case RenderOutput::Uvw:
            return "uvw";
        case RenderOutput::Mask:
            return "mask";
    }
    return "?";
}

const char* toString(AoRescale rescale) {
    switch (rescale) {
        case AoRescale::Off:
            return "off";
        case AoRescale::Paper:
            return "paper";
        case AoRescale::Exact:
            return "exact";
    }
    return "?";
}

const char* toString(GdmTechnique technique) {
    switch (technique) {
        case GdmTechnique::Gdm:
            return "gdm";
        case GdmTechnique::Refine:
            return "refine";
        case GdmTechnique::March:
            return "march";
    }
    return "?";
}

const char* toString(GdmLightFrame frame) {
    switch (frame) {
        case GdmLightFrame::Tangent:
            return "tangent";
        case GdmLightFrame::Jacobian:
            return "jacobian";
    }
    return "?";
}

Technique parseTechnique(const std::string& text) {
    for (Technique t : kAllTechniques) {
        if (text == toString(t)) return t;
    }
    throw Error(ErrorKind::InvalidInput,
                "unknown technique '" + text +
                    "' (expected texture, normal, parallax, relief, maxmip, cone or dual-depth)");
}

RenderOutput parseRenderOutput(const std::string& text) {
    for (RenderOutput o : {RenderOutput::Shaded, RenderOutput::Uv, RenderOutput::Shadow, RenderOutput::Depth,
                           RenderOutput::Uvw, RenderOutput::Mask}) {
        if (text == toString(o)) return o;
    }
    throw Error(ErrorKind::InvalidInput,
                "unknown output '" + text +
                    "' (expected shaded, uv, shadow or depth; with a GDM shaded, uvw, "
                    "shadow or mask)");
}

GdmTechnique parseGdmTechnique(const std::string& text) {
    for (GdmTechnique t : {GdmTechnique::Gdm, GdmTechnique::Refine, GdmTechnique::March}) {
        if (text == toString(t)) return t;
    }
    throw Error(ErrorKind::InvalidInput,
                "unknown GDM technique '" + text + "' (expected gdm, refine or march)");
}

GdmLightFrame parseGdmLightFrame(const std::string& text) {
    for (GdmLightFrame f : {GdmLightFrame::Tangent, GdmLightFrame::Jacobian}) {
        if (text == toString(f)) return f;
    }
    throw Error(ErrorKind::InvalidInput,
                "unknown GDM light frame '" + text + "' (expected tangent or jacobian)");
}

int parseGdmRank(const std::string& text) {
    if (text == "raw") return kGdmRankRaw;
    std::size_t used = 0;
    int rank = 0;
    try {
        rank = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || rank < 1)
        throw Error(ErrorKind::InvalidInput, "GDM rank must be an integer >= 1 or 'raw', got '" + text + "'");
    return rank;
}

AoRescale parseAoRescale(const std::string& text) {
    for (AoRescale r : {AoRescale::Off, AoRescale::Paper, AoRescale::Exact}) {
        if (text == toString(r)) return r;
    }
    throw Error(ErrorKind::InvalidInput, "unknown AO rescale '" + text + "' (expected off, paper or exact)");
}

int adaptiveLinearSteps(int linearSteps, double cosTheta) {
    // N / max(|cos|, 1/4), rounded half up like GLSL's floor(x + 0.5).
    const double c = std::clamp(std::abs(cosTheta), 0.25, 1.0);
    return static_cast<int>(std::floor(linearSteps / c + 0.5));
}

namespace {

[[noreturn]] void outOfRange(const std::string& field, const std::string& range, double value) {
    throw Error(ErrorKind::InvalidInput, field + ": must be " + range + ", got " + formatNumber(value));
}

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

void validate(const ReliefSettings& s) {
    if (s.linearSteps < 1 || s.linearSteps > 1024) outOfRange("linear_steps", "in [1, 1024]", s.linearSteps);
    if (s.binarySteps < 0 || s.binarySteps > 32) outOfRange("binary_steps", "in [0, 32]", s.binarySteps);
    if (s.depthScale &&
        !(std::isfinite(*s.depthScale) && *s.depthScale > 0.0 && *s.depthScale <= kMaxReliefDepthScale)) {
        outOfRange("depth_scale", "in (0, 10]", *s.depthScale);
    }
    if (!(std::isfinite(s.tiling) && s.tiling > 0.0 && s.tiling <= 4096.0)) {
        outOfRange("tiling", "in (0, 4096]", s.tiling);
    }
}

void validate(const Lighting& l) {
    if (!finite(l.lightPosition)) throw Error(ErrorKind::InvalidInput, "light: position must be finite");
    if (!finite(l.lightColor) || l.lightColor.x < 0.0 || l.lightColor.y < 0.0 || l.lightColor.z < 0.0) {
        throw Error(ErrorKind::InvalidInput, "light_color: components must be finite and >= 0");
    }
    if (!(std::isfinite(l.ambient) && l.ambient >= 0.0)) outOfRange("ambient", ">= 0", l.ambient);
    if (!(std::isfinite(l.specular) && l.specular >= 0.0)) outOfRange("specular", ">= 0", l.specular);
    if (!(std::isfinite(l.shininess) && l.shininess >= 1.0)) outOfRange("shininess", ">= 1", l.shininess);
}

void validate(const PictureSettings& p) {
    if (p.width < 1 || p.width > 8192) outOfRange("width", "in [1, 8192]", p.width);
    if (p.height < 1 || p.height > 8192) outOfRange("height", "in [1, 8192]", p.height);
    if (p.samples < 1 || p.samples > 16) outOfRange("samples", "in [1, 16]", p.samples);
    if (!finite(p.background)) throw Error(ErrorKind::InvalidInput, "background: must be finite");
}

void validate(const GdmSettings& gdm, const PictureSettings& picture) {
    if (gdm.rank < 0 && gdm.rank != kGdmRankRaw) outOfRange("gdm_rank", ">= 1 or \"raw\"", gdm.rank);
    if (gdm.shellThickness && !(std::isfinite(*gdm.shellThickness) && *gdm.shellThickness > 0.0))
        outOfRange("shell_thickness", "> 0 (world units)", *gdm.shellThickness);
    const bool isGdm = !gdm.source.empty();
    const auto& outputs = isGdm ? kGdmOutputs : kReliefOutputs;
    if (std::find(std::begin(outputs), std::end(outputs), picture.output) == std::end(outputs))
        throw Error(ErrorKind::InvalidInput,
                    std::string("output: ") + toString(picture.output) +
                        (isGdm ? " is a relief output; a GDM render draws shaded, uvw, shadow or mask"
                               : " is a GDM output (give a gdm); a relief render draws shaded, uv, shadow or "
                                 "depth"));
    if (!isGdm && (gdm.technique != GdmTechnique::Gdm || gdm.rank != 0 || gdm.shellThickness ||
                   gdm.lightFrame != GdmLightFrame::Tangent))
        throw Error(
            ErrorKind::InvalidInput,
            "gdm_technique, gdm_rank, shell_thickness and gdm_light_frame are for a GDM render: give a "
            "gdm");
}

void validate(const EnvironmentSettings& e, const GdmSettings& gdm) {
    if (!std::isfinite(e.rotation)) outOfRange("env_rotation", "finite (degrees)", e.rotation);
    if (!(std::isfinite(e.intensity) && e.intensity >= 0.0)) outOfRange("env_intensity", ">= 0", e.intensity);
    if (e.bounces < 0 || e.bounces > 8) outOfRange("env_bounces", "in [0, 8]", e.bounces);
    if (e.rank < 1 || e.rank > 48) outOfRange("env_rank", "in [1, 48]", e.rank);
    if (!(std::isfinite(e.specular) && e.specular >= 0.0)) outOfRange("env_specular", ">= 0", e.specular);
    if (!(e.shininess >= 0.0 && e.shininess <= 64.0)) outOfRange("env_shininess", "in [0, 64]", e.shininess);
    const EnvironmentSettings defaults;
    if (gdm.source.empty() &&
        (!e.source.empty() || e.rotation != defaults.rotation || e.intensity != defaults.intensity ||
         e.bounces != defaults.bounces || e.rank != defaults.rank || e.specular != defaults.specular ||
         e.shininess != defaults.shininess))
        throw Error(ErrorKind::InvalidInput,
                    "env, env_rotation, env_intensity, env_bounces, env_rank, env_specular and env_shininess "
                    "light a GDM render: give a gdm");
}

void applyEnvironmentFlags(const EnvironmentFlags& flags, EnvironmentSettings& settings, bool hasGdm) {
    if (flags.any() && !hasGdm)
        throw Error(ErrorKind::Usage,
                    "--env and its flags light a GDM render: give --gdm (or a scene's \"gdm\") with them");
    const auto usage = [](const std::string& message) { throw Error(ErrorKind::Usage, message); };
    if (!flags.source.empty()) settings.source = flags.source;
    if (flags.rotation) {
        if (!std::isfinite(*flags.rotation)) usage("--env-rotation must be a finite number of degrees");
        settings.rotation = *flags.rotation;
    }
    if (flags.intensity) {
        if (!(std::isfinite(*flags.intensity) && *flags.intensity >= 0.0))
            usage("--env-intensity must be >= 0, got " + formatNumber(*flags.intensity));
        settings.intensity = *flags.intensity;
    }
    if (flags.bounces) {
        if (*flags.bounces < 0 || *flags.bounces > 8)
            usage("--env-bounces must be in [0, 8], got " + std::to_string(*flags.bounces));
        settings.bounces = *flags.bounces;
    }
    if (flags.rank) {
        if (*flags.rank < 1 || *flags.rank > 48)
            usage("--env-rank must be in [1, 48], got " + std::to_string(*flags.rank));
        settings.rank = *flags.rank;
    }
    if (flags.specular) {
        if (!(std::isfinite(*flags.specular) && *flags.specular >= 0.0))
            usage("--env-specular must be >= 0, got " + formatNumber(*flags.specular));
        settings.specular = *flags.specular;
    }
    if (flags.shininess) {
        if (!(*flags.shininess >= 0.0 && *flags.shininess <= 64.0))
            usage("--env-shininess must be in [0, 64], got " + formatNumber(*flags.shininess));
        settings.shininess = *flags.shininess;
    }
}

}  // namespace strata
