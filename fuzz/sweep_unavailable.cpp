// The fuzz build's stand-in for src/occlusion/sweep_horizons.cpp, whose SIMD kernels use GCC vector built-ins
// (__builtin_shuffle) that clang 14 does not have. No reader computes AO, so the fuzzers never call these; if
// one ever did, it gets an Error(Unsupported) instead of a link failure. Only STRATA_FUZZ builds use this
// file.
#include "../src/occlusion/horizon_search.h"
#include "strata/core/error.h"

namespace strata::detail {

namespace {
[[noreturn]] void unavailable() {
    throw Error(ErrorKind::Unsupported, "the AO sweep is not built in the fuzz build (STRATA_FUZZ)");
}
}  // namespace

bool sweepKernelRuns(SweepKernel /*kernel*/) {
    return false;
}
const char* toString(SweepKernel /*kernel*/) {
    return "unavailable";
}
HorizonMap sweepHorizons(const Image& /*depth*/, const AoParams& /*params*/,
                         const SweepOptions& /*options*/) {
    unavailable();
}
Image sweepAo(const Image& /*depth*/, const AoParams& /*params*/, const SweepOptions& /*options*/) {
    unavailable();
}

}  // namespace strata::detail
