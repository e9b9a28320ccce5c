// Operations on strata::Image. All of them treat images as tileable (wrap-around), per CONVENTIONS §1.
#pragma once

#include "strata/image/image.h"

#include <vector>

namespace strata {

// Resamples to width x height. Each axis is handled separately: where it grows, values are the
// bilinear wrap-around reconstruction at the new texel centres; where it shrinks, each new texel is
// the exact area average (box filter) of the old texels it covers, wrap-aware, so the mean of the
// image is preserved. Same size returns a copy.
Image resample(const Image& image, int width, int height);

// A mip pyramid: level 0 is the image, each next level halves each dimension (rounding down, at
// least 1) with the area-correct minification of resample(), down to 1 x 1.
std::vector<Image> buildMipPyramid(const Image& image);

// Rec. 709 luminance of the first three channels (0.2126 R + 0.7152 G + 0.0722 B) of an RGB(A)
// image, as a 1-channel image; a 1- or 2-channel image returns its first channel.
Image luminance(const Image& image);

// A 3-channel copy: gray (and gray+alpha) is replicated, alpha is dropped.
Image toRgb(const Image& image);

// One channel of an image, as a 1-channel image.
Image extractChannel(const Image& image, int channel);

// Separable Gaussian blur with wrap-around, standard deviation `sigma` in texels (sigma <= 0 returns
// a copy). The kernel is truncated at 3 sigma and renormalised.
Image gaussianBlur(const Image& image, double sigma);

// Minimum and maximum over all values of channel c.
struct ValueRange {
    float min;
    float max;
};
ValueRange valueRange(const Image& image, int channel = 0);

// Linearly maps channel 0 of a 1-channel image to [0, 1]; a constant image becomes all `flatValue`.
Image normalizeToUnit(const Image& image, float flatValue = 0.0f);

}  // namespace strata
