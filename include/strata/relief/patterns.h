// The built-in procedural relief library: the textures the meta-relief paper combines (its Fig. 10),
// and a few more. Every pattern is tileable (it repeats exactly across the tile border), deterministic
// for a given seed, available at any size from 64 to 4096, and comes with a matching colour map.
// The demo, the tests and the viewer use these as their embedded defaults.
#pragma once

#include "strata/relief/relief_texture.h"

#include <cstdint>
#include <string>
#include <vector>

namespace strata {

struct PatternParams {
    int size = 512;                          // width = height, texels; [kMinPatternSize, kMaxPatternSize]
    std::uint32_t seed = 1;                  // every random choice derives from this
    double depthScale = kDefaultDepthScale;  // S for the normal map (CONVENTIONS §2, §3)
};

inline constexpr int kMinPatternSize = 64;
inline constexpr int kMaxPatternSize = 4096;

struct PatternInfo {
    std::string name;         // e.g. "fabric"
    std::string description;  // one line, for `strata pattern --list`
};

// All patterns, in a stable order.
const std::vector<PatternInfo>& patternList();
bool isPattern(const std::string& name);

// Makes a pattern: depth in [0, 1] (0 = top), normals from the depth at params.depthScale
// (normalsFromDepth), colour (sRGB, 3 channels) at the same size; no AO.
// Every pattern is a function of continuous (u, v), so its shape does not change with size: up to 512
// each texel is the box-filtered average of 512 / size samples per axis (a smaller pattern equals the
// area-correct resample() of a larger one), from 512 up one sample at each texel centre. Depth is
// mapped to [0, 1] with extremes that do not depend on the size (docs/patterns.md).
// Throws Error(InvalidInput) for an unknown name (listing the known ones), a size outside the range,
// or a depth scale that is not positive and finite.
ReliefTexture makePattern(const std::string& name, const PatternParams& params = {});

}  // namespace strata
