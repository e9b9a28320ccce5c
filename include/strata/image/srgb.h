// The sRGB transfer function (IEC 61966-2-1) between sRGB-encoded and linear values, both in [0, 1]:
//     linear = c / 12.92 for c <= 0.04045, else ((c + 0.055) / 1.055)^2.4;
//     c = 12.92 linear for linear <= 0.0031308, else 1.055 linear^(1 / 2.4) - 0.055.
// Computed in double; inputs are clamped to [0, 1] first (NaN is not: it stays NaN). The GLSL side (the
// relief shader's output encoding) uses the same formula and constants.
#pragma once

#include <algorithm>
#include <cmath>

namespace strata {

inline double srgbToLinear(double c) {
    c = std::clamp(c, 0.0, 1.0);
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

inline double linearToSrgb(double linear) {
    const double x = std::clamp(linear, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

}  // namespace strata
