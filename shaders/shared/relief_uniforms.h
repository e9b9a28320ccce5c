// The relief programs' per-draw uniforms: one std140 uniform block, declared once in the common subset of
// GLSL 4.50 and C++ (STYLE.md, "GLSL beside C++"). The shaders include it as "shared/relief_uniforms.h" and
// read the members by name (the block has no instance name); the renderer (src/gl/relief_renderer.cpp)
// includes it the same way, fills a strata::shared::ReliefUniforms per draw and uploads it whole to the
// buffer bound at kReliefUniformsBinding.
//
// Layout. std140 aligns a vec3 to 16 bytes (so each vec3 here is followed by one float that fills its
// last 4), stores a mat3 as three 16-byte columns (glm::mat3x4 in C++) and gives each element of a float
// array a 16-byte stride (glm::vec4 in C++, the value in .x). Booleans are ints (0 or 1). The C++ side
// static_asserts every offset and the size, so a member added on one side only does not compile.
//
// Spaces and units: world space as CONVENTIONS §7; tile coordinates = tiling * mesh uv; depth scale S in
// tile widths (CONVENTIONS §2); colours linear RGB unless said otherwise.
#ifdef __cplusplus
#pragma once
#endif
#include "shared/relief_bindings.h"

#ifdef __cplusplus
#include <glm/mat3x4.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>

