// Exact ray / height-field intersection by cone step mapping (Dummer 2006; Policarpo & Oliveira, GPU Gems 3
// ch. 18) made robust as Bán et al. 2024 ("Robust Cone Step Mapping"): the first intersection with the
// bilinear height field of CONVENTIONS §1, as maxmip's, with no step count.
//
// The loop, coneIntersect, is shaders/shared/cone.h (shared with the C++ that counts its fetches,
// strata/trace/shader_loops.h), which describes the method; here are its fetches. The cone map
// (strata/relief/cone_map.h, uploaded by the renderer): per cell C, RG16 = (m_C, sqrt(c_C / uConeMaxRatio)),
// m_C the cell's highest point and c_C its cone's ratio, in cells per unit of depth.
#include "bilinear_cell.glsl"

#include "shared/relief_uniforms.h"

layout(binding = kConeMapUnit) uniform sampler2D uConeMap;  // RG16, see above
// uConeMaxRatio, the ratio that sqrt(...) = 1 encodes: the per-draw block.

vec2 coneTexel(ivec2 texel) {
    return texelFetch(uConeMap, texel, 0).rg;
}

float coneMaxRatio() {
    return uConeMaxRatio;
}

#include "shared/cone.h"
