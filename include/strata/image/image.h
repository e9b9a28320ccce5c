// strata::Image: a float image of 1 to 4 channels that follows CONVENTIONS §1.
//
// Storage is row-major and top row first, exactly as in an image file: row 0 is the edge v = 1,
// column 0 is u = 0. Texel (column i, row j) of a W x H image has its centre at
//     u = (i + 0.5) / W,   v = 1 - (j + 0.5) / H.
// Between texel centres an image is reconstructed bilinearly with wrap-around in both directions
// (every Strata texture tiles toroidally); sample() implements exactly that reconstruction, and the
// exact references (AO, ray tracing) intersect this bilinear surface.
//
// Values are whatever the map holds: depth in [0, 1], tangent-space normal components in [-1, 1],
// sRGB-encoded colour in [0, 1], AO in [0, 1]. The type does not clamp.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <new>
#include <span>
#include <utility>
#include <vector>

namespace strata {

class Image {
public:
    // The largest width or height Strata accepts anywhere (readers refuse larger images before
    // allocating anything). 16384^2 x 4 channels x 4 bytes = 4 GiB.
    static constexpr int kMaxDimension = 16384;

    Image() = default;
    // A width x height image of `channels` channels (1..4), every value set to `fill`.
    // Dimensions must be in [1, kMaxDimension] (checked: a violation is a bug in the caller;
    // readers validate file dimensions and throw strata::Error first).
    Image(int width, int height, int channels, float fill = 0.0f);

    // An image whose values are unspecified, for code that overwrites every value anyway (in
    // parallel): it skips the serial fill, so the memory is first touched where it is written.
    static Image uninitialized(int width, int height, int channels);

    int width() const { return mWidth; }
    int height() const { return mHeight; }
    int channels() const { return mChannels; }
    bool empty() const { return mPixels.empty(); }
    std::size_t texelCount() const { return static_cast<std::size_t>(mWidth) * mHeight; }

    // Texel access by column x in [0, W) and row y in [0, H) (row 0 = top = v near 1).
    float& at(int x, int y, int c = 0) { return mPixels[index(x, y) + c]; }
    float at(int x, int y, int c = 0) const { return mPixels[index(x, y) + c]; }
    // Texel access with wrap-around: any integer x, y.
    float atWrapped(int x, int y, int c = 0) const { return at(wrap(x, mWidth), wrap(y, mHeight), c); }

    float* row(int y) { return mPixels.data() + index(0, y); }
    const float* row(int y) const { return mPixels.data() + index(0, y); }
    std::span<float> pixels() { return mPixels; }
    std::span<const float> pixels() const { return mPixels; }

    // Bilinear, wrap-around sample of channel c at texture coordinates (u, v); any real u, v
    // (the texture repeats). At a texel centre it returns that texel's value exactly.
    float sample(double u, double v, int c = 0) const;
    // All channels at once into out[0 .. channels()-1].
    void sample(double u, double v, float* out) const;

    // Bilinear, wrap-around sample in continuous texel coordinates: x = u * W - 0.5, y = (1 - v) * H - 0.5,
    // so that integer (x, y) is a texel centre. Compositing uses this form to stay exact at centres.
    void sampleTexel(double x, double y, float* out) const;

    // The texture coordinates of texel (x, y)'s centre.
    double texelU(int x) const { return (x + 0.5) / mWidth; }
    double texelV(int y) const { return 1.0 - (y + 0.5) / mHeight; }

    bool operator==(const Image& other) const = default;

    static int wrap(int i, int n) {
        const int r = i % n;
        return r < 0 ? r + n : r;
    }

private:
    // Leaves new elements default-initialised (for float: unset) unless a value is given, so that
    // uninitialized() costs no pass over the memory. Large buffers are placed on huge pages where
    // the OS offers them (see allocatePixels).
    template <typename T>
    struct DefaultInitAllocator : std::allocator<T> {
        template <typename U>
        struct rebind {
            using other = DefaultInitAllocator<U>;
        };
        using std::allocator<T>::allocator;
        T* allocate(std::size_t n) { return static_cast<T*>(allocatePixels(n * sizeof(T))); }
        void deallocate(T* p, std::size_t n) noexcept { freePixels(p, n * sizeof(T)); }
        template <typename U>
        void construct(U* p) noexcept {
            ::new (static_cast<void*>(p)) U;
        }
        template <typename U, typename... Args>
        void construct(U* p, Args&&... args) {
            ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
        }
    };

    // Pixel memory. Buffers of 4 MiB or more are 2 MiB-aligned and marked MADV_HUGEPAGE on Linux:
    // a 2048^2 composition writes 112 MB of fresh memory, and with 4 KiB pages the page faults alone
    // cost more than the composition (docs/composition.md).
    static void* allocatePixels(std::size_t bytes);
    static void freePixels(void* pointer, std::size_t bytes) noexcept;

    struct UninitializedTag {};
    Image(int width, int height, int channels, UninitializedTag);

    std::size_t index(int x, int y) const { return (static_cast<std::size_t>(y) * mWidth + x) * mChannels; }

    int mWidth = 0;
    int mHeight = 0;
    int mChannels = 0;
    std::vector<float, DefaultInitAllocator<float>> mPixels;
};

}  // namespace strata
