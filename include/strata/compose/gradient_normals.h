// A depth map's gradient stored as unit normals at a scale of its own, for the live meta-relief's consistent
// normals (NormalMode::Consistent combined per fragment: strata/gl/gpu_material.h, uploadLiveMaterial, and
// shaders/relief/relief.frag.glsl, metaShade). The shader recovers the gradient g = n.xy / (n.z S_L) of
// each layer and composes the gradients by the chain rule, which is exact for the composed depth.
//
// Gradients are per tile (depthGradient, strata/relief/relief_texture.h: central differences with
// wrap-around at texel centres); the normals follow CONVENTIONS §3, n = normalize(S_L g, 1).
#pragma once

#include "strata/image/image.h"

namespace strata {

// S_L for a gradient map (2 channels, e.g. depthGradient(depth)): 0.25 / max |g| over its texels, so that
// the steepest |S_L g| is 1/4. There a unit normal is within 3 % of linear in g, so filtering the normals
// (mipmaps, bilinear) filters the gradient, as the baked composition does, instead of bending it; and
// 16 bits per channel still resolve g to 1e-4 of its range. 1 for a flat map (every g = 0) or an empty one.
double gradientNormalScale(const Image& gradient);

struct GradientNormals {
    Image normals;       // 3 channels, the depth map's size: normalize(S_L g, 1), evaluated in float
    double scale = 1.0;  // S_L = gradientNormalScale(depthGradient(depth))
};

// The normals of `depth` (1 channel) at S_L. Throws Error(InvalidInput) for an empty map or one with
// other than 1 channel.
GradientNormals gradientNormals(const Image& depth);

}  // namespace strata