namespace strata::shared {
using glm::mat4;
using glm::vec3;
using Std140Mat3 = glm::mat3x4;  // three columns of 16 bytes; the fourth row is padding
using Std140Float = glm::vec4;   // one float array element; .x holds the value
struct ReliefUniforms {
#else
#define Std140Mat3 mat3
#define Std140Float float
layout(std140, binding = kReliefUniformsBinding) uniform ReliefUniforms {
#endif
    mat4 uModel;               // object -> world
    mat4 uViewProjection;      // world -> clip
    Std140Mat3 uNormalMatrix;  // inverse transpose of uModel's upper 3x3
    vec3 uEye;                 // world
    float uMirror;             // sign of det(uModel): a mirroring model flips the bitangent
    vec3 uLightPosition;       // world
    float uTiling;             // tiles per unit of mesh uv (tile coordinates = tiling * uv)
    vec3 uLightColor;          // linear RGB
    float uDepthScale;         // S of the render, tile widths (CONVENTIONS §2)
    vec3 uPlainColor;          // linear albedo of a plain surface
    float uNormalScale;        // S_render / S_material: the packed normals are valid at S_material
    int uLinearSteps;          // N, linear search steps at normal incidence
    int uBinarySteps;          // binary search steps
    float uAmbient;
    float uSpecular;
    float uShininess;
    float uAoScale;       // S_render / S_ao, for STRATA_AO_PAPER
    int uEncodeSrgb;      // shaded: 1 writes sRGB-encoded values (draw()), 0 linear (render())
    float uColorTiling;   // colour repeats per tile (a live meta-relief's colour layer's t; else 1)
    int uMaxMipLevels;    // levels of uMaxMip, the top one 1 x 1 (maxmip.glsl)
    float uConeMaxRatio;  // the cone ratio that an encoded 1 stands for (cone.glsl)
    // Live meta-relief (STRATA_META_LIVE; relief_search.glsl, relief.frag.glsl metaShade). Per layer, in
    // the renderer's search order (largest weighted depth range first).
    int uLayerCount;
    int uMetaConsistent;  // 1: normals of the composed depth (NormalMode::Consistent); 0: paper Eq. 1
    int uMetaAo;          // 0 none, 1 multiply, 2 min (the layers' AO), 3 the composed AO map
    int uPadding0;        // the arrays start at a multiple of 16 bytes
    int uPadding1;
    int uPadding2;
    Std140Float uLayerTiling[kMaxLiveLayers];       // t_i
    Std140Float uLayerDepthWeight[kMaxLiveLayers];  // w_d,i / W, W = sum_j w_d,j
    // Bounds of what the layers after layer i can add to Eq. 2: the sums of (w_d,j / W) min d_j and of
    // (w_d,j / W) max d_j over j > i (reliefBelow).
    Std140Float uLayerRestLow[kMaxLiveLayers];
    Std140Float uLayerRestHigh[kMaxLiveLayers];
    Std140Float uLayerNormalWeight[kMaxLiveLayers];  // w_n,i / sum_j w_n,j
    Std140Float uLayerAoScale[kMaxLiveLayers];       // S_i now / S_i baked (meta_relief_ao.h)
    Std140Float uLayerNormalScale[kMaxLiveLayers];   // consistent: the S_L of each layer's normals
#ifdef __cplusplus
};

static_assert(offsetof(ReliefUniforms, uModel) == 0);
static_assert(offsetof(ReliefUniforms, uViewProjection) == 64);
static_assert(offsetof(ReliefUniforms, uNormalMatrix) == 128);
static_assert(sizeof(Std140Mat3) == 48);
static_assert(offsetof(ReliefUniforms, uEye) == 176);
static_assert(offsetof(ReliefUniforms, uMirror) == 188);
static_assert(offsetof(ReliefUniforms, uLightPosition) == 192);
static_assert(offsetof(ReliefUniforms, uTiling) == 204);
static_assert(offsetof(ReliefUniforms, uLightColor) == 208);
static_assert(offsetof(ReliefUniforms, uDepthScale) == 220);
static_assert(offsetof(ReliefUniforms, uPlainColor) == 224);
static_assert(offsetof(ReliefUniforms, uNormalScale) == 236);
static_assert(offsetof(ReliefUniforms, uLinearSteps) == 240);
static_assert(offsetof(ReliefUniforms, uBinarySteps) == 244);
static_assert(offsetof(ReliefUniforms, uAmbient) == 248);
static_assert(offsetof(ReliefUniforms, uSpecular) == 252);
static_assert(offsetof(ReliefUniforms, uShininess) == 256);
static_assert(offsetof(ReliefUniforms, uAoScale) == 260);
static_assert(offsetof(ReliefUniforms, uEncodeSrgb) == 264);
static_assert(offsetof(ReliefUniforms, uColorTiling) == 268);
static_assert(offsetof(ReliefUniforms, uMaxMipLevels) == 272);
static_assert(offsetof(ReliefUniforms, uConeMaxRatio) == 276);
static_assert(offsetof(ReliefUniforms, uLayerCount) == 280);
static_assert(offsetof(ReliefUniforms, uMetaConsistent) == 284);
static_assert(offsetof(ReliefUniforms, uMetaAo) == 288);
static_assert(offsetof(ReliefUniforms, uLayerTiling) == 304);
static_assert(sizeof(Std140Float) == 16);
static_assert(offsetof(ReliefUniforms, uLayerDepthWeight) == 304 + 1 * 16 * kMaxLiveLayers);
static_assert(offsetof(ReliefUniforms, uLayerRestLow) == 304 + 2 * 16 * kMaxLiveLayers);
static_assert(offsetof(ReliefUniforms, uLayerRestHigh) == 304 + 3 * 16 * kMaxLiveLayers);
static_assert(offsetof(ReliefUniforms, uLayerNormalWeight) == 304 + 4 * 16 * kMaxLiveLayers);
static_assert(offsetof(ReliefUniforms, uLayerAoScale) == 304 + 5 * 16 * kMaxLiveLayers);
static_assert(offsetof(ReliefUniforms, uLayerNormalScale) == 304 + 6 * 16 * kMaxLiveLayers);
static_assert(sizeof(ReliefUniforms) == 304 + 7 * 16 * kMaxLiveLayers);
}  // namespace strata::shared
#else
};
#undef Std140Mat3
#undef Std140Float
#endif
