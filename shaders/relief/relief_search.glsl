// Ray / height-field intersection in texture space, written once and included by every program that
// needs it (Policarpo, Oliveira, Comba 2005, Sec. 3 and the appendix's ray_intersect_rm).
//
// Conventions (CONVENTIONS §1, §2, §5): tile coordinates (u, v) repeat (GL_REPEAT); the packed texture's
// alpha is the depth d in [0, 1], 0 = the polygon (top), 1 = the deepest point; the relief point of (u, v)
// is (u, v, -S d) in tile units. A ray is given by its entry point dp at depth 0 and ds, its (u, v) travel
// from depth 0 to depth 1: the ray's point at depth t is (dp + ds t, -S t).
//
// Sampling. Implicit derivatives are undefined in non-uniform control flow (the loops below), so the
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
// Live meta-relief (Limberger et al. 2015, Sec. III-A): up to kMaxLayers layers, each its own packed texture
// (CONVENTIONS §5 layout) at its own resolution and tiling t_i, combined per fragment. The depth the searches
// see is paper Eq. 2, D(uv) = sum_i (w_d,i / W) d_i(t_i uv), W = sum_j w_d,j; the weights arrive normalised.
// Nothing is baked, so fractional tilings have no seam and a weight change needs no re-bake.
const int kMaxLayers = kMaxLiveLayers;  // shared/relief_bindings.h
layout(binding = kLayerUnit0) uniform sampler2D uLayers[kMaxLayers];
// The renderer binds the layers in the searches' order (largest weighted depth range first; Eq. 1 and 2
// do not depend on the order). uLayerCount, uLayerTiling, uLayerDepthWeight (w_d,i / W) and, for each layer
// i, the bounds of what the layers after it can add to Eq. 2, uLayerRestLow and uLayerRestHigh (the sums of
// (w_d,j / W) min d_j and (w_d,j / W) max d_j over j > i, reliefBelow), are in the per-draw block.

// Each layer's mip level for the fragment, set once in uniform control flow (layerLods): the searches read
// every layer at every step, and an explicit level spares each fetch the derivative-to-level computation.
float gLayerLod[kMaxLayers];

// GL's isotropic level of detail for layer i: the layer repeats t_i times per tile, so its footprint is
// t_i times larger.
void layerLods() {
    for (int i = 0; i < kMaxLayers; ++i) {
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
    for (int i = 0; i < kMaxLayers; ++i) {
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
    for (int i = 0; i < kMaxLayers; ++i) {
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

// Appendix, ray_intersect_rm: the depth t in [0, 1] of the first intersection of the ray (dp, ds) with
// the height field. `linearSteps` (>= 1) is the loop bound of the linear search (the appendix's constant
// linear_search_steps, here reliefLinearSteps(N, cos theta) per fragment), `binarySteps` that of the
// binary search.
//
// Linear search (Sec. 3, Fig. 9): step from depth 0 towards 1 in increments of 1 / linearSteps until the
// first point inside the relief (t >= d). The appendix starts with best_depth = 1 ("last position 1.0")
// and tests best_depth > 0.996 for "not found yet"; a flag does the same without limiting the step count
// to 250. It also keeps fetching after the hit so that the fetches can run in parallel; here the loop
// exits instead (cheaper on current GPUs and on llvmpipe, same result).
//
// No hit in the linear search: best depth stays 1, the last position, which is never above the relief
// (d <= 1 everywhere), so the bracket [1 - 1/n, 1] always holds a crossing and the binary search refines it.
// A ray that enters the top face therefore always hits (the exact tracer agrees: between depth 0, never
// inside, and depth 1, never outside, the bilinear surface is crossed); a "miss" is only a fragment whose
// ray does not go into the surface at all (s.z <= 0, see relief.frag.glsl).
//
// Binary search (Sec. 3, Fig. 7): halve the window around the first inside point, keeping the deepest
// point known to be inside. The first iteration re-tests that point, exactly as in the appendix, so
// binarySteps = b refines the bracket to 1 / (linearSteps 2^(b-1)).
float reliefIntersect(vec2 dp, vec2 ds, int linearSteps, int binarySteps) {
    float size = 1.0 / float(linearSteps);  // current size of the search window
    float depth = 0.0;                      // current depth position
    float bestDepth = 1.0;                  // best match found (starts with the last position, 1.0)
    for (int i = 0; i < linearSteps - 1; ++i) {
        depth += size;
        if (reliefBelow(dp + ds * depth, depth, false)) {
            bestDepth = depth;
            break;
        }
    }
    depth = bestDepth;
    for (int i = 0; i < binarySteps; ++i) {
        size *= 0.5;
        if (reliefBelow(dp + ds * depth, depth, false)) {
            bestDepth = depth;
            depth -= 2.0 * size;
        }
        depth += size;
    }
    return bestDepth;
}

// Self-shadowing (Sec. 3.1, Fig. 10; appendix, RM_SHADOWS): is the relief point at (hitUv, hitDepth) lit by
// a light in direction `toLight` (tangent space, tile units, z out of the surface; need not be unit) at
// depth scale `depthScale` (S, tile widths)? The light ray through the hit enters the top face at depth 0;
// it is searched linearly from there down to the hit ("there is no need to find the actual intersection
// point, but simply decide whether such an intersection exists"), with `linearSteps` steps.
//
// Bias. The hit of reliefIntersect is the deepest point known to be inside: the surface crossing lies
// within `bracket` (its final search window, 1 / (n 2^(b-1))) above it, so a light ray through it starts
// inside the solid. The appendix searches the whole depth range and calls the point lit when the light
// ray's first hit is deeper than d - 0.05; here the light-ray search stops at hitDepth - bracket -
// kShadowBias instead: 0.002 of the depth range (2e-4 tile widths at S = 0.1) absorbs the bilinear
// filter's sub-texel rounding on slopes facing the light without lighting visibly occluded points.
// A light at or below the tangent plane (toLight.z <= 0) shadows.
// The shaded output searches the mip-mapped height field (Sec. 5), whose filtered levels move the surface by
// more than the base level's rounding: there the bias is 0.02 of the depth range (the appendix uses 0.05),
// which removes the isolated dark texels ("shadow acne") that 0.002 left on the teapot.
#ifdef STRATA_OUTPUT_SHADED
const float kShadowBias = 0.02;
#else
const float kShadowBias = 0.002;
#endif

bool reliefLit(vec2 hitUv, float hitDepth, float bracket, vec3 toLight, float depthScale, int linearSteps) {
    if (toLight.z <= 0.0) return false;
    float end = hitDepth - bracket - kShadowBias;
    if (end <= 0.0) return true;  // the hit is at the top: nothing above it
    // (u, v) travel of the light ray per unit of depth, towards the light (upwards).
    vec2 up = toLight.xy * depthScale / toLight.z;
    vec2 entry = hitUv + up * hitDepth;  // where the light ray crosses depth 0
    float size = end / float(linearSteps);
    for (int i = 1; i <= linearSteps; ++i) {
        float depth = size * float(i);
        // Strictly inside: a light ray that only touches the surface (e.g. along a flat top) is not blocked.
        if (reliefBelow(entry - up * depth, depth, true)) return false;
    }
    return true;
}
