#include "strata/compose/compose.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>

namespace strata {

namespace {

[[noreturn]] void invalid(const std::string& message) {
    throw Error(ErrorKind::InvalidInput, message);
}

std::string layerName(std::span<const CompositionLayer> layers, std::size_t i) {
    return layers[i].label.empty() ? "layer " + std::to_string(i) : layers[i].label;
}

struct WeightSums {
    double depth;
    double normal;
};

// Checks everything compose() relies on and returns the weight sums it computed on the way.
WeightSums validate(std::span<const CompositionLayer> layers, const ComposeParams& params) {
    if (layers.empty()) invalid("a meta-relief needs at least one layer");
    double sumDepth = 0.0;
    double sumNormal = 0.0;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const CompositionLayer& layer = layers[i];
        const std::string name = layerName(layers, i);
        auto checkWeight = [&](double w, const char* key) {
            if (!std::isfinite(w))
                invalid(name + ": " + key + " must be a finite number, got " + formatNumber(w));
            if (w < 0.0) invalid(name + ": " + key + " must be >= 0, got " + formatNumber(w));
        };
        checkWeight(layer.weightDepth, "weight_depth");
        checkWeight(layer.weightNormal, "weight_normal");
        if (!std::isfinite(layer.tiling) || layer.tiling <= 0.0)
            invalid(name + ": tiling must be a number > 0, got " + formatNumber(layer.tiling));
        if (layer.texture.depth.empty()) invalid(name + ": has no depth map");
        if (layer.texture.depth.channels() != 1) invalid(name + ": the depth map must have 1 channel");
        if (params.normals == NormalMode::Paper && layer.weightNormal > 0.0 &&
            (layer.texture.normal.empty() || layer.texture.normal.channels() != 3))
            invalid(name + ": the 'paper' normal mode needs the layer's normal map");
        sumDepth += layer.weightDepth;
        sumNormal += layer.weightNormal;
    }
    if (!(sumDepth > 0.0))
        invalid("the depth weights (weight_depth) of the layers sum to 0: at least one must be > 0");
    if (!(sumNormal > 0.0))
        invalid("the normal weights (weight_normal) of the layers sum to 0: at least one must be > 0");
    if (params.resolution < 0 || params.resolution > Image::kMaxDimension)
        invalid("resolution must be in [1, " + std::to_string(Image::kMaxDimension) + "], got " +
                std::to_string(params.resolution));
    if (!std::isfinite(params.depthScale) || params.depthScale <= 0.0)
        invalid("depth_scale must be a number > 0, got " + formatNumber(params.depthScale));
    if (params.colorFrom >= 0) {
        if (static_cast<std::size_t>(params.colorFrom) >= layers.size())
            invalid("color_from: " + std::to_string(params.colorFrom) + " is not a layer index (there are " +
                    std::to_string(layers.size()) + " layers, counted from 0)");
        if (layers[params.colorFrom].texture.color.empty())
            invalid("color_from: " + layerName(layers, params.colorFrom) + " has no colour map");
    } else if (params.colorFrom != -1) {
        invalid("color_from must be a layer index >= 0, or -1 for none, got " +
                std::to_string(params.colorFrom));
    }
    return {sumDepth, sumNormal};
}

// Where output texel k of an axis of `outSize` texels lands in a layer axis of `layerSize` texels
// tiled `tiling` times, as two neighbouring layer texels and a blend weight. Precomputed per column
// and per row, since the position along one axis does not depend on the other.
struct AxisTaps {
    std::vector<int> i0;
    std::vector<int> i1;
    std::vector<float> t;
};

// `flipped` is for the v axis: rows grow downwards while v grows upwards. In texel units the layer
// position is x = t * (k + 0.5) * layerSize / outSize - 0.5 along u, and for v the row
// y = (1 - t * v) * layerSize - 0.5 with v = 1 - (k + 0.5) / outSize, i.e.
// y = t * (k + 0.5) * layerSize / outSize - 0.5 + (1 - t) * layerSize. Done in double so that an
// output texel centre that falls on a layer texel centre gives a zero blend weight exactly.
AxisTaps axisTaps(int outSize, int layerSize, double tiling, bool flipped) {
    AxisTaps taps;
    taps.i0.resize(outSize);
    taps.i1.resize(outSize);
    taps.t.resize(outSize);
    const double scale = tiling * layerSize / outSize;
    double offset = -0.5;
    if (flipped) offset += std::fmod((1.0 - tiling) * layerSize, static_cast<double>(layerSize));
    for (int k = 0; k < outSize; ++k) {
        const double x = (k + 0.5) * scale + offset;
        const double fx = std::floor(x);
        const int base =
            Image::wrap(static_cast<int>(std::fmod(fx, static_cast<double>(layerSize))), layerSize);
        taps.i0[k] = base;
        taps.i1[k] = base + 1 == layerSize ? 0 : base + 1;
        taps.t[k] = static_cast<float>(x - fx);
    }
    return taps;
}

// A map of one layer prepared for sampling at the output's texel centres.
struct SampledMap {
    const Image* image = nullptr;
    AxisTaps columns;
    AxisTaps rows;

