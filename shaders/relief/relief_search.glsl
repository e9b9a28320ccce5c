// Ray / height-field intersection in texture space, included by every program that needs it (Policarpo,
// Oliveira, Comba 2005, Sec. 3 and the appendix's ray_intersect_rm): the height field's fetch, reliefBelow,
// for the search loops of shaders/shared/relief_search.h (reliefIntersect, reliefLit), and the shadow bias.
//
// Conventions (CONVENTIONS §1, §2, §5): tile coordinates (u, v) repeat (GL_REPEAT); the packed texture's
// alpha is the depth d in [0, 1], 0 = the polygon (top), 1 = the deepest point; the relief point of (u, v)
// is (u, v, -S d) in tile units. A ray is given by its entry point dp at depth 0 and ds, its (u, v) travel
// from depth 0 to depth 1: the ray's point at depth t is (dp + ds t, -S t).
//
// Sampling. Implicit derivatives are undefined in non-uniform control flow (the search loops), so the
// height field is read with explicit ones:
//   - shaded output: textureGrad with the derivatives of the fragment's own tile coordinates (set once in
//     main(), in uniform control flow), so the search sees the mip-mapped, anisotropically filtered height
//     field as in the paper (Sec. 5: "texture minification causes the resampling of the height-field surface
//     to be done on a filtered version of the depth map");
//   - debug outputs (uv, shadow, depth): textureLod(..., 0), the base level's bilinear height field that
//     CONVENTIONS §1 defines and the exact CPU tracer intersects.
#include "shared/relief_search.h"
#include "shared/relief_uniforms.h"

layout(binding = kReliefUnit) uniform sampler2D uRelief;  // packed relief texture, CONVENTIONS §5

vec2 gTileDx = vec2(0.0);  // derivatives of the fragment's tile coordinates (shaded output only)
vec2 gTileDy = vec2(0.0);

vec4 reliefSample(vec2 uv) {
#ifdef STRATA_OUTPUT_SHADED
    return textureGrad(uRelief, uv, gTileDx, gTileDy);
#else
    return textureLod(uRelief, uv, 0.0);
#endif
}

#ifdef STRATA_META_LIVE
// Live meta-relief (Limberger et al. 2015, Sec. III-A): up to kMaxLiveLayers layers, each its own packed texture
// (CONVENTIONS §5 layout) at its own resolution and tiling t_i, combined per fragment. The depth the searches
// see is paper Eq. 2, D(uv) = sum_i (w_d,i / W) d_i(t_i uv), W = sum_j w_d,j; the weights arrive normalised.
// Nothing is baked, so fractional tilings have no seam and a weight change needs no re-bake.
layout(binding = kLayerUnit0) uniform sampler2D uLayers[kMaxLiveLayers];
// The renderer binds the layers in the searches' order (largest weighted depth range first; Eq. 1 and 2
// do not depend on the order). uLayerCount, uLayerTiling, uLayerDepthWeight (w_d,i / W) and, for each layer
// i, the bounds of what the layers after it can add to Eq. 2, uLayerRestLow and uLayerRestHigh (the sums of
// (w_d,j / W) min d_j and (w_d,j / W) max d_j over j > i, reliefBelow), are in the per-draw block.

// Each layer's mip level for the fragment, set once in uniform control flow (layerLods): the searches read
// every layer at every step, and an explicit level spares each fetch the derivative-to-level computation.
float gLayerLod[kMaxLiveLayers];

// GL's isotropic level of detail for layer i: the layer repeats t_i times per tile, so its footprint is
// t_i times larger.
void layerLods() {
    for (int i = 0; i < kMaxLiveLayers; ++i) {
        if (i >= uLayerCount) break;
        vec2 size = vec2(textureSize(uLayers[i], 0)) * uLayerTiling[i];
        float footprint = max(length(gTileDx * size), length(gTileDy * size));
        gLayerLod[i] = log2(max(footprint, 1e-8));
    }
}

// Layer i at tile coordinates uv.
vec4 layerSample(int i, vec2 uv) {
    float t = uLayerTiling[i];
#ifdef STRATA_OUTPUT_SHADED
    return textureLod(uLayers[i], uv * t, gLayerLod[i]);
#else
    return textureLod(uLayers[i], uv * t, 0.0);
#endif
}
#endif

// The depth d at tile coordinates uv: the packed texture's alpha, or the live layers' Eq. 2.
float reliefDepth(vec2 uv) {
#ifdef STRATA_META_LIVE
    float depth = 0.0;
    for (int i = 0; i < kMaxLiveLayers; ++i) {
        if (i >= uLayerCount) break;
        if (uLayerDepthWeight[i] > 0.0) depth += uLayerDepthWeight[i] * layerSample(i, uv).a;
    }
    return depth;
#else
    return reliefSample(uv).a;
#endif
}

// Whether the ray's point at depth `depth` over uv lies below the relief: depth >= d(uv), or depth > d(uv)
// when `strict`. The searches ask only this, so a live meta-relief stops reading layers once the answer is
// certain: after the layers read so far (partial sum P of Eq. 2) the rest adds between uLayerRestLow and
// uLayerRestHigh (every mip level of a layer stays within its map's range), so depth < P + low means above
// and depth > P + high below. Most search steps are far above the surface and read only the first layer;
// the answer is the one the full sum gives (up to the float rounding of the sum's order).
bool reliefBelow(vec2 uv, float depth, bool strict) {
#ifdef STRATA_META_LIVE
    float partial = 0.0;
    for (int i = 0; i < kMaxLiveLayers; ++i) {
        if (i >= uLayerCount) break;
        if (uLayerDepthWeight[i] > 0.0) partial += uLayerDepthWeight[i] * layerSample(i, uv).a;
        if (depth < partial + uLayerRestLow[i]) return false;
        if (depth > partial + uLayerRestHigh[i]) return true;
    }
    return strict ? depth > partial : depth >= partial;
#else
    float d = reliefSample(uv).a;
    return strict ? depth > d : depth >= d;
#endif
}

// reliefIntersect (the appendix's ray_intersect_rm) and the light-ray search of reliefLit (RM_SHADOWS) are
// shaders/shared/relief_search.h, shared with the C++ that counts their fetches
// (strata/trace/shader_loops.h); they read the height field through reliefBelow above.
//
// Shadow bias. The hit of reliefIntersect is the deepest point known to be inside: the surface crossing lies
// within `bracket` (its final search window, 1 / (n 2^(b-1))) above it, so a light ray through it starts
// inside the solid. The appendix searches the whole depth range and calls the point lit when the light
// ray's first hit is deeper than d - 0.05; here the light-ray search stops at hitDepth - bracket -
// kShadowBias instead: 0.002 of the depth range (2e-4 tile widths at S = 0.1) absorbs the bilinear
// filter's sub-texel rounding on slopes facing the light without lighting visibly occluded points.
// The shaded output searches the mip-mapped height field (Sec. 5), whose filtered levels move the surface by
// more than the base level's rounding: there the bias is 0.02 of the depth range (the appendix uses 0.05),
// which removes the isolated dark texels ("shadow acne") that 0.002 left on the teapot.
#ifdef STRATA_OUTPUT_SHADED
const float kShadowBias = 0.02;
#else
const float kShadowBias = 0.002;
#endif

// Self-shadowing with this output's bias (shared/relief_search.h).
bool reliefLit(vec2 hitUv, float hitDepth, float bracket, vec3 toLight, float depthScale, int linearSteps) {
    return reliefLit(hitUv, hitDepth, bracket, toLight, depthScale, linearSteps, kShadowBias);
}
