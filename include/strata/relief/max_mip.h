// The maximum mipmap of a depth map (Tevs, Ihrke, Seidel 2008), as the `maxmip` technique traverses it
// (shaders/shared/maxmip.h; docs/renderer.md): the GL renderer uploads it, and strata/trace/shader_loops.h
// walks it on the CPU with the same loop.
//
// Frame: cell coordinates c = (u W - 0.5, v H - 0.5), texel centres at integers, so c.y grows with v (row 0
// of a level is at v = 0: the image's last row, as GL stores the uploaded, flipped texture). Cell (i, j) is
// the square [i, i + 1] x [j, j + 1] between four texel centres (wrapping), where the depth is bilinear in
// their values. Level 0 holds, per cell, the smallest of those four (the cell's highest point: a bilinear
// patch takes its extremes at its corners); level k the smallest of the 2 x 2 nodes of level k - 1 below
// it, a side that has shrunk to 1 staying 1 (its node covering the whole side).
#pragma once

#include "strata/image/image.h"

#include <vector>

namespace strata {

// The levels, finest first, down to 1 x 1: level k is max(1, W >> k) x max(1, H >> k), 1 channel, rows in
// the frame above. Throws Error(InvalidInput) for a map of more than one channel or whose sides are not
// powers of two.
std::vector<Image> maxMipPyramid(const Image& depth);

}  // namespace strata
