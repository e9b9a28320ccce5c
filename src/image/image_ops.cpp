#include "strata/image/image_ops.h"

#include "strata/core/check.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace strata {

namespace {

// One axis of a resampling: new texel k takes sum_j weight_j * old[index_j].
struct Tap {
    int index;
    float weight;
};
using AxisFilter = std::vector<std::vector<Tap>>;

// Magnification: bilinear between the two old texel centres around the new centre (wrap-around).
AxisFilter bilinearFilter(int oldSize, int newSize) {
    AxisFilter filter(newSize);
    for (int k = 0; k < newSize; ++k) {
        const double x = (k + 0.5) * oldSize / newSize - 0.5;
        const double fx = std::floor(x);
        const auto t = static_cast<float>(x - fx);
        const int i0 = Image::wrap(static_cast<int>(fx), oldSize);
        filter[k] = {{i0, 1.0f - t}, {Image::wrap(i0 + 1, oldSize), t}};
    }
    return filter;
}

// Minification: the exact overlap of the new texel's footprint [k, k+1) * old/new with each old texel.
AxisFilter boxFilter(int oldSize, int newSize) {
    AxisFilter filter(newSize);
    const double ratio = static_cast<double>(oldSize) / newSize;
    for (int k = 0; k < newSize; ++k) {
        const double begin = k * ratio;
        const double end = (k + 1) * ratio;
        for (int j = static_cast<int>(std::floor(begin)); j < end; ++j) {
            const double overlap = std::min(end, j + 1.0) - std::max(begin, static_cast<double>(j));
            if (overlap > 0.0)
                filter[k].push_back({Image::wrap(j, oldSize), static_cast<float>(overlap / ratio)});
        }
    }
    return filter;
}

AxisFilter axisFilter(int oldSize, int newSize) {
    if (newSize == oldSize) return {};
    return newSize > oldSize ? bilinearFilter(oldSize, newSize) : boxFilter(oldSize, newSize);
}

Image applyHorizontal(const Image& in, const AxisFilter& filter) {
    if (filter.empty()) return in;
    const int channels = in.channels();
    Image out(static_cast<int>(filter.size()), in.height(), channels);
    for (int y = 0; y < in.height(); ++y) {
        const float* src = in.row(y);
        float* dst = out.row(y);
        for (int k = 0; k < out.width(); ++k)
            for (const Tap& tap : filter[k])
                for (int c = 0; c < channels; ++c)
                    dst[k * channels + c] += tap.weight * src[tap.index * channels + c];
    }
    return out;
}

Image applyVertical(const Image& in, const AxisFilter& filter) {
    if (filter.empty()) return in;
    const int rowLength = in.width() * in.channels();
    Image out(in.width(), static_cast<int>(filter.size()), in.channels());
    for (int k = 0; k < out.height(); ++k) {
        float* dst = out.row(k);
        for (const Tap& tap : filter[k]) {
            const float* src = in.row(tap.index);
            for (int i = 0; i < rowLength; ++i) dst[i] += tap.weight * src[i];
        }
    }
    return out;
}

}  // namespace

Image resample(const Image& image, int width, int height) {
    STRATA_CHECK(!image.empty());
    // Rows run downwards (v decreasing) but a filter symmetric about texel centres does not care.
    return applyVertical(applyHorizontal(image, axisFilter(image.width(), width)),
                         axisFilter(image.height(), height));
}

std::vector<Image> buildMipPyramid(const Image& image) {
    std::vector<Image> levels{image};
    while (levels.back().width() > 1 || levels.back().height() > 1) {
        const Image& last = levels.back();
        levels.push_back(resample(last, std::max(1, last.width() / 2), std::max(1, last.height() / 2)));
    }
    return levels;
}

Image luminance(const Image& image) {
    if (image.channels() < 3) return extractChannel(image, 0);
    Image out(image.width(), image.height(), 1);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            out.at(x, y) =
                0.2126f * image.at(x, y, 0) + 0.7152f * image.at(x, y, 1) + 0.0722f * image.at(x, y, 2);
    return out;
}

Image toRgb(const Image& image) {
    Image out(image.width(), image.height(), 3);
    const bool gray = image.channels() < 3;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = image.at(x, y, gray ? 0 : c);
    return out;
}

Image extractChannel(const Image& image, int channel) {
    STRATA_CHECK_LT(channel, image.channels());
    Image out(image.width(), image.height(), 1);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) out.at(x, y) = image.at(x, y, channel);
    return out;
}

Image gaussianBlur(const Image& image, double sigma) {
    if (sigma <= 0.0) return image;
    const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
    std::vector<float> kernel(2 * radius + 1);
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) sum += std::exp(-0.5 * i * i / (sigma * sigma));
    for (int i = -radius; i <= radius; ++i)
        kernel[i + radius] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)) / sum);

    auto filterFor = [&](int size) {
        AxisFilter filter(size);
        for (int k = 0; k < size; ++k)
            for (int i = -radius; i <= radius; ++i)
                filter[k].push_back({Image::wrap(k + i, size), kernel[i + radius]});
        return filter;
    };
    return applyVertical(applyHorizontal(image, filterFor(image.width())), filterFor(image.height()));
}

ValueRange valueRange(const Image& image, int channel) {
    STRATA_CHECK_LT(channel, image.channels());
    ValueRange range{image.at(0, 0, channel), image.at(0, 0, channel)};
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            range.min = std::min(range.min, image.at(x, y, channel));
            range.max = std::max(range.max, image.at(x, y, channel));
        }
    return range;
}

Image normalizeToUnit(const Image& image, float flatValue) {
    STRATA_CHECK_EQ(image.channels(), 1);
    const ValueRange range = valueRange(image);
    Image out(image.width(), image.height(), 1, flatValue);
    const float span = range.max - range.min;
    if (!(span > 0.0f)) return out;
    for (std::size_t i = 0; i < out.pixels().size(); ++i)
        out.pixels()[i] = (image.pixels()[i] - range.min) / span;
    return out;
}

}  // namespace strata
