// One cell of the bilinear height field (CONVENTIONS §1) against a ray, in closed form: the leaf of the exact
// techniques (shared/maxmip.h, shared/cone.h), written once in the common subset of GLSL 4.50 and C++
// (shared/prelude.h). C++ includes it as "shared/bilinear_cell.h" and gets strata::shared::cellIntersect()
// and the others; shaders/relief/bilinear_cell.glsl includes it. No texture reads: the corners come from the
// includer's cellCorners.
//
// Cells. In cell coordinates c = uv * size - 0.5 (texel centres at integers; GL's rows, so c.y grows with v)
// cell (i, j) is the square [i, i + 1] x [j, j + 1] between four texel centres, where the depth is
// bilinear in their four values. A ray is c(d) = c0 + cd d for depth d from 0 to 1 (cd: cells per unit of
// depth). The corners g of a cell are those of a textureGather at its centre: x = (i, j+1), y = (i+1, j+1),
// z = (i+1, j), w = (i, j).
#ifdef __cplusplus
#pragma once
#endif
#include "prelude.h"
STRATA_SHARED_BEGIN

// The depth of the patch with corners g at p = (s, t), the position in the cell.
STRATA_SHARED_FUNCTION float cellDepth(vec4 g, vec2 p) {
    return mix(mix(g.w, g.z, p.x), mix(g.x, g.y, p.x), p.y);
}

// The first depth in [dA, dB] where the ray enters the patch with corners g of cell `cell`, or -1. With
// s, t the ray's position in the cell (affine in d) the depth under it is D = a + b s + c t + e s t, so
// f(d) = D - d is a quadratic; measured from dA, where the ray is above the surface (f > 0) unless rounding
// put it just inside.
STRATA_SHARED_FUNCTION float cellIntersect(vec4 g, vec2 cell, vec2 c0, vec2 cd, float dA, float dB) {
    float a = g.w;
    float b = g.z - g.w;
    float c = g.x - g.w;
    float e = g.w - g.z - g.x + g.y;
    vec2 p = c0 + cd * dA - cell;  // (s, t) at dA
    float C = a + b * p.x + c * p.y + e * p.x * p.y - dA;
    if (C <= 0.0f) return dA;
    float B = b * cd.x + c * cd.y + e * (p.x * cd.y + p.y * cd.x) - 1.0f;
    float A = e * cd.x * cd.y;
    float span = dB - dA;
    float first = -1.0f;  // smallest root in [0, span]
    if (abs(A) < 1e-12f * max(abs(B), 1e-30f)) {
        if (B < 0.0f) first = -C / B;
    } else {
        float disc = B * B - 4.0f * A * C;
        if (disc >= 0.0f) {
            // Both roots without cancellation (q has the sign of -B).
            float q = -0.5f * (B + (B >= 0.0f ? sqrt(disc) : -sqrt(disc)));
            float r1 = q / A;
            float r2 = q != 0.0f ? C / q : r1;
            float lo = min(r1, r2), hi = max(r1, r2);
            first = lo >= 0.0f ? lo : hi;
        }
    }
    return first >= 0.0f && first <= span ? dA + first : -1.0f;
}

// The cell that c(d) is in, a point on a face belonging to the cell ahead of it (nudged by a few float
// steps of its magnitude), and the depth where the ray leaves it (at most 1). `ahead` = step(0, cd),
// `inverse` = 1 / cd with 1e30 for an axis the ray does not move along. Cells of `width` (a power of two)
// for the maximum mipmap's nodes.
STRATA_SHARED_FUNCTION vec2 cellAt(vec2 c, vec2 cd, float width) {
    return floor((c + sign(cd) * max(vec2(1e-4f), abs(c) * 5e-7f)) / width);
}
STRATA_SHARED_FUNCTION float cellExit(vec2 cell, float width, vec2 c0, vec2 ahead, vec2 inverse) {
    vec2 exits = ((cell + ahead) * width - c0) * inverse;
    exits = mix(exits, vec2(1e30f), greaterThan(abs(inverse), vec2(1e29f)));
    return min(min(exits.x, exits.y), 1.0f);
}

STRATA_SHARED_END
