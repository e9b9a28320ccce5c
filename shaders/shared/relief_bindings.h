// The binding points and limits that the relief programs (shaders/relief/) and the renderer that binds
// their inputs (src/gl/relief_renderer.cpp) share, written once in the common subset of GLSL 4.50 and C++
// (STYLE.md, "GLSL beside C++"). C++ includes it as "shared/relief_bindings.h" and gets them in
// strata::shared; a shader includes it the same way and names them in layout(binding = ...).
#ifdef __cplusplus
#pragma once
#endif
#include "prelude.h"
STRATA_SHARED_BEGIN

// The most layers a live meta-relief has: the size of the shader's layer sampler array and of the layer
// arrays in the uniform block (relief_uniforms.h).
const int kMaxLiveLayers = 8;

// Texture units.
const int kReliefUnit = 0;       // uRelief: the packed relief texture (CONVENTIONS §5) the searches read
const int kColorUnit = 1;        // uColor: the colour map, SRGB8_ALPHA8
const int kReliefShadeUnit = 2;  // uReliefShade: the packed texture again, for the final normal and AO fetch
const int kLayerUnit0 = 3;       // uLayers[i] at unit kLayerUnit0 + i, i < kMaxLiveLayers
const int kComposedAoUnit = kLayerUnit0 + kMaxLiveLayers;  // uComposedAo: a live material's composed AO
const int kMaxMipUnit = kComposedAoUnit + 1;               // uMaxMip: the maximum mipmap (maxmip.glsl)
const int kConeMapUnit = kMaxMipUnit + 1;                  // uConeMap: the cone map (cone.glsl)

// Uniform-buffer binding points.
const int kReliefUniformsBinding = 0;  // the per-draw block ReliefUniforms (relief_uniforms.h)

#ifdef __cplusplus
// The units the renderer has always used, and within the 16 that OpenGL 4.5 guarantees a fragment shader.
static_assert(kComposedAoUnit == 11 && kMaxMipUnit == 12 && kConeMapUnit == 13);
static_assert(kConeMapUnit < 16);
#endif
STRATA_SHARED_END
