// Ambient occlusion of a meta-relief (Limberger, Schetinger, Oliveira 2015, Section IV-A, last paragraph
// but one): the AO map that goes with a composition (strata/compose/compose.h). docs/occlusion.md
// ("Combining layers") derives the per-layer parameters and measures the modes against each other.
//
// Modes (MetaAoMode):
//   Exact     (default) bakeAo() of the composed depth (paper Eq. 2) at the composition's depth scale S
//             and resolution: the AO of the composed relief itself, up to the AoMethod's own error.
//   Multiply  the paper's approach: each layer's AO is baked on the layer's own depth map at its own
//   Min       resolution, then combineAo() at the layers' tilings takes the product (the paper's choice)
//             or the minimum. An approximation: both are darker than Exact (by 0.015-0.15 on average on
//             the examples).
//
// Per-layer parameters in Multiply / Min, for layer i with depth weight w_i and tiling t_i,
// W = sum_j w_d,j over all layers (as compose() normalises Eq. 2):
//     S_i = S * (w_i / W) * t_i        (the layer's relief in its own tile units)
//     R_i = min(R * t_i, 16)           (R in composed tile widths; 16 is AoParams' limit)
// A layer with w_i = 0 is skipped (its AO is 1).
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

// The AoParams each layer is baked with in Multiply / Min (S_i, R_i above): `params` with
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
// compose), at the composition's resolution, by `mode`. `params` gives the
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
