// Dual-depth relief (Policarpo, Oliveira, Comba 2005, Section 4): the packed texture holds the front and the
// back surface of an object, B = front d, A = back d (strata/relief/dual_depth.h), and a point of the ray at
// depth t is inside the object when front <= t <= back. Texels where the sampling line missed the object
// hold front = 1 > back = 0, never inside, and so is everything outside the tile [0, 1]^2 (an impostor
// stands for one object: it does not repeat). The search is the paper's, with that inside test: linear steps
// from depth 0 to 1, then binary refinement between the last outside and the first inside point.
#include "shared/relief_search.h"

// An impostor does not repeat: outside its tile [0, 1]^2 there is nothing.
bool dualInside(vec2 uv, float t) {
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return false;
    vec4 texel = reliefSample(uv);
    return t >= texel.b && t <= texel.a;
}

// The depth of the first inside point along the ray (dp, ds) (relief_search.glsl's form), or -1 when the
// ray passes the object. `bracket` returns the final search window.
float dualDepthIntersect(vec2 dp, vec2 ds, int linearSteps, int binarySteps, out float bracket) {
    float size = 1.0 / float(linearSteps);
    float outside = 0.0;  // the last point known outside
    float inside = -1.0;  // the first point found inside
    for (int i = 1; i <= linearSteps; ++i) {
        float t = size * float(i);
        if (dualInside(dp + ds * t, t)) {
            inside = t;
            break;
        }
        outside = t;
    }
    bracket = size;
    if (inside < 0.0) return -1.0;
    for (int i = 0; i < binarySteps; ++i) {
        float middle = 0.5 * (outside + inside);
        if (dualInside(dp + ds * middle, middle)) {
            inside = middle;
        } else {
            outside = middle;
        }
    }
    bracket = inside - outside;
    return inside;
}

// Self-shadowing by the object: is the point at (hitUv, hitDepth) lit by a light in tile-space direction
// toLight? The light ray is searched from the point towards the light, up to depth 0, for any inside point
// (stepping away from the hit by the bias first: the hit lies within `bracket` of the surface).
bool dualLit(vec2 hitUv, float hitDepth, float bracket, vec3 toLight, float depthScale, int linearSteps) {
    if (toLight.z <= 0.0) return false;
    float start = hitDepth - bracket - kShadowBias;
    if (start <= 0.0) return true;
    vec2 up = toLight.xy * depthScale / toLight.z;  // (u, v) travel per unit of depth, towards the light
    float size = start / float(linearSteps);
    for (int i = 0; i < linearSteps; ++i) {
        float t = start - size * float(i);
        if (dualInside(hitUv + up * (hitDepth - t), t)) return false;
    }
    return true;
}
