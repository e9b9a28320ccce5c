// The shaders' search loops run on the CPU against the exact bilinear height field, to count texture
// fetches (bench_render, bench_techniques): the same steps and early exits as the GLSL they mirror.
#pragma once

#include "strata/scene/render_settings.h"
#include "strata/trace/heightfield_tracer.h"

#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>

namespace strata::bench {

struct ReliefSearch {
    int fetches = 0;
    double depth = 1.0;    // the deepest point found inside (reliefIntersect's result)
    double bracket = 0.0;  // the final search window: the surface lies within it above `depth`
};

// relief_search.glsl, reliefIntersect, for the ray entering at `entry` with (u, v) travel `ds` per unit of
// depth, at cos theta = cosTheta from the normal.
inline ReliefSearch reliefIntersect(const HeightFieldTracer& tracer, glm::dvec2 entry, glm::dvec2 ds,
                                    double cosTheta, int linear, int binary) {
    ReliefSearch result;
    const int n = adaptiveLinearSteps(linear, cosTheta);
    double size = 1.0 / n, depth = 0.0;
    for (int i = 0; i < n - 1; ++i) {
        depth += size;
        ++result.fetches;
        const glm::dvec2 uv = entry + ds * depth;
        if (depth >= tracer.depthAt(uv.x, uv.y)) {
            result.depth = depth;
            break;
        }
    }
    depth = result.depth;
    for (int i = 0; i < binary; ++i) {
        size *= 0.5;
        ++result.fetches;
        const glm::dvec2 uv = entry + ds * depth;
        if (depth >= tracer.depthAt(uv.x, uv.y)) {
            result.depth = depth;
            depth -= 2.0 * size;
        }
        depth += size;
    }
    result.bracket = 1.0 / (n * std::exp2(std::max(binary - 1, 0)));
    return result;
}

}  // namespace strata::bench
