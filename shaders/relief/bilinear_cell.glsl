// One cell of the bilinear height field (CONVENTIONS §1) against a ray, in closed form: the leaf of the
// exact techniques (maxmip.glsl, cone.glsl).
//
// Cells. In cell coordinates c = uv * size - 0.5 (texel centres at integers; GL's rows, so c.y grows with v)
// cell (i, j) is the square [i, i + 1] x [j, j + 1] between four texel centres, where the depth is
// bilinear in their four values. A ray is c(d) = c0 + cd d for depth d from 0 to 1 (cd: cells per unit of
// depth).
#include "relief_search.glsl"

// The four corner depths of cell `cell` (unwrapped): textureGather at the cell's centre reads exactly its
// 2x2 texels (wrapping); components x = (i, j+1), y = (i+1, j+1), z = (i+1, j), w = (i, j).
vec4 cellCorners(vec2 cell, vec2 size) {
    return textureGather(uRelief, (cell + 1.0) / size, 3);
}

// The depth of the patch with corners g (cellCorners) at p = (s, t), the position in the cell.
float cellDepth(vec4 g, vec2 p) {
    return mix(mix(g.w, g.z, p.x), mix(g.x, g.y, p.x), p.y);
}

// The first depth in [dA, dB] where the ray enters the patch with corners g of cell `cell`, or -1. With
// s, t the ray's position in the cell (affine in d) the depth under it is D = a + b s + c t + e s t, so
// f(d) = D - d is a quadratic; measured from dA, where the ray is above the surface (f > 0) unless rounding
// put it just inside.
float cellIntersect(vec4 g, vec2 cell, vec2 c0, vec2 cd, float dA, float dB) {
    float a = g.w;
    float b = g.z - g.w;
    float c = g.x - g.w;
    float e = g.w - g.z - g.x + g.y;
    vec2 p = c0 + cd * dA - cell;  // (s, t) at dA
    float C = a + b * p.x + c * p.y + e * p.x * p.y - dA;
    if (C <= 0.0) return dA;
    float B = b * cd.x + c * cd.y + e * (p.x * cd.y + p.y * cd.x) - 1.0;
    float A = e * cd.x * cd.y;
    float span = dB - dA;
    float first = -1.0;  // smallest root in [0, span]
    if (abs(A) < 1e-12 * max(abs(B), 1e-30)) {
        if (B < 0.0) first = -C / B;
    } else {
        float disc = B * B - 4.0 * A * C;
        if (disc >= 0.0) {
            // Both roots without cancellation (q has the sign of -B).
            float q = -0.5 * (B + (B >= 0.0 ? sqrt(disc) : -sqrt(disc)));
            float r1 = q / A;
            float r2 = q != 0.0 ? C / q : r1;
            float lo = min(r1, r2), hi = max(r1, r2);
            first = lo >= 0.0 ? lo : hi;
        }
    }
    return first >= 0.0 && first <= span ? dA + first : -1.0;
}

// The cell that c(d) is in, a point on a face belonging to the cell ahead of it (nudged by a few float
// steps of its magnitude), and the depth where the ray leaves it (at most 1). `ahead` = step(0, cd),
// `inverse` = 1 / cd with 1e30 for an axis the ray does not move along. Cells of `width` (a power of two)
// for the maximum mipmap's nodes.
vec2 cellAt(vec2 c, vec2 cd, float width) {
    return floor((c + sign(cd) * max(vec2(1e-4), abs(c) * 5e-7)) / width);
}
float cellExit(vec2 cell, float width, vec2 c0, vec2 ahead, vec2 inverse) {
    vec2 exits = ((cell + ahead) * width - c0) * inverse;
    exits = mix(exits, vec2(1e30), greaterThan(abs(inverse), vec2(1e29)));
    return min(min(exits.x, exits.y), 1.0);
}
