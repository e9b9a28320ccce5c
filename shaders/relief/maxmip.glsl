// Exact ray / height-field intersection by maximum-mipmap traversal (Tevs, Ihrke, Seidel 2008, "Maximum
// Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field Rendering"), with the leaf solved in closed
// form against the bilinear patch of CONVENTIONS §1. No step count: the result is the first intersection
// with the same height field the exact CPU tracer intersects (strata/trace/heightfield_tracer.h), up to
// float rounding.
//
// The traversal, maxMipIntersect, is shaders/shared/maxmip.h (shared with the C++ that counts its fetches,
// strata/trace/shader_loops.h); here are its fetches. uMaxMip level 0 holds, per cell, the highest point
// (smallest depth) of the cell's bilinear patch, level k the smallest over 2^k x 2^k cells (uploadMaterial
// builds it, power-of-two maps only).
#include "bilinear_cell.glsl"

#include "shared/relief_uniforms.h"

layout(binding = kMaxMipUnit) uniform sampler2D uMaxMip;  // R16: the highest point (smallest d) per node
// uMaxMipLevels, the levels of uMaxMip (the top one is 1 x 1): the per-draw block.

float maxMipNode(ivec2 texel, int level) {
    return texelFetch(uMaxMip, texel, level).r;
}

int maxMipLevels() {
    return uMaxMipLevels;
}

#include "shared/maxmip.h"