    SampledMap(const Image& map, int outSize, double tiling)
        : image(&map),
          columns(axisTaps(outSize, map.width(), tiling, false)),
          rows(axisTaps(outSize, map.height(), tiling, true)) {}

    // Adds weight * (bilinear sample at output texel (x, y)) to dst[x * C + c] for a whole output
    // row. C is the map's channel count, fixed at compile time so the inner loop unrolls.
    template <int C>
    void accumulateRow(int y, float weight, float* dst) const {
        const float* r0 = image->row(rows.i0[y]);
        const float* r1 = image->row(rows.i1[y]);
        const float ty = rows.t[y];
        const int width = static_cast<int>(columns.t.size());
        for (int x = 0; x < width; ++x) {
            const int c0 = columns.i0[x] * C;
            const int c1 = columns.i1[x] * C;
            const float tx = columns.t[x];
            for (int c = 0; c < C; ++c) {
                const float top = r0[c0 + c] + tx * (r0[c1 + c] - r0[c0 + c]);
                const float bottom = r1[c0 + c] + tx * (r1[c1 + c] - r1[c0 + c]);
                dst[x * C + c] += weight * (top + ty * (bottom - top));
            }
        }
    }

    void accumulateRow(int y, float weight, float* dst) const {
        switch (image->channels()) {
            case 1:
                accumulateRow<1>(y, weight, dst);
                break;
            case 2:
                accumulateRow<2>(y, weight, dst);
                break;
            case 3:
                accumulateRow<3>(y, weight, dst);
                break;
            default:
                accumulateRow<4>(y, weight, dst);
                break;
        }
    }
};

bool isInteger(double value) {
    return std::fabs(value - std::round(value)) < 1e-9;
}

}  // namespace

namespace {

// Makes `image` width x height x channels, keeping its memory if it already has that shape.
// The contents are left as they are: the caller overwrites every value.
void reshape(Image& image, int width, int height, int channels) {
    if (image.width() != width || image.height() != height || image.channels() != channels)
        image = Image::uninitialized(width, height, channels);
}

}  // namespace

Composition compose(std::span<const CompositionLayer> layers, const ComposeParams& params) {
    Composition result;
    composeInto(layers, params, result);
    return result;
}

