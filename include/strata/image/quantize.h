// Quantising [0, 1] values to the unsigned-normalised integers that 8- and 16-bit PNG files and GL's
// R8 / R16 / RGBA16 textures store (CONVENTIONS §5): q = round(clamp(v, 0, 1) * (2^n - 1)), half rounded
// up. The product is taken in double, where it is exact for every float v, so the rounding is the correct
// one (in float, v * 65535 is itself rounded first and can cross a half). NaN and values <= 0 give 0.
#pragma once

#include <cmath>
#include <cstdint>

namespace strata {

inline std::uint16_t toUnorm16(double v) {
    if (!(v > 0.0)) return 0;
    if (v >= 1.0) return 65535;
    return static_cast<std::uint16_t>(std::floor(v * 65535.0 + 0.5));
}

inline std::uint8_t toUnorm8(double v) {
    if (!(v > 0.0)) return 0;
    if (v >= 1.0) return 255;
    return static_cast<std::uint8_t>(std::floor(v * 255.0 + 0.5));
}

// v as a 16-bit texture or PNG holds it: toUnorm16(v) / 65535.
inline float quantizeUnorm16(double v) {
    return static_cast<float>(toUnorm16(v)) / 65535.0f;
}

}  // namespace strata
