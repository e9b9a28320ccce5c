// Making relief textures from files a user already has.
#pragma once

#include "strata/relief/relief_texture.h"

#include <filesystem>
#include <string>
#include <vector>

namespace strata {

// ---------------------------------------------------------------------------------------------
// From a colour photo, the way CrazyBump-like tools do it (the meta-relief paper, Section V).
//
// The luminance of the photo is split into frequency bands with wrap-around Gaussian filters, so the
// result stays tileable when the photo is. Bright reads as high. Each band is weighted and summed:
//     h = wLarge * B(sigmaLarge, sigmaHuge) + wMedium * B(sigmaMedium, sigmaLarge) + wSmall * B(sigmaSmall?, sigmaMedium)
// where B(a, b) = G_a * L - G_b * L is a difference of Gaussians (sigmas in fractions of the tile
// width so the result does not depend on resolution). The lowest frequencies (uneven lighting across
// the photo) are dropped. h is normalised to [0, 1] and d = 1 - h.
struct PhotoImportParams {
    double weightLarge = 1.0;    // >= 0. Large detail: shapes a tenth of the tile or bigger.
    double weightMedium = 0.6;   // >= 0. Medium detail.
    double weightSmall = 0.3;    // >= 0. Fine detail: texel-scale grain.
    double sigmaSmall = 0.0;     // fraction of tile width; 0 = no smoothing of the finest band
    double sigmaMedium = 0.004;  // fraction of tile width (about 2 texels at 512)
    double sigmaLarge = 0.02;    // fraction of tile width
    double sigmaHuge = 0.12;     // fraction of tile width: anything broader is lighting, dropped
    bool invert = false;         // true when dark means high (e.g. a photo of raised dark stones)
    double depthScale = kDefaultDepthScale;  // S for the derived normal map
};

// Returns depth, normals (at params.depthScale) and the photo itself as colour.
// Throws Error(InvalidInput) for negative or all-zero weights, or non-increasing sigmas.
ReliefTexture reliefFromPhoto(const Image& photo, const PhotoImportParams& params = {});

// ---------------------------------------------------------------------------------------------
// Which convention a normal map follows, found by comparing it with the normals derived from its
// depth map: the x components must agree in sign; the y components agree for OpenGL (green up)
// and are opposite for DirectX (green down). Maps of different resolutions are compared at the
// normal map's resolution.
enum class NormalConvention { OpenGL, DirectX, Unknown };

struct NormalConventionReport {
    NormalConvention convention;
    double correlationX;  // Pearson correlation of the file's nx with the derived nx (should be > 0)
    double correlationY;  // of the file's ny with the derived ny: > 0 OpenGL, < 0 DirectX
    std::string summary;  // one line for a human
};

// `normals` are decoded (n in [-1, 1]) as stored, without any flip.
NormalConventionReport detectNormalConvention(const Image& normals, const Image& depth);

const char* toString(NormalConvention convention);

} // namespace strata
