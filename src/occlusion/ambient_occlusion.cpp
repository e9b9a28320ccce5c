// Texture-space AO (meta-relief paper, Section IV): horizon search, the paper's polygon AO, the
// cosine-weighted reference, the filter, the depth rescale and layer combination.
#include "strata/occlusion/ambient_occlusion.h"

#include "horizon_line.h"
#include "horizon_search.h"
#include "shared/ao_rescale.h"
#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace strata {
namespace {

constexpr double kPi = std::numbers::pi;

void requireRange(const char* name, double value, double lo, double hi, bool loOpen) {
    const bool ok = std::isfinite(value) && (loOpen ? value > lo : value >= lo) && value <= hi;
    if (!ok)
        throw Error(ErrorKind::InvalidInput, std::string("ambient occlusion: ") + name + " = " +
                                                 formatNumber(value) + " is outside " + (loOpen ? "(" : "[") +
                                                 formatNumber(lo) + ", " + formatNumber(hi) + "]");
}

void validate(const Image& depth, const AoParams& params) {
    if (depth.empty()) throw Error(ErrorKind::InvalidInput, "ambient occlusion: the depth map is empty");
    if (depth.channels() != 1)
        throw Error(ErrorKind::InvalidInput, "ambient occlusion: the depth map has " +
                                                 std::to_string(depth.channels()) + " channels, expected 1");
    requireRange("directions", params.directions, 3, 1024, false);
    requireRange("radius", params.radius, 0.0, 16.0, true);
    requireRange("depth scale", params.depthScale, 0.0, 100.0, true);
    if (params.marchStep != 0.0) requireRange("march step", params.marchStep, 1.0 / 64.0, 16.0, false);
    requireRange("filter radius", params.filterRadius, 0, 8, false);
    requireRange("filter sigma", params.filterSigma, 0.0, 16.0, true);
}

bool anyOccluded(std::span<const float> tans) {
    return std::any_of(tans.begin(), tans.end(), [](float t) { return t > 0.0f; });
}

}  // namespace

float HorizonMap::aoAt(int x, int y, double s) const {
    const auto sf = static_cast<float>(s);
    double sum = 0.0;
    for (const float t : texel(x, y)) sum += static_cast<double>(shared::aoDirectionExact(t, sf));
    return static_cast<float>(sum / directions);
}

Image HorizonMap::ao(double s) const {
    STRATA_CHECK_EQ(tanHorizon.size(), static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                                           static_cast<std::size_t>(directions));
    Image out = Image::uninitialized(width, height, 1);
    parallelFor(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) out.at(x, y) = aoAt(x, y, s);
    });
    return out;
}

HorizonMap computeHorizons(const Image& depth, const AoParams& params) {
    validate(depth, params);
    if (params.method == AoMethod::Sweep) return detail::sweepHorizons(depth, params);
    return detail::marchHorizons(depth, params);
}

