// strata::ReliefTexture: the maps that describe one tile of relief (CONVENTIONS §1-§5).
#pragma once

#include "strata/image/image.h"

namespace strata {

// The depth scale Strata uses where none is given: the depth of d = 1 as a fraction of the tile's
// width (CONVENTIONS §2). The same default everywhere: patterns, imports, materials, the CLI.
inline constexpr double kDefaultDepthScale = 0.08;
// The largest depth scale anything in Strata writes or renders: a relief ten tile widths deep. Every
// command and file key that takes a depth scale accepts (0, kMaxReliefDepthScale], so that a set one
// command writes, another can render.
inline constexpr double kMaxReliefDepthScale = 10.0;

struct ReliefTexture {
    // 1 channel, d in [0, 1]: 0 is the polygon's surface (the top), 1 the deepest point.
    Image depth;
    // 3 channels, unit tangent-space normals (nx, ny, nz), OpenGL convention (+y towards v = 1).
    // Stored decoded; files store n * 0.5 + 0.5. Valid for `depthScale`.
    Image normal;
    // Optional, 3 channels, sRGB-encoded colour in [0, 1]. May have another resolution.
    Image color;
    // Optional, 1 channel, ambient occlusion in [0, 1] (1 = open), CONVENTIONS §4.
    Image ao;
    // The depth scale S the normal map was made for (and the AO was baked at).
    double depthScale = kDefaultDepthScale;
};

// The normal of a depth field at depth scale S (CONVENTIONS §3):
//     n = normalize(S * dd/du, S * dd/dv, 1),
// with derivatives per tile (a texel step is 1/W of the tile), taken by central differences with
// wrap-around at texel centres. Returns a 3-channel image of the depth map's resolution.
Image normalsFromDepth(const Image& depth, double depthScale);

// Per-tile gradient of a depth field, (dd/du, dd/dv), central differences with wrap-around.
// 2 channels. normalsFromDepth() is normalize(S * g.x, S * g.y, 1) of this.
Image depthGradient(const Image& depth);

// Encodes unit normals to the stored form n * 0.5 + 0.5 (3 channels) and back. decodeNormals
// renormalises (a quantised map is not exactly unit) and, with `flipY`, converts a DirectX-convention
// map (green down) to Strata's OpenGL convention.
Image encodeNormals(const Image& normals);
Image decodeNormals(const Image& encoded, bool flipY = false);

// d = 1 - h for a height map (white = high) and back; the same function both ways.
Image heightToDepth(const Image& height);

}  // namespace strata
