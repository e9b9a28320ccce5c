#include "strata/compose/gradient_normals.h"

#include "strata/core/error.h"
#include "strata/relief/relief_texture.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace strata {

double gradientNormalScale(const Image& gradient) {
    double steepest = 0.0;
    for (int y = 0; y < gradient.height(); ++y)
        for (int x = 0; x < gradient.width(); ++x)
            steepest = std::max(steepest, std::hypot(static_cast<double>(gradient.at(x, y, 0)),
                                                     static_cast<double>(gradient.at(x, y, 1))));
    return steepest > 0.0 ? 0.25 / steepest : 1.0;
}

GradientNormals gradientNormals(const Image& depth) {
    if (depth.empty() || depth.channels() != 1) {
        throw Error(ErrorKind::InvalidInput, "gradientNormals: need a 1-channel depth map, got " +
                                                 std::to_string(depth.channels()) + " channels");
    }
    const Image gradient = depthGradient(depth);
    GradientNormals result;
    result.scale = gradientNormalScale(gradient);
    // In float, as the renderer has always stored them (the texture holds 16 bits anyway).
    const auto scale = static_cast<float>(result.scale);
    result.normals = Image(gradient.width(), gradient.height(), 3);
    for (int y = 0; y < gradient.height(); ++y)
        for (int x = 0; x < gradient.width(); ++x) {
            const glm::vec3 n =
                glm::normalize(glm::vec3(scale * gradient.at(x, y, 0), scale * gradient.at(x, y, 1), 1.0f));
            for (int c = 0; c < 3; ++c) result.normals.at(x, y, c) = n[c];
        }
    return result;
}

}  // namespace strata
