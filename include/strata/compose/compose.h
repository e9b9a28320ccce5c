// Meta-relief composition (Limberger, Schetinger, Oliveira 2015, Section III-A): layers of relief at
// several scales, resolutions and tiling factors combined into one relief texture.
//
//   depth   = sum_i w_d,i * d_i(t_i * uv) / sum_i w_d,i                        (paper Eq. 2)
//   normal  = normalize( sum_i w_n,i * n_i(t_i * uv) / sum_i w_n,i )           (paper Eq. 1, `paper`)
//   normal  = normalize(S * dD/du, S * dD/dv, 1), D the composed depth above    (`consistent`)
//
// Each layer is sampled with wrap-around bilinear reconstruction at t_i times the output texel
// centre (CONVENTIONS §1), at its own resolution. `paper` averages the layers' normal maps as the
// paper does; those maps were made for each layer's own depth scale and tiling 1, so the result is
// not the normal of the composed depth. `consistent` is that normal: the chain rule gives
// dD/du = sum_i w_d,i * t_i * (dd_i/du)(t_i * uv) / sum_i w_d,i, so a layer tiled t times has t times
// steeper slopes, and everything is at the output depth scale S. docs/composition.md measures the
// difference between the two.
//
// Baking a layer whose tiling factor is not an integer gives a texture that does not tile (the
// layer is cut at the tile border); compose() reports that as a warning. The live path in the
// renderer samples the layers per fragment and has no such seam.
#pragma once

#include "strata/relief/relief_texture.h"

#include <span>
#include <string>
#include <vector>

namespace strata {

struct CompositionLayer {
    // depth is required. normal is required in NormalMode::Paper (3 channels, decoded, any resolution).
    // color is optional and used only by the layer chosen in ComposeParams::colorFrom.
    ReliefTexture texture;
    double tiling = 1.0;        // > 0, any real: the layer is sampled at tiling * uv
    double weightDepth = 1.0;   // w_d >= 0 (Eq. 2)
    double weightNormal = 1.0;  // w_n >= 0 (Eq. 1)
    std::string label;          // names the layer in messages, e.g. "layers[1] (fabric)"
};

enum class NormalMode {
    Paper,       // Eq. 1: weighted average of the layers' normal maps, normalised for storage
    Consistent,  // the normal of the composed depth field at the output depth scale
};

struct ComposeParams {
    int resolution = 0;  // output width = height in texels; 0 = the largest layer depth width
    double depthScale =
        kDefaultDepthScale;  // output S (tile widths): the consistent normals' S, recorded in the set
    NormalMode normals = NormalMode::Paper;
    int colorFrom = 0;  // index of the layer whose colour map is used; -1 = no colour
};

struct Composition {
    ReliefTexture texture;              // depth, normal, colour (if any); ao stays empty
    std::vector<std::string> warnings;  // e.g. fractional tiling factors
};

// Throws Error(InvalidInput) naming the layer and the value for: no layers, a NaN, infinite or
// negative weight, a zero sum of depth or normal weights, a tiling factor that is not > 0, a missing
// depth map, a missing normal map in paper mode, a colorFrom index out of range or naming a layer
// without colour, a resolution outside [1, Image::kMaxDimension], a depth scale that is not > 0.
// Multithreaded (oneTBB) over output rows.
Composition compose(std::span<const CompositionLayer> layers, const ComposeParams& params);

// The same, into `result`, reusing its images' memory when their sizes already match: for
// interactive re-composition (a weight changed), where a 2048^2 result would otherwise be 112 MB of
// fresh memory per call (docs/composition.md has both timings).
void composeInto(std::span<const CompositionLayer> layers, const ComposeParams& params, Composition& result);

// The mean and largest angle in degrees between two unit-normal images of the same size.
struct AngleStats {
    double meanDegrees;
    double maxDegrees;
};
AngleStats angleBetween(const Image& normalsA, const Image& normalsB);

const char* toString(NormalMode mode);
// "paper" or "consistent"; throws Error(InvalidInput) for anything else.
NormalMode parseNormalMode(const std::string& text);

}  // namespace strata
