// Exact ray / height-field intersection by maximum-mipmap traversal (Tevs, Ihrke, Seidel 2008, "Maximum
// Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field Rendering"), with the leaf solved in closed
// form against the bilinear patch of CONVENTIONS §1. No step count: the result is the first intersection
// with the same height field the exact CPU tracer intersects (strata/trace/heightfield_tracer.h), up to
// float rounding.
//
// Cells. In cell coordinates c = uv * size - 0.5 (texel centres at integers; GL's rows, so c.y grows with v)
// cell (i, j) is the square [i, i + 1] x [j, j + 1] between four texel centres, where the depth is
// bilinear in their four values. uMaxMip level 0 holds, per cell, the smallest of those four (a bilinear
// patch takes its extremes at its corners): the highest point of the cell, as depth is 0 at the top. Level
// k holds the smallest over 2^k x 2^k cells (uploadMaterial builds it, power-of-two maps only). Nodes wrap
// like the texture.
//
// Traversal (the ray's depth d from 0 to 1 along c(d) = c0 + cd d), from the level whose nodes are about as
// wide as the ray's travel |cd| (Tevs et al. start at the top): at a node of level k whose highest point
// is m, a ray that leaves the node's square before reaching depth m cannot meet anything inside: skip to the
// exit and go up a level; otherwise move down to depth m (nothing above it) and descend. At level 0 solve
// the cell exactly; if the ray passes, skip to the exit and go up. Every step reads one node
// (texelFetch), a cell one textureGather of the four depths.
#include "shared/relief_search.h"

layout(binding = 12) uniform sampler2D uMaxMip;  // R16: the highest point (smallest d) per node
uniform int uMaxMipLevels;                       // levels of uMaxMip (the top one is 1 x 1)

// The first depth in [dA, dB] where the ray enters the bilinear patch of cell `cell` (unwrapped), or -1.
// With s, t the ray's position in the cell (affine in d) the depth under it is
// D = a + b s + c t + e s t, so f(d) = D - d is a quadratic; measured from dA, where the ray is above the
// surface (f > 0) unless rounding put it just inside.
float maxMipCell(vec2 cell, vec2 size, vec2 c0, vec2 cd, float dA, float dB) {
    // The four corner depths: textureGather at the cell's centre reads exactly its 2x2 texels (wrapping);
    // components x = (i, j+1), y = (i+1, j+1), z = (i+1, j), w = (i, j).
    vec4 g = textureGather(uRelief, (cell + 1.0) / size, 3);
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

// Depth t in [0, 1] of the first intersection of the ray (dp, ds) (relief_search.glsl's form) with the
// bilinear height field of uRelief's base level.
float maxMipIntersect(vec2 dp, vec2 ds) {
    vec2 size = vec2(textureSize(uRelief, 0));
    vec2 c0 = dp * size - 0.5;
    vec2 cd = ds * size;
    // Per axis, which face of a node the ray leaves by, and 1 / cd (a ray parallel to an axis never leaves
    // through that axis's faces).
    vec2 ahead = step(0.0, cd);
    vec2 inverse = vec2(abs(cd.x) > 1e-20 ? 1.0 / cd.x : 1e30, abs(cd.y) > 1e-20 ? 1.0 / cd.y : 1e30);
    int top = uMaxMipLevels - 1;
    // Start where a node is about as wide as the ray's whole travel through the depth range: a larger one
    // is never left before the ray reaches its highest point, so reading it only costs a fetch.
    int level = min(top, int(ceil(log2(max(max(abs(cd.x), abs(cd.y)), 1.0)))));
    float d = 0.0;
    for (int iteration = 0; iteration < 1024; ++iteration) {
        float width = exp2(float(level));
        // A point on a face belongs to the node ahead of it: nudged by a few float steps of its magnitude.
        vec2 c = c0 + cd * d;
        vec2 node = floor((c + sign(cd) * max(vec2(1e-4), abs(c) * 5e-7)) / width);
        vec2 exitFace = (node + ahead) * width;
        vec2 exits = (exitFace - c0) * inverse;
        exits = mix(exits, vec2(1e30), greaterThan(abs(inverse), vec2(1e29)));
        float dExit = min(min(exits.x, exits.y), 1.0);
        if (level == 0) {
            float hit = maxMipCell(node, size, c0, cd, d, dExit);
            if (hit >= 0.0) return hit;
            if (dExit >= 1.0) break;
            d = dExit;
            level = min(level + 1, top);
            continue;
        }
        ivec2 levelSize = max(ivec2(size) >> level, ivec2(1));
        ivec2 wrapped = ivec2(node - floor(node / vec2(levelSize)) * vec2(levelSize));
        float highest = texelFetch(uMaxMip, wrapped, level).r;
        if (highest > dExit) {
            if (dExit >= 1.0) break;
            d = dExit;
            level = min(level + 1, top);
        } else {
            d = max(d, highest);
            --level;
        }
    }
    // Not found (rounding at d = 1, or the iteration cap): the bottom, as the relief search does.
    return 1.0;
}
