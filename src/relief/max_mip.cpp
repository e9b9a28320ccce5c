#include "strata/relief/max_mip.h"

#include "strata/core/error.h"

#include <algorithm>
#include <string>

namespace strata {

namespace {

bool isPowerOfTwo(int n) {
    return n > 0 && (n & (n - 1)) == 0;
}

}  // namespace

std::vector<Image> maxMipPyramid(const Image& depth) {
    const int width = depth.width();
    const int height = depth.height();
    if (depth.channels() != 1 || !isPowerOfTwo(width) || !isPowerOfTwo(height)) {
        throw Error(ErrorKind::InvalidInput,
                    "maximum mipmap: needs a 1-channel depth map whose sides are powers of two, got " +
                        std::to_string(width) + "x" + std::to_string(height) + "x" +
                        std::to_string(depth.channels()));
    }
    // Row y of the frame is image row height - 1 - y.
    const auto texel = [&](int x, int y) { return depth.at(x % width, height - 1 - (y % height)); };
    std::vector<Image> levels;
    Image level(width, height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            level.at(x, y) = std::min({texel(x, y), texel(x + 1, y), texel(x, y + 1), texel(x + 1, y + 1)});
    for (;;) {
        const int w = level.width(), h = level.height();
        levels.push_back(level);
        if (w == 1 && h == 1) break;
        Image next(std::max(1, w / 2), std::max(1, h / 2), 1);
        for (int y = 0; y < next.height(); ++y)
            for (int x = 0; x < next.width(); ++x) {
                float m = level.at(std::min(2 * x, w - 1), std::min(2 * y, h - 1));
                for (int dy = 0; dy < (h > 1 ? 2 : 1); ++dy)
                    for (int dx = 0; dx < (w > 1 ? 2 : 1); ++dx)
                        m = std::min(m, level.at(2 * x + dx, 2 * y + dy));
                next.at(x, y) = m;
            }
        level = std::move(next);
    }
    return levels;
}

}  // namespace strata
