// Internal: the horizon searches behind computeHorizons (strata/occlusion/ambient_occlusion.h).
#pragma once

#include "strata/occlusion/ambient_occlusion.h"

namespace strata::detail {

// Marches each direction at params.marchStep (AoMethod::Brute and AoMethod::Paper).
HorizonMap marchHorizons(const Image& depth, const AoParams& params);
// The line sweep with a convex-hull stack (AoMethod::Sweep).
HorizonMap sweepHorizons(const Image& depth, const AoParams& params);
// The sweep's cosine-weighted AO, accumulated direction by direction without storing the horizons.
Image sweepAo(const Image& depth, const AoParams& params);

}  // namespace strata::detail
