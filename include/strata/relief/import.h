// Making relief textures from files a user already has: a colour photo (reliefFromPhoto), or a
// normal map whose green-channel convention must be checked against its height map
// (detectNormalConvention). docs/import-from-photo.md shows both with pictures.
#pragma once

#include "strata/relief/relief_texture.h"

#include <string>

namespace strata {

// ---------------------------------------------------------------------------------------------
// From a colour photo, the way CrazyBump-like tools do it. The meta-relief paper (Section V) made
// the depth and normal maps of most of its Fig. 10 textures from their colour maps with CrazyBump;
// this is Strata's equivalent, built on the assumption those tools make: in a photo of a surface,
// what is bright is (mostly) what sticks out, and detail of different sizes should be weighted
// separately.
//
// The band model. L is the photo's luminance (Rec. 709 of the sRGB-encoded values, as luminance()
// computes it), G_s a wrap-around Gaussian blur of standard deviation s (in tile widths), and
//     B(a, b) = G_a L - G_b L     (a < b)
// the band of L between the scales a and b (a difference of Gaussians). Then
//     h = weightSmall  * B(sigmaSmall,  sigmaMedium)
//       + weightMedium * B(sigmaMedium, sigmaLarge)
//       + weightLarge  * B(sigmaLarge,  sigmaHuge)
// The three bands together are L with its finest texel noise (below sigmaSmall) and its lowest
// frequencies (G_sigmaHuge L: uneven lighting across the photo, vignetting) removed. h is then
// mapped linearly to [0, 1] (its minimum to 0, its maximum to 1; a featureless photo gives a flat
// h = 1) and the depth is d = 1 - h (CONVENTIONS §2), or d = h with `invert`.
//
// Because the filters wrap around, a tileable photo gives a tileable relief. Because the sigmas are
// fractions of the tile, the same photo at 512^2 and 1024^2 gives the same relief up to resampling
// (only the finest band, which is texel-scale by nature, differs). For speed, a blur wider than
// kExactBlurSigmaTexels texels is computed with four wrap-around extended box filters (running
// sums, Gwosdek et al. 2011, "Theoretical foundations of Gaussian convolution by extended box
// filtering") whose variance equals the Gaussian's exactly; docs/import-from-photo.md gives its
// measured accuracy. Narrower blurs of a square photo use gaussianBlur() directly (it takes one sigma
// for both axes, so a non-square photo uses the box filters throughout).
struct PhotoImportParams {
    // Weights of the three bands. Each >= 0 and finite; at least one > 0. Only their ratios matter
    // for the depth map (h is normalised afterwards).
    double weightLarge = 1.0;   // shapes between sigmaLarge and sigmaHuge (stones, bricks, cushions)
    double weightMedium = 0.5;  // detail between sigmaMedium and sigmaLarge (cracks, weave, grain)
    double weightSmall = 0.25;  // the finest detail, between sigmaSmall and sigmaMedium

    // Band edges, as standard deviations in tile widths (a value of 0.01 is 5.12 texels at 512^2).
    // They must satisfy 0 <= sigmaSmall < sigmaMedium < sigmaLarge < sigmaHuge <= 1.
    double sigmaSmall = 0.0;     // 0 = keep detail down to the texel
    double sigmaMedium = 0.003;  // 1.5 texels at 512^2
    double sigmaLarge = 0.015;   // 7.7 texels at 512^2
    double sigmaHuge = 0.08;     // 41 texels at 512^2: anything broader is lighting, and dropped

    // false: bright is high (the usual case: lit tops, dark crevices). true: dark is high (e.g. dark
    // stones raised from pale mortar).
    bool invert = false;

