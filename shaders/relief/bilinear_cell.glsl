// One cell of the bilinear height field (CONVENTIONS §1) against a ray, in closed form: the leaf of the
// exact techniques (maxmip.glsl, cone.glsl). The math is shared with C++ (shaders/shared/bilinear_cell.h:
// cells, cellIntersect, cellAt, cellExit); here are the fetches that the exact techniques' shared loops
// (shared/maxmip.h, shared/cone.h) declare and the shader supplies.
#include "relief_search.glsl"
#include "shared/bilinear_cell.h"

// The four corner depths of cell `cell` (unwrapped): textureGather at the cell's centre reads exactly its
// 2x2 texels (wrapping); components x = (i, j+1), y = (i+1, j+1), z = (i+1, j), w = (i, j).
vec4 cellCorners(vec2 cell, vec2 size) {
    return textureGather(uRelief, (cell + 1.0) / size, 3);
}

// Texels per side of the height field's base level.
vec2 reliefSize() {
    return vec2(textureSize(uRelief, 0));
}