HorizonMap detail::marchHorizons(const Image& depth, const AoParams& params) {
    const int w = depth.width();
    const int h = depth.height();
    const int m = params.directions;
    HorizonMap result;
    result.width = w;
    result.height = h;
    result.directions = m;
    result.depthScale = params.depthScale;
    result.radius = params.radius;
    result.tanHorizon.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) *
                             static_cast<std::size_t>(m));

    const auto range = std::minmax_element(depth.pixels().begin(), depth.pixels().end());
    const double minDepth = *range.first;
    const double scale = params.depthScale;
    if (params.marchStep == 0.0) {
        // Cell by cell along each texel's own line: exact for the bilinear relief.
        std::vector<detail::LineDirection> directions;
        for (int i = 0; i < m; ++i) directions.emplace_back(2.0 * kPi * i / m, w, h);
        parallelFor(0, h, [&](int y) {
            for (int x = 0; x < w; ++x) {
                float* out =
                    result.tanHorizon.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                                static_cast<std::size_t>(x)) *
                                                   static_cast<std::size_t>(m);
                for (int i = 0; i < m; ++i) {
                    const detail::LineDirection& dir = directions[static_cast<std::size_t>(i)];
                    const detail::MajorMinorDepth grid(depth, dir.xMajor);
                    out[i] = static_cast<float>(
                        detail::horizonAlongLine(depth, grid, dir, x, y, scale, params.radius, minDepth));
                }
            }
        });
        return result;
    }

    // N samples at t_k = k R / N, k = 1..N: a step of at most marchStep texels of the larger side.
    const double side = std::max(w, h);
    const int steps = std::max(1, static_cast<int>(std::ceil(params.radius * side / params.marchStep)));
    const double dt = params.radius / steps;
    // Per direction, the step in continuous texel coordinates (x = u W - 0.5, y = (1 - v) H - 0.5):
    // +u is +x, +v is -y.
    std::vector<double> stepX(static_cast<std::size_t>(m));
    std::vector<double> stepY(static_cast<std::size_t>(m));
    for (int i = 0; i < m; ++i) {
        const double phi = 2.0 * kPi * i / m;
        stepX[static_cast<std::size_t>(i)] = std::cos(phi) * dt * w;
        stepY[static_cast<std::size_t>(i)] = -std::sin(phi) * dt * h;
    }

    parallelFor(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const double d0 = depth.at(x, y);
            // No sample can rise above S (d0 - min d) / t: the early stop below changes nothing.
            const double rise = scale * (d0 - minDepth);
            float* out =
                result.tanHorizon.data() +
                (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) *
                    static_cast<std::size_t>(m);
            for (int i = 0; i < m; ++i) {
                // The limit t -> 0+: the slope of the bilinear cell the direction enters. At a texel
                // centre that cell's depth along the ray is d0 + t (|ex| (dX - d0) + |ey| (dY - d0)) +
                // O(t^2), dX and dY the neighbours on the side the ray moves to (ex, ey: its texel
                // velocity). Without it the first sample's secant underestimates every horizon that
                // starts at the texel (a convex neighbourhood) by O(step).
                const double ex = stepX[static_cast<std::size_t>(i)] / dt;
                const double ey = stepY[static_cast<std::size_t>(i)] / dt;
                const double dX = depth.atWrapped(ex > 0.0 ? x + 1 : x - 1, y);
                const double dY = depth.atWrapped(x, ey > 0.0 ? y + 1 : y - 1);
                // Horizons below the reference plane count as 0.
                double best = std::max(0.0, scale * (std::abs(ex) * (d0 - dX) + std::abs(ey) * (d0 - dY)));
                for (int k = 1; k <= steps; ++k) {
                    const double t = k * dt;
                    if (rise <= best * t) break;
                    float d = 0.0f;
                    depth.sampleTexel(x + k * stepX[static_cast<std::size_t>(i)],
                                      y + k * stepY[static_cast<std::size_t>(i)], &d);
                    best = std::max(best, scale * (d0 - static_cast<double>(d)) / t);
                }
                out[i] = static_cast<float>(best);
            }
        }
    });
    return result;
}

std::vector<float> texelHorizons(const Image& depth, const AoParams& params, int x, int y) {
    validate(depth, params);
    if (x < 0 || y < 0 || x >= depth.width() || y >= depth.height())
        throw Error(ErrorKind::InvalidInput, "ambient occlusion: texel (" + std::to_string(x) + ", " +
                                                 std::to_string(y) + ") is outside the " +
                                                 std::to_string(depth.width()) + " x " +
                                                 std::to_string(depth.height()) + " map");
    const double minDepth = *std::min_element(depth.pixels().begin(), depth.pixels().end());
    std::vector<float> out(static_cast<std::size_t>(params.directions));
    for (int i = 0; i < params.directions; ++i) {
        const detail::LineDirection dir(2.0 * kPi * i / params.directions, depth.width(), depth.height());
        const detail::MajorMinorDepth grid(depth, dir.xMajor);
        out[static_cast<std::size_t>(i)] = static_cast<float>(
            detail::horizonAlongLine(depth, grid, dir, x, y, params.depthScale, params.radius, minDepth));
    }
    return out;
}

double polygonOpenValue(int directions, AoNormalize normalize) {
    if (normalize == AoNormalize::Open) return 1.0;
    return 0.5 * directions * std::sin(2.0 * kPi / directions) / kPi;
}