    // S, the depth of d = 1 in tile widths (CONVENTIONS §2), for the normal map. > 0 and finite.
    double depthScale = kDefaultDepthScale;
};

// Blurs of at most this many texels (standard deviation) use the exact truncated Gaussian of
// gaussianBlur(); wider ones the extended-box approximation described above.
inline constexpr double kExactBlurSigmaTexels = 4.0;

// Returns depth (1 channel, the photo's size), normals at params.depthScale (normalsFromDepth),
// the photo's RGB as colour (its first three channels; a gray or gray+alpha photo gives its gray
// channel three times) and depthScale = params.depthScale. No AO.
// Throws Error(InvalidInput, "<field>: <what is wrong>") for a parameter outside the ranges above
// (a negative or non-finite weight, all weights zero, sigmas out of order, depthScale <= 0), and
// Error(InvalidInput, "photo: ...") for an empty image.
ReliefTexture reliefFromPhoto(const Image& photo, const PhotoImportParams& params = {});

// ---------------------------------------------------------------------------------------------
// Which convention a normal map follows (CONVENTIONS §3: Strata's is OpenGL, green towards v = 1),
// found by comparing it with the normals derived from its own depth map. The Pearson correlation of
// the file's nx with the derived nx must be clearly positive (otherwise the two files do not
// describe the same relief, or x is flipped, and nothing can be concluded); the y correlation is
// then clearly positive for OpenGL (green up) and clearly negative for DirectX (green down).
// "Clearly" is kConventionCorrelationThreshold, raised for tiny maps (see below).
enum class NormalConvention { OpenGL, DirectX, Unknown };

// A genuine pair (a normal map baked from the same height field, even with another filter, blur,
// depth scale or resolution) correlates at r > 0.8 in practice, and unrelated maps of N texels at
// |r| ~ 1/sqrt(N) (under 0.01 at 256^2), so 0.3 separates them with a wide margin on both sides.
// For maps so small that chance correlations reach that level, the threshold is raised to
// 4/sqrt(N) (four standard errors of a correlation between unrelated maps).
inline constexpr double kConventionCorrelationThreshold = 0.3;

struct NormalConventionReport {
    NormalConvention convention = NormalConvention::Unknown;
    double correlationX = 0.0;  // Pearson r of the file's nx with the derived nx; 0 if undefined
    double correlationY = 0.0;  // of ny: > threshold OpenGL, < -threshold DirectX; 0 if undefined
    double threshold = kConventionCorrelationThreshold;  // the threshold applied to these maps
    std::string summary;  // one line for a human, e.g. "OpenGL (green up): y agrees ... (r = 0.98)"
};

// `normals`: the decoded normal map (3 or more channels, n in [-1, 1], first three used) exactly as
// stored, without any flip. `depth`: its depth map (1 channel, d = 1 - h for a height map; a height
// map given as is only swaps both signs, so the x check then reports Unknown). When the sizes
// differ, the depth map is resampled to the normal map's size. The depth scale does not matter:
// it changes the derived normals' magnitudes, never their signs.
// Throws Error(InvalidInput) for an empty image or a wrong channel count.
NormalConventionReport detectNormalConvention(const Image& normals, const Image& depth);

// "OpenGL", "DirectX", "unknown".
const char* toString(NormalConvention convention);

// ---------------------------------------------------------------------------------------------
// Normal-convention safety, shared by every reader of a normal map that has a depth map beside it
// (import, material layers, texture sets), so that all of them decide the same way.
enum class NormalY { Up, Down, Auto };  // "normal_y" / --normal-y: up (OpenGL), down (DirectX), auto

// An explicit choice is refused when the gradient contradicts it by this much: the file's x must
// follow the depth map (r_x > the detection threshold) and its y must point the other way with
// |r_y| > kConventionContradiction. Measured (tests/relief/test_normal_safety.cpp, six patterns at
// 128^2, flipped): |r_y| = 1.00 clean and 0.78 to 0.97 with Gaussian noise of 0.2 on x and y;
// unrelated maps give |r_y| < 0.01 at 256^2. 0.6 sits between, so only a map that is clearly the
// other convention is refused; a weaker disagreement keeps the explicit choice.
inline constexpr double kConventionContradiction = 0.6;

struct NormalYResolution {
    bool flipY = false;  // convert DirectX -> OpenGL
    std::string note;    // for auto: what was found (or the fallback); for a forced choice: the warning
};

// `normals`: decoded as stored (no flip); `depth`: its depth map. `label` names the file (or the
// material key) in messages; `howToFix` ends the error (e.g. "use --normal-y down or auto, or add
// --force to keep up"). Auto: the detected convention, or up (OpenGL) with a note when it
// cannot tell. Up/Down: kept, unless the gradient contradicts it by kConventionContradiction;
// then Error(InvalidInput) "<label>: read as up (OpenGL), but its gradient says DirectX (green down):
// ... (r = -0.98), more than 0.6 against; <howToFix>", or, with `force`, kept with that text in `note`.
NormalYResolution resolveNormalY(const Image& normals, const Image& depth, NormalY setting, bool force,
                                 const std::string& label, const std::string& howToFix);

// Obviously wrong inputs (section B of the input-safety issue). `encoded` is the file as read (values
// in [0, 1], before decoding); `label` names the file. Each throws Error(InvalidInput) naming the
// file and what was found.
// checkNormalMapContent: a normal map that is
//  - grey: at least 90 % of its texels have r = g = b (within 1/255): a height or grey map;
//  - signed or zero: more than 25 % of the decoded normals point into the surface (z < 0; a map
//    stored as signed values clamped to 0, or black, decodes to z = -1), or their mean length before
//    renormalisation is outside [0.5, 1.5] (a unit map gives 1 up to quantisation).
// checkDepthMapContent: an RGB(A) image read as height or depth that is a tangent-space normal map:
//  mean b >= 0.75, mean r and g within 0.15 of 0.5, z > 0 for 99 % of the texels and a mean decoded
//  length within [0.85, 1.15]. A colour photo or a coloured height map does not meet all of these.
void checkNormalMapContent(const Image& encoded, const std::string& label);
void checkDepthMapContent(const Image& encoded, const std::string& label);

}  // namespace strata
