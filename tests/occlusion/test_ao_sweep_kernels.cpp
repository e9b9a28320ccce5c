// The sweep's SIMD kernels (8 lanes: SSE2, AVX2; 16 lanes: AVX-512) against each other: every kernel
// this CPU runs must give the horizons of the portable one. CI's machine has AVX-512, so without this
// test the kernels that other machines pick would go untested.
#include "occlusion/horizon_search.h"
#include "strata/core/error.h"
#include "strata/relief/patterns.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

namespace strata {
namespace {

using detail::SweepKernel;

struct Case {
    const char* pattern;
    int width;
    int height;
    double radius;
    int directions;
};

Image depthOf(const Case& c) {
    const Image square = makePattern(c.pattern, {c.width, 1, 0.08}).depth;
    if (c.height == c.width) return square;
    Image depth(c.width, c.height, 1, 0.0f);
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) depth.at(x, y) = square.at(x, y * c.width / c.height);
    return depth;
}

// How many horizons differ, and the largest difference relative to 1 + |tan h|.
struct Difference {
    std::size_t differ = 0;
    double worst = 0.0;
};
Difference difference(const HorizonMap& reference, const HorizonMap& horizons) {
    EXPECT_EQ(horizons.tanHorizon.size(), reference.tanHorizon.size());
    Difference d;
    for (std::size_t i = 0; i < std::min(reference.tanHorizon.size(), horizons.tanHorizon.size()); ++i) {
        const double a = reference.tanHorizon[i];
        const double b = horizons.tanHorizon[i];
        if (a != b) ++d.differ;
        d.worst = std::max(d.worst, std::abs(a - b) / (1.0 + std::abs(a)));
    }
    return d;
}

TEST(AoSweepKernels, EveryKernelGivesThePortableHorizons) {
    // Paired (M even) and unpaired, R from all near field to past a tile, square and not, a map narrower
    // than one 16-lane group; windows read sample by sample (at most kShortWindow samples: the smaller
    // maps) and through hulls (stone-bricks at 192^2, metal at R = 4).
    const Case cases[] = {{"stone-bricks", 192, 192, 1.0, 50}, {"metal", 80, 48, 4.0, 49},
                          {"scales", 64, 64, 0.1, 50},         {"jeans", 96, 64, 1.0, 24},
                          {"hex-tiles", 64, 12, 0.5, 50},      {"base", 64, 64, 0.02, 50}};
    int kernelsRun = 0;
    for (const SweepKernel kernel : {SweepKernel::Avx2, SweepKernel::Avx512}) {
        if (!detail::sweepKernelRuns(kernel)) {
            std::cout << "  " << detail::toString(kernel) << ": not on this CPU\n";
            continue;
        }
        ++kernelsRun;
        for (const Case& c : cases) {
            SCOPED_TRACE(std::string(detail::toString(kernel)) + ", " + c.pattern + " " +
                         std::to_string(c.width) + "x" + std::to_string(c.height) +
                         ", R = " + std::to_string(c.radius) + ", M = " + std::to_string(c.directions));
            const Image depth = depthOf(c);
            AoParams params;
            params.radius = c.radius;
            params.directions = c.directions;
            const HorizonMap reference = detail::sweepHorizons(depth, params, {SweepKernel::Portable});
            const HorizonMap horizons = detail::sweepHorizons(depth, params, {kernel});
            const Difference d = difference(reference, horizons);
            std::cout << "  " << detail::toString(kernel) << " " << c.pattern << ": " << d.differ << " of "
                      << reference.tanHorizon.size() << " differ, worst " << d.worst << "\n";
            EXPECT_EQ(d.differ, 0u);
            const Image ao = detail::sweepAo(depth, params, {kernel});
            const Image aoReference = detail::sweepAo(depth, params, {SweepKernel::Portable});
            EXPECT_TRUE(std::ranges::equal(ao.pixels(), aoReference.pixels()));
        }
    }
    std::cout << "  kernels compared with the portable one: " << kernelsRun << "\n";
}

// Where every window is short (at most 192 samples), the sweep reads them sample by sample instead of
// through hulls: the same highest sample by the same division, so the same numbers but for ties.
TEST(AoSweepKernels, ReadingShortWindowsGivesTheHullsNumbers) {
    const Case cases[] = {
        {"stone-bricks", 96, 96, 1.0, 50}, {"metal", 64, 64, 2.0, 49}, {"scales", 128, 128, 0.1, 50}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.pattern);
        const Image depth = depthOf(c);
        AoParams params;
        params.radius = c.radius;
        params.directions = c.directions;
        const HorizonMap read = detail::sweepHorizons(depth, params);
        const HorizonMap hulls = detail::sweepHorizons(depth, params, {.hullsOnly = true});
        const Difference d = difference(hulls, read);
        std::cout << "  " << c.pattern << ": " << d.differ << " of " << read.tanHorizon.size()
                  << " differ, worst " << d.worst << "\n";
        // Ties: two samples that the texel sees equally high, one of them popped from the hull as
        // collinear, give the same elevation to within float rounding.
        EXPECT_LE(d.worst, 1e-6);
        EXPECT_LE(d.differ, read.tanHorizon.size() / 10000);
    }
}

TEST(AoSweepKernels, AKernelThisCpuLacksIsRefusedByName) {
    for (const SweepKernel kernel : {SweepKernel::Avx2, SweepKernel::Avx512}) {
        if (detail::sweepKernelRuns(kernel)) continue;
        try {
            detail::sweepAo(Image(16, 16, 1, 0.5f), AoParams{}, {kernel});
            ADD_FAILURE() << "expected an error";
        } catch (const Error& error) {
            EXPECT_NE(std::string(error.what()).find(detail::toString(kernel)), std::string::npos)
                << error.what();
        }
    }
    EXPECT_TRUE(detail::sweepKernelRuns(SweepKernel::Portable));
    EXPECT_TRUE(detail::sweepKernelRuns(SweepKernel::Auto));
}

}  // namespace
}  // namespace strata