Image polygonAo(const HorizonMap& horizons, AoNormalize normalize, double s) {
    const int m = horizons.directions;
    // area = 1/2 sin(2 pi / M) sum_i cos h_i cos h_(i+1); divided by pi or by (M/2) sin(2 pi / M).
    const double factor = normalize == AoNormalize::Open ? 1.0 / m : 0.5 * std::sin(2.0 * kPi / m) / kPi;
    Image out = Image::uninitialized(horizons.width, horizons.height, 1);
    parallelFor(0, horizons.height, [&](int y) {
        std::vector<double> cosH(static_cast<std::size_t>(m));
        for (int x = 0; x < horizons.width; ++x) {
            const std::span<const float> tans = horizons.texel(x, y);
            for (int i = 0; i < m; ++i) {
                const double t = s * static_cast<double>(tans[static_cast<std::size_t>(i)]);
                cosH[static_cast<std::size_t>(i)] = 1.0 / std::sqrt(1.0 + t * t);
            }
            double sum = 0.0;
            for (int i = 0; i < m; ++i)
                sum += cosH[static_cast<std::size_t>(i)] * cosH[static_cast<std::size_t>((i + 1) % m)];
            out.at(x, y) = static_cast<float>(sum * factor);
        }
    });
    return out;
}

Image filterOccluded(const Image& ao, const HorizonMap& horizons, int radius, double sigma) {
    STRATA_CHECK_EQ(ao.width(), horizons.width);
    STRATA_CHECK_EQ(ao.height(), horizons.height);
    STRATA_CHECK_EQ(ao.channels(), 1);
    STRATA_CHECK_GE(radius, 0);
    STRATA_CHECK_GT(sigma, 0.0);
    const int taps = 2 * radius + 1;
    std::vector<double> kernel(static_cast<std::size_t>(taps * taps));
    double total = 0.0;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            const double weight = std::exp(-(dx * dx + dy * dy) / (2.0 * sigma * sigma));
            kernel[static_cast<std::size_t>((dy + radius) * taps + dx + radius)] = weight;
            total += weight;
        }
    for (double& weight : kernel) weight /= total;

    Image out = ao;
    parallelFor(0, ao.height(), [&](int y) {
        for (int x = 0; x < ao.width(); ++x) {
            if (!anyOccluded(horizons.texel(x, y))) continue;
            double sum = 0.0;
            for (int dy = -radius; dy <= radius; ++dy)
                for (int dx = -radius; dx <= radius; ++dx)
                    sum += kernel[static_cast<std::size_t>((dy + radius) * taps + dx + radius)] *
                           static_cast<double>(ao.atWrapped(x + dx, y + dy));
            out.at(x, y) = static_cast<float>(sum);
        }
    });
    return out;
}

Image bakeAo(const Image& depth, const AoParams& params) {
    const bool filter = params.filter == AoFilter::Paper ||
                        (params.filter == AoFilter::Auto && params.method == AoMethod::Paper);
    if (params.method == AoMethod::Sweep && !filter) {
        validate(depth, params);
        return detail::sweepAo(depth, params);
    }
    const HorizonMap horizons = computeHorizons(depth, params);
    const Image ao = params.method == AoMethod::Paper ? polygonAo(horizons, params.normalize) : horizons.ao();
    return filter ? filterOccluded(ao, horizons, params.filterRadius, params.filterSigma) : ao;
}

float rescaleAoPaper(float ao, float s) {
    return shared::aoRescalePaper(ao, s);
}

Image rescaleAoPaper(const Image& ao, double s) {
    Image out = ao;
    const auto sf = static_cast<float>(s);
    for (float& value : out.pixels()) value = shared::aoRescalePaper(value, sf);
    return out;
}

Image rescaleAoExact(const HorizonMap& horizons, double s) {
    return horizons.ao(s);
}

std::uint8_t encodeHorizon8(float tanHorizon) {
    const double angle = std::atan(std::max(0.0, static_cast<double>(tanHorizon)));
    return static_cast<std::uint8_t>(std::lround(std::clamp(angle / (0.5 * kPi), 0.0, 1.0) * 255.0));
}

float decodeHorizon8(std::uint8_t code) {
    // Code 255 (pi/2, a vertical wall at zero distance) decodes to a huge but finite tangent.
    const double angle = std::min(code * (0.5 * kPi) / 255.0, 0.5 * kPi - 1e-6);
    return static_cast<float>(std::tan(angle));
}

