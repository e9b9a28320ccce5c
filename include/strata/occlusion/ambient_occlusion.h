// Texture-space ambient occlusion of a relief (depth) map: Limberger, Schetinger, Oliveira 2015,
// "Meta-Relief Texture Mapping with Dynamic Texture-Space Ambient Occlusion", Section IV-A.
// docs/occlusion.md derives every formula below and measures each method's accuracy and speed.
//
// Conventions (CONVENTIONS §1, §2, §4). The relief is the bilinear, wrap-around surface through the
// texel centres at z = -S d(u, v), in tile units. AO is in [0, 1], 1 = fully open. Direction i is
// phi_i = 2 pi i / M in the (u, v) plane, from +u towards +v (v is up: +v moves to smaller row indices).
// The horizon h_i of a texel is the largest elevation atan((z - z0) / t) of the relief over horizontal
// distances t in (0, R] tile widths, clamped at 0; the search wraps toroidally (t may span tiles).
//
// Methods (AoMethod):
//   Sweep  (default) the cosine-weighted AO (1/M) sum_i cos^2 h_i, from a convex-hull line sweep
//          (Timonen & Westerholm 2010): exact up to 4 texel steps, then from the nearest line's hull, at
//          most half a texel beside the texel's own line. RMSE <= 0.003 against Brute on every built-in
//          pattern (tested). SSE2/NEON, AVX2 or AVX-512 kernels, chosen at run time, give the same
//          numbers bit for bit.
//   Brute  the same quantity from each texel's exact walk along its own line (every grid crossing and
//          every concave arc's peak: the bilinear surface's horizon up to float rounding). The reference.
//   Paper  the paper as written: the area of the projected polygon of the horizon points,
//          1/2 sin(2 pi / M) sum_i cos h_i cos h_(i+1), over pi (AoNormalize::Paper) or over the open
//          M-gon's area (AoNormalize::Open); on Brute's horizons, then the paper's filter. Open and
//          unfiltered, it is Brute minus (1/(2M)) sum_i (cos h_i - cos h_(i+1))^2: never brighter.
//
// Filter (AoFilter; Section IV-A): a (2k + 1)^2 normalised Gaussian, wrap-around, whose result replaces
// the AO only at texels with some horizon above the plane (tan h > 0); open texels keep their value.
//
// Depth rescale (Section IV-A, Eq. 4-6): rescaleAoPaper, the paper's disc model (an approximation,
// shared with GLSL in shaders/shared/ao_rescale.h); rescaleAoExact / HorizonMap::aoAt, exact for any
// factor s because tan h is linear in the depth scale.
//
// Combination of layers (Section IV-A, last paragraph but one): combineAo, the product (the paper's
// choice) or the minimum of the layers' AO maps.
#pragma once

#include "strata/image/image.h"
#include "strata/relief/relief_texture.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace strata {

enum class AoMethod {
    Sweep,  // cosine-weighted AO from the sweep's horizons (the default)
    Brute,  // cosine-weighted AO from each texel's exact walk (CONVENTIONS §4): the reference
    Paper,  // the paper's projected polygon area (Section IV-A), same horizon search
};

enum class AoFilter {
    Auto,   // Paper for AoMethod::Paper, None otherwise
    Paper,  // Gaussian low-pass, applied only at texels with some occlusion (Section IV-A)
    None,
};

enum class AoNormalize {
    Open,   // divide the polygon's area by the open M-gon's area: open = 1 exactly (default)
    Paper,  // divide by pi as in the paper: open = (M/2) sin(2 pi / M) / pi (0.99737 at M = 50)
};

enum class AoCombine {
    Multiply,  // product of the layers' AO (the paper's choice)
    Min,       // smallest of the layers' AO
};

struct AoParams {
    AoMethod method = AoMethod::Sweep;
    // M, the number of directions, taken at phi_i = 2 pi i / M; [3, 1024]. 50 = 7.2 degrees (the paper).
    int directions = 50;
    // R, how far the horizon search looks, in tile widths; (0, 16]. Default 1 (CONVENTIONS §4).
    double radius = 1.0;
    // S, the depth of d = 1 in tile widths (CONVENTIONS §2); (0, 100]. Default kDefaultDepthScale.
    double depthScale = kDefaultDepthScale;
    // Brute and Paper: 0 (the default) walks cell by cell, exactly; a step in [1/64, 16] texels of the
    // larger image side samples at that step instead, as horizon mapping does (1 = texel by texel).
    double marchStep = 0.0;
    AoFilter filter = AoFilter::Auto;
    AoNormalize normalize = AoNormalize::Open;  // used by AoMethod::Paper only
    // The low-pass kernel: half-width k in texels ((2k + 1)^2 taps), [0, 8], default 1 (3 x 3); and its
    // standard deviation in texels, (0, 16], default 1.
    int filterRadius = 1;
    double filterSigma = 1.0;
};

