// Internal: the horizon searches behind computeHorizons (strata/occlusion/ambient_occlusion.h).
#pragma once

#include "strata/occlusion/ambient_occlusion.h"

namespace strata::detail {

// Marches each direction at params.marchStep (AoMethod::Brute and AoMethod::Paper).
HorizonMap marchHorizons(const Image& depth, const AoParams& params);
// The sweep's SIMD kernels: 4 lanes with the baseline ISA (SSE2 on x86-64, NEON on AArch64), 8 with
// AVX2, 16 with AVX-512 (F, VL, BW, DQ). They compute the same numbers bit for bit. Auto, the default,
// is the widest that this CPU runs; the others are there for tests and benchmarks.
enum class SweepKernel { Auto, Portable, Avx2, Avx512 };
// Whether this CPU (and build) runs `kernel`; Auto and Portable always do.
bool sweepKernelRuns(SweepKernel kernel);
const char* toString(SweepKernel kernel);

struct SweepOptions {
    SweepKernel kernel = SweepKernel::Auto;
    // Every direction through hulls, also those whose windows are short enough that reading them sample
    // by sample is faster (the default there). For tests: both give the same numbers but for ties.
    bool hullsOnly = false;
};

// The line sweep with a convex-hull stack (AoMethod::Sweep). Throws Error when this CPU cannot run
// options.kernel.
HorizonMap sweepHorizons(const Image& depth, const AoParams& params, const SweepOptions& options = {});
// The sweep's cosine-weighted AO, accumulated direction by direction without storing the horizons.
Image sweepAo(const Image& depth, const AoParams& params, const SweepOptions& options = {});

}  // namespace strata::detail
