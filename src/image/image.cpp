#include "strata/image/image.h"

#include "strata/core/check.h"
#include "strata/core/memory_budget.h"

#include <sys/mman.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>

namespace strata {

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kHugeThreshold = std::size_t{4} << 20;

void* allocateUntracked(std::size_t bytes) {
    if (bytes < kHugeThreshold) return ::operator new(bytes);
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* pointer = std::aligned_alloc(kHugePage, rounded);
    if (!pointer) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
    ::madvise(pointer, rounded, MADV_HUGEPAGE);  // advice only: failure just means 4 KiB pages
#endif
    return pointer;
}

}  // namespace

// Every pixel buffer counts against the memory budget for as long as it lives, copies included. The
// constructor has already checked the same request with a message naming the image's dimensions.
void* Image::allocatePixels(std::size_t bytes) {
    // reserveOrThrow throws with what is held; it returns only when another thread released images in
    // between, and the acquisition is tried again.
    while (!tryAcquireTracked(bytes)) reserveOrThrow(bytes, "an image of " + formatBytes(bytes));
    try {
        return allocateUntracked(bytes);
    } catch (...) {
        releaseTracked(bytes);
        throw;
    }
}

void Image::freePixels(void* pointer, std::size_t bytes) noexcept {
    if (bytes < kHugeThreshold) {
        ::operator delete(pointer);
    } else {
        std::free(pointer);
    }
    releaseTracked(bytes);
}

Image::Image(int width, int height, int channels, UninitializedTag)
    : mWidth(width), mHeight(height), mChannels(channels) {
    STRATA_CHECK_GE(width, 1);
    STRATA_CHECK_GE(height, 1);
    STRATA_CHECK_LE(width, kMaxDimension);
    STRATA_CHECK_LE(height, kMaxDimension);
    STRATA_CHECK_GE(channels, 1);
    STRATA_CHECK_LE(channels, 4);
    checkAllocation(width, height, channels, sizeof(float),
                    "a " + std::to_string(width) + " x " + std::to_string(height) + " image of " +
                        std::to_string(channels) + (channels == 1 ? " channel" : " channels"));
    mPixels.resize(static_cast<std::size_t>(width) * height * channels);
}

Image::Image(int width, int height, int channels, float fill)
    : Image(width, height, channels, UninitializedTag{}) {
    std::fill(mPixels.begin(), mPixels.end(), fill);
}

Image Image::uninitialized(int width, int height, int channels) {
    return Image(width, height, channels, UninitializedTag{});
}

void Image::sampleTexel(double x, double y, float* out) const {
    const double fx = std::floor(x);
    const double fy = std::floor(y);
    // Weights in float: at a texel centre the fractional parts are exactly 0 and the result is the
    // texel itself, bit for bit.
    const auto tx = static_cast<float>(x - fx);
    const auto ty = static_cast<float>(y - fy);
    const int x0 = wrap(static_cast<int>(std::fmod(fx, static_cast<double>(mWidth))), mWidth);
    const int y0 = wrap(static_cast<int>(std::fmod(fy, static_cast<double>(mHeight))), mHeight);
    const int x1 = x0 + 1 == mWidth ? 0 : x0 + 1;
    const int y1 = y0 + 1 == mHeight ? 0 : y0 + 1;
    const float* p00 = &mPixels[index(x0, y0)];
    const float* p10 = &mPixels[index(x1, y0)];
    const float* p01 = &mPixels[index(x0, y1)];
    const float* p11 = &mPixels[index(x1, y1)];
    for (int c = 0; c < mChannels; ++c) {
        const float top = p00[c] + tx * (p10[c] - p00[c]);
        const float bottom = p01[c] + tx * (p11[c] - p01[c]);
        out[c] = top + ty * (bottom - top);
    }
}

void Image::sample(double u, double v, float* out) const {
    sampleTexel(u * mWidth - 0.5, (1.0 - v) * mHeight - 0.5, out);
}

float Image::sample(double u, double v, int c) const {
    float values[4];
    sample(u, v, values);
    return values[c];
}

}  // namespace strata
