// The relief search's linear step count, written once in the common subset of GLSL 4.50 and C++
// (shared/prelude.h). C++ includes it as "shared/relief_search.h" and gets
// strata::shared::reliefLinearSteps(); shaders/relief/relief_search.glsl includes it.
//
// Policarpo et al. 2005, Sec. 3: "delta varies from fragment to fragment as function of the angle between
// VD' and the interpolated surface normal; as this angle grows, delta decreases". Strata's form
// (strata::adaptiveLinearSteps, render_settings.h): n = round(N / max(|cos theta|, 1/4)), N the step count at
// normal incidence, rounded half up as floor(x + 0.5). The ray crosses the depth range [0, S] over a length
// S / cos theta, so n proportional to 1 / cos theta keeps the 3-D step length S / N the same at every angle;
// past 75.5 degrees the count stays at 4 N. Evaluated in float here and in double by
// adaptiveLinearSteps; the two agree except where x + 0.5 is within float rounding of an integer
// (tests/gl/test_program.cpp checks them on a sweep of angles).
#ifdef __cplusplus
#pragma once
#endif
#include "prelude.h"
STRATA_SHARED_BEGIN

STRATA_SHARED_FUNCTION int reliefLinearSteps(int linearSteps, float cosTheta) {
    float c = clamp(abs(cosTheta), 0.25f, 1.0f);
    return int(floor(float(linearSteps) / c + 0.5f));
}

STRATA_SHARED_END
