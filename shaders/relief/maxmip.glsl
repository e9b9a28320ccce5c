// Exact ray / height-field intersection by maximum-mipmap traversal (Tevs, Ihrke, Seidel 2008, "Maximum
// Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field Rendering"), with the leaf solved in closed
// form against the bilinear patch of CONVENTIONS §1. No step count: the result is the first intersection
// with the same height field the exact CPU tracer intersects (strata/trace/heightfield_tracer.h), up to
// float rounding.
//
// Cells (bilinear_cell.glsl): cell (i, j) is the square between four texel centres, where the depth is
// bilinear in their values. uMaxMip level 0 holds, per cell, the smallest of those four (a bilinear patch
// takes its extremes at its corners): the highest point of the cell, as depth is 0 at the top. Level k
// holds the smallest over 2^k x 2^k cells (uploadMaterial builds it, power-of-two maps only). Nodes wrap
// like the texture.
//
// Traversal (the ray's depth d from 0 to 1 along c(d) = c0 + cd d), from the level whose nodes are about as
// wide as the ray's travel |cd| (Tevs et al. start at the top): at a node of level k whose highest point
// is m, a ray that leaves the node's square before reaching depth m cannot meet anything inside: skip to the
// exit and go up a level; otherwise move down to depth m (nothing above it) and descend. At level 0 solve
// the cell exactly; if the ray passes, skip to the exit and go up. Every step reads one node
// (texelFetch), a cell one textureGather of the four depths.
#include "bilinear_cell.glsl"

#include "shared/relief_uniforms.h"

layout(binding = kMaxMipUnit) uniform sampler2D uMaxMip;  // R16: the highest point (smallest d) per node
// uMaxMipLevels, the levels of uMaxMip (the top one is 1 x 1): the per-draw block.

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
        vec2 node = cellAt(c0 + cd * d, cd, width);
        float dExit = cellExit(node, width, c0, ahead, inverse);
        if (level == 0) {
            float hit = cellIntersect(cellCorners(node, size), node, c0, cd, d, dExit);
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
