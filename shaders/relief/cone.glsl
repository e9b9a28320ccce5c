// Exact ray / height-field intersection by cone step mapping (Dummer 2006; Policarpo & Oliveira, GPU Gems 3
// ch. 18) made robust as Bán et al. 2024 ("Robust Cone Step Mapping") ask: cones valid for the whole
// bilinear cell (their min filter), never wider than computed (rounded down when quantised), and every
// step reaching at least the cell border, where the cell itself is solved in closed form
// (bilinear_cell.glsl). No step count, and no binary search: the result is the first intersection with the
// bilinear height field of CONVENTIONS §1, as maxmip's.
//
// The cone map (strata/relief/cone_map.h, uploaded by the renderer): per cell C, RG16 =
// (m_C, sqrt(c_C / uConeMaxRatio)), m_C the cell's highest point (smallest corner depth) and c_C a ratio,
// in cells per unit of depth, such that for every x in C the cone of apex (x, d(x)) opening upwards with
// radius c_C per unit of depth holds no relief: d(y) >= d(x) - |y - x| / c_C everywhere.
//
// A ray at depth d (c(d) = c0 + cd d, travelling |cd| cells per unit of depth) whose point x lies above an
// apex of depth a (a >= d) may move on while it stays inside that cone: while
// d + dd <= a - |cd| dd / c, i.e. by dd = c (a - d) / (c + |cd|). The loop, per cell:
//   1. the ray above m_C: the apex (x, m_C) is conservative (d(x) >= m_C); step by its cone, and if that
//      leaves the cell, go on without reading the cell (one texelFetch);
//   2. otherwise solve the cell exactly from d to its exit (one textureGather); at a miss, move to the
//      exit, and on from there by the cone of the exit point's own apex depth (the patch's depth there).
// Both steps only skip relief-free space, so the first cell whose solve finds a root holds the first hit.
#include "bilinear_cell.glsl"

#include "shared/relief_uniforms.h"

layout(binding = kConeMapUnit) uniform sampler2D uConeMap;  // RG16, see above
// uConeMaxRatio, the ratio that sqrt(...) = 1 encodes: the per-draw block.

// (m_C, c_C) of cell `cell` (unwrapped). The decoded ratio is nudged down so that float rounding of the
// unorm conversion never widens the cone.
vec2 coneOf(vec2 cell, vec2 size) {
    ivec2 wrapped = ivec2(cell - floor(cell / size) * size);
    vec2 texel = texelFetch(uConeMap, wrapped, 0).rg;
    return vec2(texel.r, texel.g * texel.g * uConeMaxRatio * (1.0 - 1e-6));
}

// Depth t in [0, 1] of the first intersection of the ray (dp, ds) (relief_search.glsl's form) with the
// bilinear height field of uRelief's base level.
float coneIntersect(vec2 dp, vec2 ds) {
    vec2 size = vec2(textureSize(uRelief, 0));
    vec2 c0 = dp * size - 0.5;
    vec2 cd = ds * size;
    float travel = length(cd);
    vec2 ahead = step(0.0, cd);
    vec2 inverse = vec2(abs(cd.x) > 1e-20 ? 1.0 / cd.x : 1e30, abs(cd.y) > 1e-20 ? 1.0 / cd.y : 1e30);
    float d = 0.0;
    for (int iteration = 0; iteration < 2048; ++iteration) {
        vec2 cell = cellAt(c0 + cd * d, cd, 1.0);
        float dExit = cellExit(cell, 1.0, c0, ahead, inverse);
        vec2 cone = coneOf(cell, size);
        if (d < cone.x) {
            d += cone.y * (cone.x - d) / (cone.y + travel);
            if (d >= 1.0) break;
            if (d >= dExit) continue;
        }
        vec4 g = cellCorners(cell, size);
        float hit = cellIntersect(g, cell, c0, cd, d, dExit);
        if (hit >= 0.0) return hit;
        if (dExit >= 1.0) break;
        float apex = cellDepth(g, clamp(c0 + cd * dExit - cell, 0.0, 1.0));
        d = max(dExit, dExit + cone.y * (apex - dExit) / (cone.y + travel));
    }
    // Not found (rounding at d = 1, or the iteration cap): the bottom, as the relief search does.
    return 1.0;
}
