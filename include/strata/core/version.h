#pragma once

namespace strata {

// The tool version recorded in every sidecar (CONVENTIONS §6).
inline constexpr const char* kVersion = "0.1.0";

}  // namespace strata
