// Exact ray / height-field intersection by cone step mapping (Dummer 2006; Policarpo & Oliveira, GPU Gems 3
// ch. 18) made robust as Bán et al. 2024 ("Robust Cone Step Mapping") ask, written once in the common subset
// of GLSL 4.50 and C++ (shared/prelude.h). C++ includes it as "shared/cone.h" and gets the class
// strata::shared::ConeStepping; shaders/relief/cone.glsl includes it and supplies the fetches.
//
// Cones valid for the whole bilinear cell (their min filter), never wider than computed (rounded down when
// quantised), and every step reaching at least the cell border, where the cell itself is solved in closed
// form (shared/bilinear_cell.h). No step count, and no binary search: the result is the first intersection
// with the bilinear height field of CONVENTIONS §1, as maxmip's.
//
// The cone map (strata/relief/cone_map.h, packConeMap): per cell C, RG16 = (m_C, sqrt(c_C / maxRatio)),
// m_C the cell's highest point (smallest corner depth) and c_C a ratio, in cells per unit of depth, such that
// for every x in C the cone of apex (x, d(x)) opening upwards with radius c_C per unit of depth holds no
// relief: d(y) >= d(x) - |y - x| / c_C everywhere.
//
// A ray at depth d (c(d) = c0 + cd d, travelling |cd| cells per unit of depth) whose point x lies above an
// apex of depth a (a >= d) may move on while it stays inside that cone: while
// d + dd <= a - |cd| dd / c, i.e. by dd = c (a - d) / (c + |cd|). The loop, per cell:
//   1. the ray above m_C: the apex (x, m_C) is conservative (d(x) >= m_C); step by its cone, and if that
//      leaves the cell, go on without reading the cell (one coneTexel);
//   2. otherwise solve the cell exactly from d to its exit (one cellCorners); at a miss, move to the
//      exit, and on from there by the cone of the exit point's own apex depth (the patch's depth there).
// Both steps only skip relief-free space, so the first cell whose solve finds a root holds the first hit.
#ifdef __cplusplus
#pragma once
#endif
#include "bilinear_cell.h"
#include "prelude.h"
STRATA_SHARED_BEGIN

STRATA_SHARED_CLASS_BEGIN(ConeStepping)
// The fetches. The base level's size in texels (textureSize); the cone map's texel `texel` (wrapped), its
// two unorm channels (texelFetch); the ratio that a second channel of 1 encodes (packConeMap's maxRatio);
// the four corner depths of cell `cell` (unwrapped), as bilinear_cell.h orders them (textureGather).
STRATA_SHARED_FETCH(vec2 reliefSize())
STRATA_SHARED_FETCH(vec2 coneTexel(ivec2 texel))
STRATA_SHARED_FETCH(float coneMaxRatio())
STRATA_SHARED_FETCH(vec4 cellCorners(vec2 cell, vec2 size))

// (m_C, c_C) of cell `cell` (unwrapped). The decoded ratio is nudged down so that float rounding of the
// unorm conversion never widens the cone.
vec2 coneOf(vec2 cell, vec2 size) {
    ivec2 wrapped = ivec2(cell - floor(cell / size) * size);
    vec2 texel = coneTexel(wrapped);
    return vec2(texel.x, texel.y * texel.y * coneMaxRatio() * (1.0f - 1e-6f));
}

// Depth t in [0, 1] of the first intersection of the ray (dp, ds) (shared/relief_search.h's form) with the
// bilinear height field of the base level, up to float rounding; 1 when none is found (rounding at d = 1, or
// the iteration cap), as the relief search does.
float coneIntersect(vec2 dp, vec2 ds) {
    vec2 size = reliefSize();
    vec2 c0 = dp * size - 0.5f;
    vec2 cd = ds * size;
    float travel = length(cd);
    vec2 ahead = step(0.0f, cd);
    vec2 inverse = vec2(abs(cd.x) > 1e-20f ? 1.0f / cd.x : 1e30f, abs(cd.y) > 1e-20f ? 1.0f / cd.y : 1e30f);
    float d = 0.0f;
    for (int iteration = 0; iteration < 2048; ++iteration) {
        vec2 cell = cellAt(c0 + cd * d, cd, 1.0f);
        float dExit = cellExit(cell, 1.0f, c0, ahead, inverse);
        vec2 cone = coneOf(cell, size);
        if (d < cone.x) {
            d += cone.y * (cone.x - d) / (cone.y + travel);
            if (d >= 1.0f) break;
            if (d >= dExit) continue;
        }
        vec4 g = cellCorners(cell, size);
        float hit = cellIntersect(g, cell, c0, cd, d, dExit);
        if (hit >= 0.0f) return hit;
        if (dExit >= 1.0f) break;
        float apex = cellDepth(g, clamp(c0 + cd * dExit - cell, 0.0f, 1.0f));
        d = max(dExit, dExit + cone.y * (apex - dExit) / (cone.y + travel));
    }
    return 1.0f;
}
STRATA_SHARED_CLASS_END

STRATA_SHARED_END