void composeInto(std::span<const CompositionLayer> layers, const ComposeParams& params, Composition& result) {
    const WeightSums sums = validate(layers, params);
    result.warnings.clear();

    int size = params.resolution;
    if (size == 0)
        for (const auto& layer : layers) size = std::max(size, layer.texture.depth.width());

    for (std::size_t i = 0; i < layers.size(); ++i)
        if (!isInteger(layers[i].tiling))
            result.warnings.push_back(
                layerName(layers, i) + ": tiling " + formatNumber(layers[i].tiling) +
                " is not an integer, so the baked texture does not tile (the layer is cut at the tile "
                "border). "
                "strata render --meta live samples the layers per fragment and has no such seam.");

    // Per-layer sampling plans. Consistent normals need each layer's depth gradient (per layer tile),
    // sampled like the depth and scaled by the tiling factor (chain rule).
    struct LayerPlan {
        float depthWeight;    // w_d / sum w_d
        float normalWeight;   // w_n / sum w_n
        float gradientScale;  // w_d / sum w_d * tiling
        SampledMap depth;
        std::optional<SampledMap> normal;
        std::optional<SampledMap> gradient;
    };
    std::vector<Image> gradients(layers.size());
    std::vector<LayerPlan> plans;
    plans.reserve(layers.size());
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const CompositionLayer& layer = layers[i];
        if (layer.weightDepth == 0.0 && layer.weightNormal == 0.0) continue;
        LayerPlan plan{static_cast<float>(layer.weightDepth / sums.depth),
                       static_cast<float>(layer.weightNormal / sums.normal),
                       static_cast<float>(layer.weightDepth / sums.depth * layer.tiling),
                       SampledMap(layer.texture.depth, size, layer.tiling),
                       std::nullopt,
                       std::nullopt};
        if (params.normals == NormalMode::Paper && layer.weightNormal > 0.0)
            plan.normal.emplace(layer.texture.normal, size, layer.tiling);
        if (params.normals == NormalMode::Consistent && layer.weightDepth > 0.0) {
            gradients[i] = depthGradient(layer.texture.depth);
            plan.gradient.emplace(gradients[i], size, layer.tiling);
        }
        plans.push_back(std::move(plan));
    }

    ReliefTexture& out = result.texture;
    out.depthScale = params.depthScale;
    out.ao = Image();
    reshape(out.depth, size, size, 1);
    reshape(out.normal, size, size, 3);
    const auto s = static_cast<float>(params.depthScale);

    // Row by row, layer by layer: each layer's row taps are fetched once per row, and the inner
    // loops have no per-texel branching.
    parallelForChunks(0, size, [&](int rowBegin, int rowEnd) {
        std::vector<float> gradientRow(2 * static_cast<std::size_t>(size));
        for (int y = rowBegin; y < rowEnd; ++y) {
            float* depthRow = out.depth.row(y);
            float* normalRow = out.normal.row(y);
            std::fill(depthRow, depthRow + size, 0.0f);
            std::fill(normalRow, normalRow + 3 * size, 0.0f);
            std::fill(gradientRow.begin(), gradientRow.end(), 0.0f);
            for (const LayerPlan& plan : plans) {
                // A lone layer keeps its values bit for bit: its w / sum w is exactly 1, and 0 + 1 * v = v.
                if (plan.depthWeight > 0.0f) plan.depth.accumulateRow<1>(y, plan.depthWeight, depthRow);
                if (plan.normal) plan.normal->accumulateRow<3>(y, plan.normalWeight, normalRow);
                if (plan.gradient) plan.gradient->accumulateRow<2>(y, plan.gradientScale, gradientRow.data());
            }
            for (int x = 0; x < size; ++x) {
                float* n = normalRow + 3 * x;
                if (params.normals == NormalMode::Consistent) {
                    // CONVENTIONS §3: n = normalize(S dD/du, S dD/dv, 1).
                    n[0] = s * gradientRow[2 * x];
                    n[1] = s * gradientRow[2 * x + 1];
                    n[2] = 1.0f;
                }
                const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                // Opposite normals can cancel in Eq. 1; fall back to the plane's normal there. A vector
                // already unit to far below 16-bit quantisation (1.5e-5) is kept as is, so that a lone
                // layer's normals come out bit for bit.
                if (!(length > 1e-12f)) {
                    n[0] = n[1] = 0.0f;
                    n[2] = 1.0f;
                } else if (std::fabs(length - 1.0f) > 1e-6f) {
                    for (int c = 0; c < 3; ++c) n[c] /= length;
                }
            }
        }
    });

    if (params.colorFrom >= 0) {
        const CompositionLayer& layer = layers[params.colorFrom];
        const SampledMap color(layer.texture.color, size, layer.tiling);
        const int channels = layer.texture.color.channels();
        reshape(out.color, size, size, channels);
        parallelFor(0, size, [&](int y) {
            float* row = out.color.row(y);
            std::fill(row, row + channels * size, 0.0f);
            color.accumulateRow(y, 1.0f, row);
        });
    } else {
        out.color = Image();
    }
}

AngleStats angleBetween(const Image& a, const Image& b) {
    STRATA_CHECK_EQ(a.width(), b.width());
    STRATA_CHECK_EQ(a.height(), b.height());
    STRATA_CHECK_EQ(a.channels(), 3);
    STRATA_CHECK_EQ(b.channels(), 3);
    double sum = 0.0;
    double worst = 0.0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            double dot = 0.0;
            for (int c = 0; c < 3; ++c)
                dot += static_cast<double>(a.at(x, y, c)) * static_cast<double>(b.at(x, y, c));
            const double angle = std::acos(std::clamp(dot, -1.0, 1.0)) * 180.0 / std::numbers::pi;
            sum += angle;
            worst = std::max(worst, angle);
        }
    return {sum / static_cast<double>(a.texelCount()), worst};
}

const char* toString(NormalMode mode) {
    return mode == NormalMode::Paper ? "paper" : "consistent";
}

NormalMode parseNormalMode(const std::string& text) {
    if (text == "paper") return NormalMode::Paper;
    if (text == "consistent") return NormalMode::Consistent;
    throw Error(ErrorKind::InvalidInput,
                "normals: must be \"paper\" or \"consistent\", got \"" + text + "\"");
}

}  // namespace strata
