// Texture-space ambient occlusion of a relief (depth) map: Limberger, Schetinger, Oliveira 2015,
// "Meta-Relief Texture Mapping with Dynamic Texture-Space Ambient Occlusion", Section IV.
//
// Geometry (CONVENTIONS §1, §2, §4). The relief is the bilinear, wrap-around surface through the texel
// centres, at height z = -S d(u, v) in tile units. For texel (u0, v0) with depth d0 (z0 = -S d0) and
// direction phi_i = 2 pi i / M, measured in the (u, v) plane from +u towards +v (v is up, so +v moves to
// smaller row indices), a sample at distance t (tile widths) has elevation atan((z - z0) / t). The
// horizon h_i is the largest elevation over t in (0, R], clamped at 0 (the reference plane; the
// hemisphere is the one around +z). The search wraps toroidally: t may run over several tiles.
//
// Horizon searches. The exact one (AoParams::marchStep = 0, the default for Brute and Paper) walks each
// texel's own line cell by cell: the relief along a straight line is linear on every grid line it
// crosses and a quadratic arc inside each cell, so it takes every crossing, the arc's interior maximum
// where the arc is concave, the limit t -> 0+ (the slope of the cell the direction enters) and the
// point at R. That is the horizon of the bilinear relief exactly, up to float rounding. It stops early
// once nothing can rise higher (S (d0 - min d) / t <= the current tan h), which changes nothing.
// marchStep > 0 samples instead at t_k = k R / N, N = ceil(R / step) (step in texels of the larger side)
// with Image::sampleTexel, plus the t -> 0+ slope: it misses peaks between samples, by O(step).
//
// The sweep (AoMethod::Sweep) finds the same horizons for all texels at once: per direction, parallel
// lines one texel apart cross the map against the direction, and each keeps the upper convex hull of
// its profile on a stack (Timonen & Westerholm 2010; Stewart 1998), so a texel's far horizon is one
// tangent query from its own point and the cost is linear in texels x directions. Each texel reads
// the hull of the line nearest to it (at most half a texel beside its own line) for distances beyond
// 4 texel steps, and walks its own line exactly up to there. The lateral half texel is its one
// approximation; it matters only beyond those 4 steps, and docs/occlusion.md measures it against the
// exact walk: RMSE <= 0.0023 AO on every built-in pattern at 256^2. The window is exact: a texel sees
// the line's samples between R and 4 steps away and the point at exactly R, nothing farther (one hull
// per side holds the line from R before its start; where the texel's tangent to it lies beyond R and
// would raise its horizon, the texel reads its window itself; short windows are always read). 4, 8 or
// 16 lines run in lockstep in SIMD lanes (SSE2 or NEON, AVX2, AVX-512: the same numbers bit for bit).
//
// Methods (AoMethod):
//   Brute  the convention's AO (CONVENTIONS §4): the cosine-weighted fraction of the hemisphere that is
//          not blocked, = projected solid angle / pi. Per direction the visible projected solid angle of
//          a wedge of width 2 pi / M above elevation h is (2 pi / M) cos^2(h) / 2, so
//              AO = (1/M) sum_i cos^2(h_i) = (1/M) sum_i 1 / (1 + tan^2 h_i).
//          Errors: the M-direction discretisation of the azimuth integral only (exact search).
//   Sweep  the same quantity from the sweep's horizons (the default: ~180x faster than Brute at 256^2).
//   Paper  Section IV-A as written: the generalised cone's edges meet the unit hemisphere at
//          p_i = cos(h_i) (cos phi_i, sin phi_i) (orthographic projection onto the plane); the AO is the
//          area of that polygon, 1/2 sin(2 pi / M) sum_i cos h_i cos h_(i+1), divided by pi (paper) or by
//          the open polygon's area (M/2) sin(2 pi / M) (open). This is NOT the discrete
//          cosine-weighted sum above. Both discretise the same integral (the projected solid angle is
//          the area of the visible region's orthographic projection, 1/2 integral cos^2 h(phi) dphi),
//          but the polygon joins neighbouring directions by chords: with open normalisation it is
//          (1/M) sum_i cos h_i cos h_(i+1) = brute - (1/(2M)) sum_i (cos h_i - cos h_(i+1))^2 <= brute,
//          darker wherever the horizon changes fast with direction. docs/occlusion.md measures it.
//
// Normalisation (AoNormalize): the paper divides by pi, so a fully open texel gets the regular M-gon's
// area / pi = (M/2) sin(2 pi / M) / pi = 0.99737 at M = 50, never 1. `Open` divides by the open M-gon's
// area instead, so open is exactly 1 (CONVENTIONS §4: 1 = fully open) and flat relief is not darkened
// by 0.3 %; it is the default. `Paper` is offered for reproducing the paper.
//
// Filter (AoFilter; Section IV-A: "applied only at texels with some degree of occlusion"): a normalised
// (2 k + 1)^2 Gaussian, weights exp(-(dx^2 + dy^2) / (2 sigma^2)) for |dx|, |dy| <= k (k =
// filterRadius, sigma = filterSigma, in texels), wrap-around, applied to the unfiltered AO map; its
// result replaces the AO only at texels where some direction has a horizon above the plane (tan h > 0).
// Open texels keep their exact open value, so the filter never darkens open ground.
// `Auto` (the default) means `Paper` for AoMethod::Paper and `None` for the exact method(s).
//
// Dynamic depth rescale (Section IV-A, Eq. 4-6): rescaleAoPaper(), the shared GLSL/C++ function in
// shaders/shared/ao_rescale.h. It is an approximation (a disc model of the visible region). The exact
// rescale needs the per-direction horizons: tan h scales linearly with depth, so
//     AO(s) = (1/M) sum_i 1 / (1 + s^2 tan^2 h_i)
// is exact for any factor s (HorizonMap::aoAt, rescaleAoExact).
//
// Combination of layers (Section IV-A): the product of the layers' AO (the paper's choice) or their
// minimum, each layer sampled at tiling * uv like compose() (bilinear, wrap-around).
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
    Sweep,  // cosine-weighted AO from the sweep's horizons (the default; see the top of this file)
    Brute,  // cosine-weighted AO from each texel's exact walk (CONVENTIONS §4); slow and obviously right
    Paper,  // the paper's projected polygon area (Section IV-A), same horizon search
};

enum class AoFilter {
    Auto,   // Paper for AoMethod::Paper, None otherwise
    Paper,  // Gaussian low-pass, applied only at texels with some occlusion (see the top of this file)
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

// The horizon search of params.method described at the top of this file, for every texel.
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

// The low-pass filter of Section IV-A (see the top of this file) applied to `ao`, at the texels whose
// horizons show some occlusion. ao and horizons must have the same size (checked).
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
// at s = 1 is at most (pi/2) / 255 / 2 = pi/1020 = 0.0031 per direction (|d cos^2 h / dh| <= 1), hence
// per texel; docs/occlusion.md measures it.
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
// "brute" | "paper"; "auto" | "paper" | "none"; "open" | "paper"; "multiply" | "min". Anything else
// throws Error(InvalidInput) listing the accepted names.
AoMethod parseAoMethod(const std::string& text);
AoFilter parseAoFilter(const std::string& text);
AoNormalize parseAoNormalize(const std::string& text);
AoCombine parseAoCombine(const std::string& text);

}  // namespace strata
