// The relief search (Policarpo, Oliveira, Comba 2005, Sec. 3, 3.1 and the appendix's ray_intersect_rm and
// RM_SHADOWS) and its linear step count, written once in the common subset of GLSL 4.50 and C++
// (shared/prelude.h). C++ includes it as "shared/relief_search.h" and gets
// strata::shared::reliefLinearSteps() and the class strata::shared::ReliefSearch;
// shaders/relief/relief_search.glsl includes it and supplies the fetch, reliefBelow (the packed texture's
// depth, or a live meta-relief's layers).
//
// Conventions (CONVENTIONS §1, §2, §5): tile coordinates (u, v) repeat; d in [0, 1], 0 = the polygon (top),
// 1 = the deepest point. A ray is given by its entry point dp at depth 0 and ds, its (u, v) travel from
// depth 0 to depth 1: the ray's point at depth t is (dp + ds t, -S t).
#ifdef __cplusplus
#pragma once
#endif
#include "prelude.h"
STRATA_SHARED_BEGIN

// Policarpo et al. 2005, Sec. 3: "delta varies from fragment to fragment as function of the angle between
// VD' and the interpolated surface normal; as this angle grows, delta decreases". Strata's form
// (strata::adaptiveLinearSteps, render_settings.h): n = round(N / max(|cos theta|, 1/4)), N the step count at
// normal incidence, rounded half up as floor(x + 0.5). The ray crosses the depth range [0, S] over a length
// S / cos theta, so n proportional to 1 / cos theta keeps the 3-D step length S / N the same at every angle;
// past 75.5 degrees the count stays at 4 N. Evaluated in float here and in double by
// adaptiveLinearSteps; the two agree except where x + 0.5 is within float rounding of an integer
// (tests/gl/test_program.cpp checks them on a sweep of angles).
STRATA_SHARED_FUNCTION int reliefLinearSteps(int linearSteps, float cosTheta) {
    float c = clamp(abs(cosTheta), 0.25f, 1.0f);
    return int(floor(float(linearSteps) / c + 0.5f));
}

STRATA_SHARED_CLASS_BEGIN(ReliefSearch)
// The fetch: whether the ray's point at depth `depth` over uv lies below the relief, depth >= d(uv), or
// depth > d(uv) when `strict`. One call is one read of the height field (or of a live meta-relief's layers).
STRATA_SHARED_FETCH(bool reliefBelow(vec2 uv, float depth, bool strict))

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
// binarySteps = b refines the bracket to 1 / (linearSteps 2^(b-1)): the surface is crossed within that
// window above the result (or above depth 0, when the first linear step is already inside).
float reliefIntersect(vec2 dp, vec2 ds, int linearSteps, int binarySteps) {
    float size = 1.0f / float(linearSteps);  // current size of the search window
    float depth = 0.0f;                      // current depth position
    float bestDepth = 1.0f;                  // best match found (starts with the last position, 1.0)
    for (int i = 0; i < linearSteps - 1; ++i) {
        depth += size;
        if (reliefBelow(dp + ds * depth, depth, false)) {
            bestDepth = depth;
            break;
        }
    }
    depth = bestDepth;
    for (int i = 0; i < binarySteps; ++i) {
        size *= 0.5f;
        if (reliefBelow(dp + ds * depth, depth, false)) {
            bestDepth = depth;
            depth -= 2.0f * size;
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
// The hit of reliefIntersect is the deepest point known to be inside: the surface crossing lies within
// `bracket` (its final search window) above it, so a light ray through it starts inside the solid. The
// search stops at hitDepth - bracket - bias instead (relief_search.glsl's kShadowBias says how large).
// A light at or below the tangent plane (toLight.z <= 0) shadows.
bool reliefLit(vec2 hitUv, float hitDepth, float bracket, vec3 toLight, float depthScale, int linearSteps,
               float bias) {
    if (toLight.z <= 0.0f) return false;
    float end = hitDepth - bracket - bias;
    if (end <= 0.0f) return true;  // the hit is at the top: nothing above it
    // (u, v) travel of the light ray per unit of depth, towards the light (upwards).
    vec2 up = vec2(toLight.x, toLight.y) * depthScale / toLight.z;
    vec2 entry = hitUv + up * hitDepth;  // where the light ray crosses depth 0
    float size = end / float(linearSteps);
    for (int i = 1; i <= linearSteps; ++i) {
        float depth = size * float(i);
        // Strictly inside: a light ray that only touches the surface (e.g. along a flat top) is not blocked.
        if (reliefBelow(entry - up * depth, depth, true)) return false;
    }
    return true;
}
STRATA_SHARED_CLASS_END

STRATA_SHARED_END
