// Exact ray / height-field intersection by maximum-mipmap traversal (Tevs, Ihrke, Seidel 2008, "Maximum
// Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field Rendering"), with the leaf solved in closed
// form against the bilinear patch of CONVENTIONS §1 (shared/bilinear_cell.h), written once in the common
// subset of GLSL 4.50 and C++ (shared/prelude.h). C++ includes it as "shared/maxmip.h" and gets the class
// strata::shared::MaxMipTraversal; shaders/relief/maxmip.glsl includes it and supplies the fetches.
//
// Cells (shared/bilinear_cell.h): cell (i, j) is the square between four texel centres, where the depth is
// bilinear in their values. Level 0 of the maximum mipmap holds, per cell, the smallest of those four (a
// bilinear patch takes its extremes at its corners): the highest point of the cell, as depth is 0 at the top.
// Level k holds the smallest over 2^k x 2^k cells (strata/relief/max_mip.h; power-of-two maps only). Nodes
// wrap like the texture.
//
// Traversal (the ray's depth d from 0 to 1 along c(d) = c0 + cd d), from the level whose nodes are about as
// wide as the ray's travel |cd| (Tevs et al. start at the top): at a node of level k whose highest point
// is m, a ray that leaves the node's square before reaching depth m cannot meet anything inside: skip to the
// exit and go up a level; otherwise move down to depth m (nothing above it) and descend. At level 0 solve
// the cell exactly; if the ray passes, skip to the exit and go up. Every step reads one node (maxMipNode),
// a cell its four depths (cellCorners).
#ifdef __cplusplus
#pragma once
#endif
#include "bilinear_cell.h"
#include "prelude.h"
STRATA_SHARED_BEGIN

STRATA_SHARED_CLASS_BEGIN(MaxMipTraversal)
// The fetches. The base level's size in texels (textureSize); the mipmap's level count (its top is 1 x 1);
// the highest point (smallest d) of node `texel` (wrapped, in [0, size >> level)) of `level` (texelFetch);
// the four corner depths of cell `cell` (unwrapped), as bilinear_cell.h orders them (textureGather).
STRATA_SHARED_FETCH(vec2 reliefSize())
STRATA_SHARED_FETCH(int maxMipLevels())
STRATA_SHARED_FETCH(float maxMipNode(ivec2 texel, int level))
STRATA_SHARED_FETCH(vec4 cellCorners(vec2 cell, vec2 size))

// Depth t in [0, 1] of the first intersection of the ray (dp, ds) (shared/relief_search.h's form) with the
// bilinear height field of the base level, up to float rounding; 1 when none is found (rounding at d = 1, or
// the iteration cap), as the relief search does.
float maxMipIntersect(vec2 dp, vec2 ds) {
    vec2 size = reliefSize();
    vec2 c0 = dp * size - 0.5f;
    vec2 cd = ds * size;
    // Per axis, which face of a node the ray leaves by, and 1 / cd (a ray parallel to an axis never leaves
    // through that axis's faces).
    vec2 ahead = step(0.0f, cd);
    vec2 inverse = vec2(abs(cd.x) > 1e-20f ? 1.0f / cd.x : 1e30f, abs(cd.y) > 1e-20f ? 1.0f / cd.y : 1e30f);
    int top = maxMipLevels() - 1;
    // Start where a node is about as wide as the ray's whole travel through the depth range: a larger one
    // is never left before the ray reaches its highest point, so reading it only costs a fetch.
    int level = min(top, int(ceil(log2(max(max(abs(cd.x), abs(cd.y)), 1.0f)))));
    float d = 0.0f;
    for (int iteration = 0; iteration < 1024; ++iteration) {
        float width = exp2(float(level));
        // A point on a face belongs to the node ahead of it: nudged by a few float steps of its magnitude.
        vec2 node = cellAt(c0 + cd * d, cd, width);
        float dExit = cellExit(node, width, c0, ahead, inverse);
        if (level == 0) {
            float hit = cellIntersect(cellCorners(node, size), node, c0, cd, d, dExit);
            if (hit >= 0.0f) return hit;
            if (dExit >= 1.0f) break;
            d = dExit;
            level = min(level + 1, top);
            continue;
        }
        ivec2 levelSize = max(ivec2(size) >> level, ivec2(1));
        ivec2 wrapped = ivec2(node - floor(node / vec2(levelSize)) * vec2(levelSize));
        float highest = maxMipNode(wrapped, level);
        if (highest > dExit) {
            if (dExit >= 1.0f) break;
            d = dExit;
            level = min(level + 1, top);
        } else {
            d = max(d, highest);
            --level;
        }
    }
    return 1.0f;
}
STRATA_SHARED_CLASS_END

STRATA_SHARED_END
