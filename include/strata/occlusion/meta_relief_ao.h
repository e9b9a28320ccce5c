// Ambient occlusion of a meta-relief (Limberger, Schetinger, Oliveira 2015, Section IV-A, last two
// paragraphs but one): the AO map that goes with a composition (strata/compose/compose.h).
//
// Modes (MetaAoMode):
//   Exact     bakeAo() of the composed depth D = sum_i w_d,i d_i(t_i uv) / sum_i w_d,i (paper Eq. 2) at
//             the composition's depth scale S and resolution. This is the AO of the composed relief
//             itself (CONVENTIONS §4), up to the AoMethod's own errors. The default.
//   Multiply  the paper's approach: each layer's AO is baked on the layer's own depth map, at its own
//   Min       resolution, and the maps are combined with combineAo() at the layers' tilings: the product
//             (the paper's choice, "used for the images in the paper") or the minimum. An approximation:
//             occlusion by one layer's relief of another's is not the product (nor the minimum) of the
//             two, and a layer's relief sits on the others' slopes, which the per-layer bake ignores.
//
// Per-layer parameters in Multiply / Min. Layer i (depth d_i, tiling t_i, weight w_i = w_d,i) enters
// Eq. 2 as (w_i / W) d_i(t_i uv), W = sum_j w_d,j over all layers (as compose() normalises: layers with
// both weights 0 are in the sum with 0). In tile units of the composed texture that relief point is
// (u, v, -S (w_i / W) d_i(t_i u, t_i v)). In the layer's own tile units (u' = t_i u) it is
// (u' / t_i, v' / t_i, -S (w_i / W) d_i(u', v')); scaling all three axes by t_i (which changes no angle,
// hence no AO) gives (u', v', -S_i d_i(u', v')) with
//     S_i = S * (w_i / W) * t_i,
// i.e. a layer tiled t times is t times steeper in its own tile units. The search radius R (composed
// tile widths) becomes R * t_i layer tiles; AoParams allows at most 16, so
//     R_i = min(R * t_i, 16)
// (a layer tiled more than 16 / R times searches less far than R; the nearest occluders, which dominate,
// are all within it). A layer with w_i = 0 contributes nothing to the depth, so its AO is 1 everywhere
// and it is skipped. AoNormalize::Paper scales an open texel to (M/2) sin(2 pi / M) / pi per layer, so
// under Multiply n layers give that value to the power n in the open; Open (the default) gives 1.
#pragma once

#include "strata/compose/compose.h"
#include "strata/occlusion/ambient_occlusion.h"

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace strata {

enum class MetaAoMode {
    Exact,     // bakeAo of the composed depth (default)
    Multiply,  // product of the per-layer AO maps (the paper's choice)
    Min,       // minimum of the per-layer AO maps
};

// "exact" | "multiply" | "min".
const char* toString(MetaAoMode mode);
// Throws Error(InvalidInput) listing the accepted names for anything else.
MetaAoMode parseMetaAoMode(const std::string& text);

// The AoParams each layer is baked with in Multiply / Min (see the top of this file): `params` with
// depthScale = S_i and radius = R_i, or nullopt for a layer with weight_depth 0 (skipped, AO 1).
// S is compose.depthScale; params.depthScale is not used. Throws Error(InvalidInput) like compose()
// for bad layers or weights, and naming the layer for an S_i outside AoParams' range (0, 100].
std::vector<std::optional<AoParams>> metaReliefLayerAoParams(std::span<const CompositionLayer> layers,
                                                             const ComposeParams& compose,
                                                             const AoParams& params);

// Called before each bake with a short description of it (e.g. "layers[1] (fabric): 512x512,
// S = 0.024, R = 8"), for progress reports. May be empty.
using MetaAoProgress = std::function<void(const std::string& message)>;

// The AO map (1 channel, in [0, 1], 1 = open) of the meta-relief `composition` = compose(layers,
// compose), at the composition's resolution, by `mode` (see the top of this file). `params` gives the
// method, directions, radius R (composed tile widths), filter, normalisation and march step; its
// depthScale is not used: the depth scale is compose.depthScale (Exact) or S_i (Multiply / Min).
// Multithreaded (through bakeAo). Throws Error(InvalidInput) like compose() for bad layers, like
// bakeAo() for AoParams out of range (the message names the layer in Multiply / Min), and if
// `composition` has no depth map.
Image metaReliefAo(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                   const Composition& composition, MetaAoMode mode, const AoParams& params,
                   const MetaAoProgress& progress = {});

// How a meta-relief AO map was made, for the texture set's AoRecord::method: the AoMethod's name in
// Exact ("sweep"), "<mode> of per-layer <method>" otherwise ("multiply of per-layer sweep").
std::string metaReliefAoMethodName(MetaAoMode mode, AoMethod method);

}  // namespace strata