// The per-direction horizons of every texel, kept so that AO at any depth scale factor is exact.
// tanHorizon[(y * width + x) * directions + i] = tan(h_i) >= 0 of texel (x, y) (row 0 = top) at the
// depth scale `depthScale` it was computed for; direction i is phi_i = 2 pi i / directions.
struct HorizonMap {
    int width = 0;
    int height = 0;
    int directions = 0;
    double depthScale = 0.0;  // S the horizons were computed at (tile widths)
    double radius = 0.0;      // R of the search (tile widths)
    std::vector<float> tanHorizon;

    std::span<const float> texel(int x, int y) const {
        return std::span<const float>(tanHorizon)
            .subspan((static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                      static_cast<std::size_t>(x)) *
                         static_cast<std::size_t>(directions),
                     static_cast<std::size_t>(directions));
    }
    // The cosine-weighted AO of texel (x, y) after scaling the depth by s (s = 1: as computed):
    // (1/M) sum_i 1 / (1 + s^2 tan^2 h_i). Exact for any s >= 0.
    float aoAt(int x, int y, double s = 1.0) const;
    // aoAt for every texel, as a 1-channel image. Multithreaded.
    Image ao(double s = 1.0) const;
};

// The horizons of every texel by params.method's search: the sweep for Sweep, the exact walk (or the
// march, marchStep > 0) for Brute and Paper.
// Multithreaded (oneTBB).
// Throws Error(InvalidInput) naming the parameter and the value for: an empty depth map or one with
// more than one channel, and any AoParams field outside its documented range (method, filter and
// normalisation are not used here).
HorizonMap computeHorizons(const Image& depth, const AoParams& params);

// The exact horizons tan h_i of one texel (x, y) (the walk Brute uses), for checking any map at a few
// texels. Throws like computeHorizons, and Error(InvalidInput) for a texel outside the map.
std::vector<float> texelHorizons(const Image& depth, const AoParams& params, int x, int y);

// The paper's AO (projected polygon area, Section IV-A) from horizons, after scaling the depth by s
// (the polygon of the scaled horizons: exact for the polygon too). Unfiltered.
Image polygonAo(const HorizonMap& horizons, AoNormalize normalize, double s = 1.0);
// The open texel's value of polygonAo: 1 for Open, (M/2) sin(2 pi / M) / pi for Paper.
double polygonOpenValue(int directions, AoNormalize normalize);

// The low-pass filter of Section IV-A applied to `ao`, at the texels whose horizons show some
// occlusion; radius and sigma in texels as AoParams::filterRadius / filterSigma. ao and horizons must
// have the same size (checked).
Image filterOccluded(const Image& ao, const HorizonMap& horizons, int radius, double sigma);

// The AO map of a depth map: computeHorizons, then the method's AO, then the filter. 1 channel.
// Throws like computeHorizons.
Image bakeAo(const Image& depth, const AoParams& params);

// Eq. 4-6 (shaders/shared/ao_rescale.h): the paper's approximate AO after scaling the depth by s >= 0.
float rescaleAoPaper(float ao, float s);
Image rescaleAoPaper(const Image& ao, double s);
// The exact cosine-weighted AO after scaling the depth by s >= 0: horizons.ao(s).
Image rescaleAoExact(const HorizonMap& horizons, double s);

// 8-bit horizons: the angle h in [0, pi/2] stored as round(h / (pi/2) * 255). The AO error this causes
// at s = 1 is at most pi/1020 = 0.0031 per texel (half a step of angle; docs/occlusion.md).
std::uint8_t encodeHorizon8(float tanHorizon);
float decodeHorizon8(std::uint8_t code);
// A copy whose tangents are those an 8-bit store gives back (encode, then decode).
HorizonMap quantizeHorizons8(const HorizonMap& horizons);

// One layer of a meta-relief AO combination: a 1-channel AO map sampled at tiling * uv.
struct AoLayer {
    Image ao;
    double tiling = 1.0;  // > 0, any real
    std::string label;    // names the layer in messages
};

// resolution x resolution map; texel (x, y) combines layer.ao.sample(tiling * u, tiling * v) over the
// layers, (u, v) the texel centre. Throws Error(InvalidInput) naming the layer and the value for: no
// layers, an empty AO map or one with more than one channel, a tiling that is not > 0 and finite, a
// resolution outside [1, Image::kMaxDimension].
Image combineAo(std::span<const AoLayer> layers, AoCombine mode, int resolution);

const char* toString(AoMethod method);
const char* toString(AoFilter filter);
const char* toString(AoNormalize normalize);
const char* toString(AoCombine mode);
// "sweep" | "brute" | "paper"; "auto" | "paper" | "none"; "open" | "paper"; "multiply" | "min". Anything
// else throws Error(InvalidInput) listing the accepted names.
AoMethod parseAoMethod(const std::string& text);
AoFilter parseAoFilter(const std::string& text);
AoNormalize parseAoNormalize(const std::string& text);
AoCombine parseAoCombine(const std::string& text);

}  // namespace strata
