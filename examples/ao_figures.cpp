// The pictures and tables of docs/occlusion.md: AO by each method on one pattern with difference
// images, the sweep against the exact walk on every pattern, and the layer combinations (multiply, min)
// against the AO of the composed depth.
//
//   build/release/examples/example_ao_figures examples docs/img
//
// Writes <out>/ao_methods_stone_bricks.png and prints markdown tables on stdout.
#include "strata/compose/compose.h"
#include "strata/image/image_io.h"
#include "strata/image/image_ops.h"
#include "strata/occlusion/ambient_occlusion.h"
#include "strata/occlusion/meta_relief_ao.h"
#include "strata/relief/patterns.h"
#include "strata/scene/material.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

namespace fs = std::filesystem;
using namespace strata;

namespace {

struct Stats {
    double bias = 0.0;
    double meanAbs = 0.0;
    double maxAbs = 0.0;
    double rmse = 0.0;
};

Stats compare(const Image& a, const Image& b) {
    Stats s;
    const auto n = static_cast<double>(a.pixels().size());
    for (std::size_t i = 0; i < a.pixels().size(); ++i) {
        const double d = static_cast<double>(a.pixels()[i]) - static_cast<double>(b.pixels()[i]);
        s.bias += d / n;
        s.meanAbs += std::abs(d) / n;
        s.maxAbs = std::max(s.maxAbs, std::abs(d));
        s.rmse += d * d / n;
    }
    s.rmse = std::sqrt(s.rmse);
    return s;
}

double seconds(const auto& body) {
    const auto start = std::chrono::steady_clock::now();
    body();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Gray panels side by side, 4 px white gaps.
Image strip(const std::vector<Image>& panels) {
    constexpr int kGap = 4;
    int width = -kGap;
    for (const Image& p : panels) width += p.width() + kGap;
    Image out(width, panels.front().height(), 1, 1.0f);
    int x0 = 0;
    for (const Image& p : panels) {
        for (int y = 0; y < p.height(); ++y)
            for (int x = 0; x < p.width(); ++x) out.at(x0 + x, y) = std::clamp(p.at(x, y), 0.0f, 1.0f);
        x0 += p.width() + kGap;
    }
    return out;
}

Image scaledDifference(const Image& a, const Image& b, float gain) {
    Image out(a.width(), a.height(), 1);
    for (std::size_t i = 0; i < a.pixels().size(); ++i)
        out.pixels()[i] = 1.0f - gain * std::abs(a.pixels()[i] - b.pixels()[i]);  // white = equal
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3 && argc != 4) {
        std::fprintf(stderr, "usage: %s EXAMPLES_DIR OUTPUT_DIR [combine]\n", argv[0]);
        return 1;
    }
    const fs::path examples = argv[1];
    const fs::path out = argv[2];
    fs::create_directories(out);

    const bool all = argc == 3;  // "combine": only part 3
    // 1. Every method on stone-bricks at 256^2.
    if (all) {
        const Image depth = makePattern("stone-bricks", {256, 1, kDefaultDepthScale}).depth;
        AoParams params;
        params.filter = AoFilter::None;
        Image sweep, brute, paper;
        params.method = AoMethod::Sweep;
        const double tSweep = seconds([&] { sweep = bakeAo(depth, params); });
        params.method = AoMethod::Brute;
        const double tBrute = seconds([&] { brute = bakeAo(depth, params); });
        params.method = AoMethod::Paper;
        params.filter = AoFilter::Auto;
        params.normalize = AoNormalize::Paper;
        paper = bakeAo(depth, params);
        Image height = depth;
        for (float& v : height.pixels()) v = 1.0f - v;
        writePng(out / "ao_methods_stone_bricks.png",
                 strip({height, sweep, brute, paper, scaledDifference(sweep, brute, 20.0f),
                        scaledDifference(paper, brute, 5.0f)}),
                 {PngBitDepth::Eight, true});
        const Stats s = compare(sweep, brute);
        const Stats p = compare(paper, brute);
        std::printf("stone-bricks 256^2: sweep %.3f s, brute %.3f s (%.1fx)\n", tSweep, tBrute,
                    tBrute / tSweep);
        std::printf("  sweep - brute: RMSE %.5f bias %+.5f max %.4f\n", s.rmse, s.bias, s.maxAbs);
        std::printf("  paper as written - brute: RMSE %.5f bias %+.5f max %.4f\n\n", p.rmse, p.bias,
                    p.maxAbs);
    }

    // 2. Sweep against the exact walk on every pattern at 256^2.
    std::printf("| pattern | brute mean AO | sweep − brute: RMSE / bias / max abs | brute s | sweep s |\n");
    std::printf("|---|---|---|---|---|\n");
    for (const PatternInfo& info : patternList()) {
        if (!all) break;
        const Image depth = makePattern(info.name, {256, 1, kDefaultDepthScale}).depth;
        AoParams params;
        params.filter = AoFilter::None;
        Image sweep, brute;
        params.method = AoMethod::Sweep;
        const double tSweep = seconds([&] { sweep = bakeAo(depth, params); });
        params.method = AoMethod::Brute;
        const double tBrute = seconds([&] { brute = bakeAo(depth, params); });
        double mean = 0.0;
        for (const float v : brute.pixels()) mean += static_cast<double>(v);
        mean /= static_cast<double>(brute.pixels().size());
        const Stats s = compare(sweep, brute);
        std::printf("| %s | %.4f | %.5f / %+.5f / %.4f | %.2f | %.3f |\n", info.name.c_str(), mean, s.rmse,
                    s.bias, s.maxAbs, tBrute, tSweep);
    }

    // 3. Layer combinations against the AO of the composed depth, for the example materials at 512^2.
    std::printf(
        "\n| material | exact mean AO | multiply − exact: bias / mean abs / max abs | min − exact: bias / "
        "mean abs / max abs |\n|---|---|---|---|\n");
    for (const char* name : {"shaped_fabric.json", "shaped_metal.json", "three_layers.json"}) {
        Material material = readMaterial(examples / name);
        material.compose.resolution = 512;
        const std::vector<CompositionLayer> layers = loadLayers(material);
        const Composition composition = compose(layers, material.compose);
        AoParams params;
        params.filter = AoFilter::None;
        const Image exact = metaReliefAo(layers, material.compose, composition, MetaAoMode::Exact, params);
        const Image multiply =
            metaReliefAo(layers, material.compose, composition, MetaAoMode::Multiply, params);
        const Image minimum = metaReliefAo(layers, material.compose, composition, MetaAoMode::Min, params);
        double mean = 0.0;
        for (const float v : exact.pixels()) mean += static_cast<double>(v);
        mean /= static_cast<double>(exact.pixels().size());
        const Stats m = compare(multiply, exact);
        const Stats n = compare(minimum, exact);
        std::printf("| %s | %.4f | %+.4f / %.4f / %.4f | %+.4f / %.4f / %.4f |\n", name, mean, m.bias,
                    m.meanAbs, m.maxAbs, n.bias, n.meanAbs, n.maxAbs);
        if (std::string(name) == "three_layers.json") {
            // The top-left quarter at full resolution, differences x 2.
            auto crop = [](const Image& image) {
                Image c(256, 256, 1);
                for (int y = 0; y < 256; ++y)
                    for (int x = 0; x < 256; ++x) c.at(x, y) = image.at(x, y);
                return c;
            };
            writePng(out / "ao_combine_three_layers.png",
                     strip({crop(exact), crop(multiply), crop(minimum),
                            scaledDifference(crop(multiply), crop(exact), 2.0f),
                            scaledDifference(crop(minimum), crop(exact), 2.0f)}),
                     {PngBitDepth::Eight, true});
        }
    }
    return 0;
}
