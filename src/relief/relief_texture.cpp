#include "strata/relief/relief_texture.h"

#include "strata/core/check.h"

#include <cmath>

namespace strata {

Image depthGradient(const Image& depth) {
    STRATA_CHECK_EQ(depth.channels(), 1);
    const int w = depth.width();
    const int h = depth.height();
    Image gradient(w, h, 2);
    // Per-tile derivatives: one texel step is 1/W of the tile in u and 1/H in v. v grows upwards
    // while rows grow downwards, so dd/dv = (row above - row below) / (2 / H).
    const float su = 0.5f * static_cast<float>(w);
    const float sv = 0.5f * static_cast<float>(h);
    for (int y = 0; y < h; ++y) {
        const float* above = depth.row(Image::wrap(y - 1, h));
        const float* below = depth.row(Image::wrap(y + 1, h));
        const float* here = depth.row(y);
        for (int x = 0; x < w; ++x) {
            const int left = x == 0 ? w - 1 : x - 1;
            const int right = x + 1 == w ? 0 : x + 1;
            gradient.at(x, y, 0) = su * (here[right] - here[left]);
            gradient.at(x, y, 1) = sv * (above[x] - below[x]);
        }
    }
    return gradient;
}

Image normalsFromDepth(const Image& depth, double depthScale) {
    const Image gradient = depthGradient(depth);
    Image normals(depth.width(), depth.height(), 3);
    const auto s = static_cast<float>(depthScale);
    for (int y = 0; y < depth.height(); ++y)
        for (int x = 0; x < depth.width(); ++x) {
            // The relief point is (u, v, -S d): its normal is (S dd/du, S dd/dv, 1), normalised (CONVENTIONS
            // §3).
            const float nx = s * gradient.at(x, y, 0);
            const float ny = s * gradient.at(x, y, 1);
            const float inv = 1.0f / std::sqrt(nx * nx + ny * ny + 1.0f);
            normals.at(x, y, 0) = nx * inv;
            normals.at(x, y, 1) = ny * inv;
            normals.at(x, y, 2) = inv;
        }
    return normals;
}

Image encodeNormals(const Image& normals) {
    STRATA_CHECK_EQ(normals.channels(), 3);
    Image out(normals.width(), normals.height(), 3);
    for (std::size_t i = 0; i < out.pixels().size(); ++i) out.pixels()[i] = normals.pixels()[i] * 0.5f + 0.5f;
    return out;
}

Image decodeNormals(const Image& encoded, bool flipY) {
    STRATA_CHECK_GE(encoded.channels(), 3);
    Image out(encoded.width(), encoded.height(), 3);
    for (int y = 0; y < encoded.height(); ++y)
        for (int x = 0; x < encoded.width(); ++x) {
            float n[3];
            for (int c = 0; c < 3; ++c) n[c] = encoded.at(x, y, c) * 2.0f - 1.0f;
            if (flipY) n[1] = -n[1];
            const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int c = 0; c < 3; ++c)
                out.at(x, y, c) = length > 0.0f ? n[c] / length : (c == 2 ? 1.0f : 0.0f);
        }
    return out;
}

Image heightToDepth(const Image& height) {
    STRATA_CHECK_EQ(height.channels(), 1);
    Image out = height;
    for (float& value : out.pixels()) value = 1.0f - value;
    return out;
}

}  // namespace strata