HorizonMap quantizeHorizons8(const HorizonMap& horizons) {
    HorizonMap out = horizons;
    for (float& t : out.tanHorizon) t = decodeHorizon8(encodeHorizon8(t));
    return out;
}

Image combineAo(std::span<const AoLayer> layers, AoCombine mode, int resolution) {
    if (layers.empty()) throw Error(ErrorKind::InvalidInput, "combine ambient occlusion: no layers");
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const AoLayer& layer = layers[i];
        const std::string name = layer.label.empty() ? "layers[" + std::to_string(i) + "]" : layer.label;
        if (layer.ao.empty())
            throw Error(ErrorKind::InvalidInput, "combine ambient occlusion: " + name + " has no AO map");
        if (layer.ao.channels() != 1)
            throw Error(ErrorKind::InvalidInput, "combine ambient occlusion: " + name + " has " +
                                                     std::to_string(layer.ao.channels()) +
                                                     " channels, expected 1");
        if (!std::isfinite(layer.tiling) || layer.tiling <= 0.0)
            throw Error(ErrorKind::InvalidInput, "combine ambient occlusion: " + name + " tiling = " +
                                                     formatNumber(layer.tiling) + ", expected > 0");
    }
    if (resolution < 1 || resolution > Image::kMaxDimension)
        throw Error(ErrorKind::InvalidInput,
                    "combine ambient occlusion: resolution = " + std::to_string(resolution) +
                        " is outside [1, " + std::to_string(Image::kMaxDimension) + "]");
    Image out = Image::uninitialized(resolution, resolution, 1);
    parallelFor(0, resolution, [&](int y) {
        for (int x = 0; x < resolution; ++x) {
            const double u = out.texelU(x);
            const double v = out.texelV(y);
            float value = mode == AoCombine::Multiply ? 1.0f : 0.0f;
            for (std::size_t i = 0; i < layers.size(); ++i) {
                const float a = layers[i].ao.sample(layers[i].tiling * u, layers[i].tiling * v);
                if (mode == AoCombine::Multiply)
                    value *= a;
                else
                    value = i == 0 ? a : std::min(value, a);
            }
            out.at(x, y) = value;
        }
    });
    return out;
}

const char* toString(AoMethod method) {
    switch (method) {
        case AoMethod::Sweep:
            return "sweep";
        case AoMethod::Brute:
            return "brute";
        case AoMethod::Paper:
            return "paper";
    }
    return "?";
}
const char* toString(AoFilter filter) {
    switch (filter) {
        case AoFilter::Auto:
            return "auto";
        case AoFilter::Paper:
            return "paper";
        case AoFilter::None:
            return "none";
    }
    return "?";
}
const char* toString(AoNormalize normalize) {
    return normalize == AoNormalize::Paper ? "paper" : "open";
}
const char* toString(AoCombine mode) {
    return mode == AoCombine::Min ? "min" : "multiply";
}

AoMethod parseAoMethod(const std::string& text) {
    if (text == "sweep") return AoMethod::Sweep;
    if (text == "brute") return AoMethod::Brute;
    if (text == "paper") return AoMethod::Paper;
    throw Error(ErrorKind::InvalidInput, "unknown AO method '" + text + "' (expected sweep, brute or paper)");
}
AoFilter parseAoFilter(const std::string& text) {
    if (text == "auto") return AoFilter::Auto;
    if (text == "paper") return AoFilter::Paper;
    if (text == "none") return AoFilter::None;
    throw Error(ErrorKind::InvalidInput, "unknown AO filter '" + text + "' (expected auto, paper or none)");
}
AoNormalize parseAoNormalize(const std::string& text) {
    if (text == "open") return AoNormalize::Open;
    if (text == "paper") return AoNormalize::Paper;
    throw Error(ErrorKind::InvalidInput, "unknown AO normalisation '" + text + "' (expected open or paper)");
}
AoCombine parseAoCombine(const std::string& text) {
    if (text == "multiply") return AoCombine::Multiply;
    if (text == "min") return AoCombine::Min;
    throw Error(ErrorKind::InvalidInput, "unknown AO combination '" + text + "' (expected multiply or min)");
}

}  // namespace strata
