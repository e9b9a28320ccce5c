// What a relief render does, independent of OpenGL: technique, search steps, depth scale, tiling, shadows,
// depth correction, AO, lighting and the picture. One parameter struct shared by the CLI, the scene JSON,
// the viewer and the GL renderer (STYLE.md: a parameter is defined in one place). docs/scenes.md documents
// every field with its scene-file key and flag.
//
// Techniques (Policarpo, Oliveira, Comba 2005, "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces"):
//   texture   colour only, lit with the mesh's own normal;
//   normal    normal mapping: colour and normal at the fragment's own uv;
//   parallax  parallax mapping with the Kaneko offset uv += (d_top - d) ... (form: docs/renderer.md);
//   relief    the paper's linear + binary search along the tangent-space view ray (its Sec. 3 and the
//             appendix's ray_intersect_rm), with self-shadowing by the same search along the light ray;
//   maxmip    exact: maximum-mipmap traversal (Tevs, Ihrke, Seidel 2008) down to the cell, where the ray
//             meets the bilinear patch of CONVENTIONS §1 in closed form; no step count (docs/renderer.md);
//   cone      exact: cone step mapping (Dummer 2006; Policarpo & Oliveira 2007) with cones valid for whole
//             bilinear cells and steps of at least one cell, each cell solved in closed form (Bán et al.
//             2024's robustness fixes; strata/relief/cone_map.h); no step count;
//   dual-depth the paper's Sec. 4: a dual-depth texture (strata/relief/dual_depth.h) as an impostor, the
//             relief search with the inside test front <= d <= back.
#pragma once

#include <glm/vec3.hpp>

#include <optional>
#include <string>

