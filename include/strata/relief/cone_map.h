// Conservative cone maps for cone step mapping (Dummer 2006; Policarpo & Oliveira, GPU Gems 3 ch. 18), with
// cones valid for whole bilinear cells and quantised downwards, as Bán et al. 2024 ("Robust Cone Step
// Mapping") ask. The `cone` technique traces with them (shaders/shared/cone.h, shaders/relief/cone.glsl).
//
// Frame and units: exactly those of max_mip.h's level 0. Cell coordinates c = (u W - 0.5, v H - 0.5), texel
// centres at integers; frame row y is image row H - 1 - y (row 0 at v = 0, as GL stores the flipped
// upload). Cell (i, j) is the closed square [i, i + 1] x [j, j + 1] between four texel centres, wrapping.
// Horizontal distances are in texels (cells), depths in depth units (CONVENTIONS §2: 0 = top, 1 = deepest);
// a ratio is texels per unit of depth.
//
// What a cell's ratio c_C guarantees. d is the bilinear, toroidal depth surface of CONVENTIONS §1. For every
// point x of the cell C and every point y of the (periodic) plane,
//     d(y) >= d(x) - |y - x| / c_C,
// i.e. the cone opening upwards from the surface point (x, d(x)), of radius c_C per unit of depth, holds no
// relief, whichever point of the cell is the apex. A tracer may therefore use c_C anywhere in the cell. The
// ratio is a lower bound of the largest such value (the true cone), never above it; it is exact for a
// flat map (the cap) and for the four cells around a lone pit or spike (1 / sqrt(2)), and within a small
// factor of the truth elsewhere (src/relief/cone_map.cpp explains the bound and the proof;
// tests/relief/test_cone_map.cpp measures the factor).
#pragma once

#include "strata/image/image.h"

#include <cstdint>

namespace strata {

struct ConeMapOptions {
    // K, the number of depth bands the far-field bound sorts cells into; [1, 4096], default 64. Cost grows
    // about linearly with it. More bands give wider cones (never less conservative), above all on gentle
    // ground: stone-bricks at 1024^2 has a mean ratio of 58 at K = 16, 116 at 64, 149 at 128.
    int depthLevels = 64;
    // The cap on the ratio, texels per unit of depth; >= 0, default 0, which means max(W, H) (a cone that
    // reaches across the whole tile per unit of depth). Also the value encodeConeRatio's 65535 stands for.
    float maxRatio = 0.0f;
};

// Per cell, the conservative cone ratio described at the top of this file, in [0, maxRatio]: a W x H,
// 1-channel image indexed exactly as maxMipPyramid's level 0 (at(i, j) is cell (i, j) of the frame, so row
// j of the result is NOT the image's row j: it belongs to image rows H - 1 - j and H - 2 - j). Any size.
// Throws Error(InvalidInput) naming the problem for an empty map, a map of more than one channel, a
// non-finite depth, or options out of range.
Image coneMap(const Image& depth, const ConeMapOptions& options = {});

// The cap coneMap uses for this map and these options: options.maxRatio, or max(W, H) where it is 0.
// Throws as coneMap does for an empty or multi-channel map or out-of-range options (it reads no depth).
float coneMapMaxRatio(const Image& depth, const ConeMapOptions& options);

// 16-bit quantisation as engines store cone maps: GPU Gems 3 ch. 18 stores sqrt(ratio), which spends the
// precision on narrow cones. q = floor(sqrt(ratio / maxRatio) * 65535), rounded DOWN so that the decoded
// cone is never wider than the computed one (Bán et al. 2024): decodeConeRatio(encodeConeRatio(r, m), m)
// <= r holds exactly in float, as decodeConeRatio computes it. A ratio >= maxRatio encodes as 65535, a ratio
// <= 0 (or NaN) as 0. maxRatio must be positive and finite (checked).
std::uint16_t encodeConeRatio(float ratio, float maxRatio);
// (q / 65535)^2 * maxRatio, in float: q / 65535.0f, squared, times maxRatio. A GPU's unorm conversion may
// round q / 65535 differently by an ulp; a shader should nudge the decoded ratio down by a relative 1e-6.
float decodeConeRatio(std::uint16_t q, float maxRatio);

// The cone map as the `cone` technique reads it (shaders/relief/cone.glsl) and as `strata cone-map` writes
// it: per cell, in the frame above, channel 0 the cell's highest point m_C (the smallest of its four corner
// depths, so that a ray above it may step by the cone of the apex (x, m_C)) and channel 1
// sqrt(ratio / maxRatio) rounded down (encodeConeRatio), both 16-bit values q stored as q / 65535 (writing
// them to a 16-bit PNG or a 16-bit unorm texture is exact). `depth` should hold the 16-bit values the
// tracer will read, so that m_C and the cones describe that very height field.
struct PackedConeMap {
    Image texels;  // W x H x 2, frame rows (row j is cell row j, v growing with j)
    float maxRatio = 0.0f;
    int depthLevels = 0;
};
PackedConeMap packConeMap(const Image& depth, const ConeMapOptions& options = {});

}  // namespace strata
