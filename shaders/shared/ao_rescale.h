// Dynamic depth rescaling of texture-space ambient occlusion, written once in the common subset of
// GLSL 4.50 and C++ (shared/prelude.h). C++ includes it as "shared/ao_rescale.h" and gets
// strata::shared::aoRescalePaper(); a shader pastes it after its `#version 450` line.
//
// AO follows CONVENTIONS §4: in [0, 1], 1 = fully open. s is the depth scale factor applied at render
// time relative to the depth scale S the AO map was baked at (s = S_render / S_baked, s >= 0).
//
// aoRescalePaper: Limberger, Schetinger, Oliveira 2015, Section IV-A, Eq. 4-6. The paper models the
// visible solid angle as a disc of radius r on the unit hemisphere:
//     r^2 = AO                      (Eq. 4, r = sqrt(AO))
//     H^2 = 1 - r^2                 (the height of the cone's rim above the plane)
//     R'^2 = (s H)^2 + r^2          (Eq. 5: depth scaling stretches H, not r)
//     AO_new = AO / R'^2            (Eq. 6)
// Squares only, so no sqrt is needed. AO is clamped to [0, 1] first; s = 0 with AO = 0 returns 0.
// It is an approximation: docs/occlusion.md measures it against the exact rescale below.
//
// aoDirectionExact: one direction's exact contribution at scale s from its baked horizon tangent
// tan(h) >= 0 (tan scales linearly with depth): cos^2(h_s) = 1 / (1 + s^2 tan^2(h)). The cosine-weighted
// AO at any s is the mean of this over the directions (strata::HorizonMap::aoAt).
#ifdef __cplusplus
#pragma once
#endif
#include "prelude.h"
STRATA_SHARED_BEGIN

STRATA_SHARED_FUNCTION float aoRescalePaper(float ao, float s) {
    float r2 = clamp(ao, 0.0f, 1.0f);  // Eq. 4: r^2 = AO
    float h2 = 1.0f - r2;              // H^2 = 1 - r^2
    // Eq. 5, (s H)^2 + r^2, written as 1 + (s^2 - 1) H^2 (equal, as H^2 + r^2 = 1) so that s = 1
    // gives R'^2 = 1 exactly and the AO comes back unchanged, bit for bit.
    float rPrime2 = 1.0f + (s * s - 1.0f) * h2;
    return r2 / max(rPrime2, 1.0e-30f);  // Eq. 6 (the guard matters only for AO = s = 0)
}

STRATA_SHARED_FUNCTION float aoDirectionExact(float tanHorizon, float s) {
    float t = s * tanHorizon;
    return 1.0f / (1.0f + t * t);
}

STRATA_SHARED_END