namespace strata {

enum class Technique { Texture, Normal, Parallax, Relief, MaxMip, Cone, DualDepth };

// Every technique, in the order above.
inline constexpr Technique kAllTechniques[] = {Technique::Texture,  Technique::Normal, Technique::Parallax,
                                               Technique::Relief,   Technique::MaxMip, Technique::Cone,
                                               Technique::DualDepth};

// What a pixel of the picture holds (CONVENTIONS §7 for uv, shadow and depth; §8 for a GDM render's uvw,
// shadow and mask). uv and depth are relief outputs, uvw and mask GDM outputs (GdmSettings); shaded and
// shadow are both's.
enum class RenderOutput {
    Shaded,  // RGB, sRGB-encoded colour in [0, 1]
    Uv,      // RGB = (u, v, hit) of the first hit, u, v in [0, 1) (modulo 1); (0, 0, 0) where nothing is hit
    Shadow,  // gray, 1 where the first hit is lit by the light, 0 where it is shadowed or nothing is hit
    Depth,   // gray, d of the first hit, 0 where nothing is hit
    Uvw,     // GDM: RGBA = (u, v, w, 1) of the first hit, u, v modulo 1; (0, 0, 0, 0) where nothing is hit
    Mask,    // GDM: gray, 1 on a hit, 0 elsewhere
};

// The outputs of each renderer, in the order above.
inline constexpr RenderOutput kReliefOutputs[] = {RenderOutput::Shaded, RenderOutput::Uv,
                                                  RenderOutput::Shadow, RenderOutput::Depth};
inline constexpr RenderOutput kGdmOutputs[] = {RenderOutput::Shaded, RenderOutput::Uvw, RenderOutput::Shadow,
                                               RenderOutput::Mask};

// How the AO map follows a render depth scale that differs from the one it was baked at.
enum class AoRescale {
    Off,    // use the map as baked
    Paper,  // Limberger et al. 2015 Eq. 4-6, per fragment (shaders/shared/ao_rescale.h)
    Exact,  // re-bake the AO of the depth map at the render's depth scale (the sweep baker), exact
};

struct ReliefSettings {
    Technique technique = Technique::Relief;
    // Linear search steps at normal incidence; the count grows with the view angle as
    // n = round(N / max(|cos theta|, 1/4)) (theta from the normal), which keeps the step length along the
    // ray constant, up to 4 N beyond 75.5 degrees. [1, 1024], the paper's shader uses 10.
    int linearSteps = 10;
    // Binary refinement steps after the linear search. [0, 32], the paper's shader uses 5.
    int binarySteps = 5;
    // Depth of d = 1 in tile widths (CONVENTIONS §2). nullopt: the material's own S.
    std::optional<double> depthScale;
    // Tiles per unit of mesh uv (tile coordinates = tiling * uv). > 0, default 1.
    double tiling = 1.0;
    bool selfShadow = true;       // the paper's light-ray test, every technique (docs/renderer.md)
    bool depthCorrection = true;  // write gl_FragDepth of the relief hit (relief and parallax)
    bool ao = true;               // texture-space AO multiplies the ambient term (if the material has AO)
    AoRescale aoRescale = AoRescale::Exact;
};

// How a GDM render finds a prism's hit along its segment T_in -> T_out (docs/gdm.md; strata::gl's
// GdmRenderer draws them):
enum class GdmTechnique {
    Gdm,     // the paper's (Wang et al. 2004, Sec. 3.2): one GDM lookup d(T_in, V), a hit if d < dt. Default.
    Refine,  // the lookup, then exact steps against the asset's volumes near it (beyond the paper)
    March,   // no GDM: the occupancy volume stepped every voxel (the paper's slice-based baseline)
};

// How a GDM render's shadow lookup takes the direction to the light into texture space:
enum class GdmLightFrame {
    Tangent,   // the direction in the surface's local frame (T, B, N), unscaled: the paper's approximation
               // (Sec. 3.2: "the object space light direction", as horizon maps and VDM take it). Default.
    Jacobian,  // mapped by the inverse of each prism's own Jacobian from texture to world (not the paper's)
};

// A GDM render instead of a relief one (Wang et al. 2004, "Generalized Displacement Maps"): the
// mesostructure drawn in the prism shell of the scene's mesh (CONVENTIONS §8). The tiling is
// ReliefSettings::tiling; the lighting and the picture are the scene's.
struct GdmSettings {
    // Empty: no GDM, the scene is a relief render. Else a GDM asset directory (`strata gdm bake`) or a
    // built-in mesostructure name (mesostructureList()), baked on the fly at `strata gdm bake`'s defaults.
    std::string source;
    GdmTechnique technique = GdmTechnique::Gdm;
    // The GDM the lookups read: 0 = the asset's SVD at its stored rank; K >= 1 = its first K terms (K at most
    // the stored rank); kGdmRankRaw = the raw GDM (an asset baked with --keep-raw; a built-in has it).
    int rank = 0;
    // T, the shell's thickness in world units (> 0). nullopt: H times the world length of one tile (§8).
    std::optional<double> shellThickness;
    GdmLightFrame lightFrame = GdmLightFrame::Tangent;
};
inline constexpr int kGdmRankRaw = -1;

// Environment lighting of a GDM render (issue 19; docs/gdm.md "Global illumination"): the paper's bi-scale
// radiance transfer (Wang et al. 2004, Sec. 3.2), a distant environment carried to each vertex by the mesh's
// macro transfer and to the eye by the GDM's radiance transfer volume (RTV). It replaces the ambient term;
// the point light still adds its own.
struct EnvironmentSettings {
    // Empty: none. Else a built-in sky (environmentList(): sky-clear, sky-overcast, sky-sunset, studio) or an
    // equirectangular EXR (CONVENTIONS §9: world space, +z up, row 0 the zenith, column 0 azimuth 0 (+x),
    // azimuth growing towards +y).
    std::string source;
    double rotation = 0.0;   // degrees the environment turns about world +z (towards +y), finite
    double intensity = 1.0;  // its radiance's scale, finite and >= 0
    int bounces = 1;         // the RTV's interreflections, [0, 8]
    int rank = 4;            // the RTV's SVD terms, [1, 48] (the paper keeps 4; 48 loses nothing)
    // The glossy term (gdm_rtv_glossy.h): its specular coefficient, >= 0 (0: none, nothing baked), and the
    // Phong lobe's shininess, [0, 64] (band 3 holds a broad lobe: 8 or less).
    double specular = 0.0;
    double shininess = 8.0;
};

// The environment's command-line flags, as `strata render` and `strata-view` take them (--env,
// --env-rotation, --env-intensity, --env-bounces, --env-rank, --env-specular, --env-shininess); unset: the
// scene's value.
struct EnvironmentFlags {
    std::string source;
    std::optional<double> rotation, intensity, specular, shininess;
    std::optional<int> bounces, rank;
    bool any() const {
        return !source.empty() || rotation || intensity || specular || shininess || bounces || rank;
    }
};
// Applies the flags that are set to `settings`, each range checked with the flag named in the message
// (Error(Usage)); Error(Usage) as well when any is set and `hasGdm` is false (they light a GDM render).
void applyEnvironmentFlags(const EnvironmentFlags& flags, EnvironmentSettings& settings, bool hasGdm);

// Blinn-Phong with one point light (paper appendix: ambient, diffuse, specular, shininess).
struct Lighting {
    glm::dvec3 lightPosition{2.0, -2.0, 3.0};  // world units
    glm::dvec3 lightColor{1.0, 1.0, 1.0};      // linear RGB, multiplies diffuse and specular
    double ambient = 0.25;                     // ambient intensity, times the albedo (and the AO)
    double specular = 0.35;                    // specular intensity
    double shininess = 48.0;                   // Blinn-Phong exponent, >= 1
};

struct PictureSettings {
    int width = 1280;  // pixels, [1, 8192]
    int height = 720;  // pixels, [1, 8192]
    // Antialiasing samples per pixel for `shaded`, taken as a k x k supersampling grid, k =
    // round(sqrt(samples)) (4 = 2 x 2, 9 = 3 x 3, 16 = 4 x 4), box-filtered in linear colour; 1 = none. [1,
    // 16], default 4. Debug outputs always use 1 (CONVENTIONS §7: no antialiasing).
    int samples = 4;
    RenderOutput output = RenderOutput::Shaded;
    glm::dvec3 background{0.16, 0.17, 0.19};  // sRGB-encoded colour of empty pixels (shaded only)
};

const char* toString(Technique technique);
const char* toString(RenderOutput output);
const char* toString(AoRescale rescale);
const char* toString(GdmTechnique technique);
const char* toString(GdmLightFrame frame);
// Parse the names above; throw Error(InvalidInput) listing the valid names (callers add the key or flag).
Technique parseTechnique(const std::string& text);
RenderOutput parseRenderOutput(const std::string& text);
AoRescale parseAoRescale(const std::string& text);
GdmTechnique parseGdmTechnique(const std::string& text);
GdmLightFrame parseGdmLightFrame(const std::string& text);
// "raw" -> kGdmRankRaw, "K" -> K (an integer >= 1); throws Error(InvalidInput) otherwise.
int parseGdmRank(const std::string& text);

// The linear step count for a view ray at |cos theta| = cosTheta (see ReliefSettings::linearSteps).
// The shaders compute the same (shaders/shared/relief_search.h is the GLSL).
int adaptiveLinearSteps(int linearSteps, double cosTheta);

// Throw Error(InvalidInput) naming the offending field for values outside the documented ranges.
void validate(const ReliefSettings& settings);
void validate(const Lighting& lighting);
void validate(const PictureSettings& picture);
// Also checks that picture.output is one of the renderer's (kReliefOutputs without a GDM, kGdmOutputs with
// one).
void validate(const GdmSettings& gdm, const PictureSettings& picture);
// The environment's keys (env, env_rotation, env_intensity, env_bounces, env_rank): ranges, and that they go
// with a GDM render (`gdm`).
void validate(const EnvironmentSettings& environment, const GdmSettings& gdm);

}  // namespace strata
