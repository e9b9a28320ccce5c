// The built-in mesostructures: their contract (periodic, 1-Lipschitz, within 0 <= z <= H with the top
// voxel layers empty), and the shape each must have (yarns and links that do not interpenetrate, links
// that interlock, open holes, scales and bark that are not height fields).
#include "strata/core/error.h"
#include "strata/gdm/mesostructure.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <string>

namespace strata {
namespace {

// A deterministic uniform [0, 1) sequence (no <random>: the same numbers everywhere).
class Sequence {
public:
    double next() {
        mState = mState * 6364136223846793005ull + 1442695040888963407ull;
        return double(mState >> 11) * 0x1.0p-53;
    }

private:
    std::uint64_t mState = 12345;
};

std::string errorMessage(const std::string& name, const MesostructureParams& params) {
    try {
        makeMesostructure(name, params);
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
        return e.what();
    }
    return "";
}

// The runs of solid along the vertical line at (u, v), sampled every H / 400.
int solidRuns(const Mesostructure& meso, double u, double v) {
    int runs = 0;
    bool inside = false;
    for (int k = 0; k <= 400; ++k) {
        const bool now = meso.distance({u, v, meso.height() * k / 400.0}) < 0.0;
        if (now && !inside) ++runs;
        inside = now;
    }
    return runs;
}

TEST(Mesostructure, ListsTheFiveBuiltInsInOrder) {
    const auto& list = mesostructureList();
    ASSERT_EQ(list.size(), 5u);
    const char* names[] = {"weave", "chain", "grid", "scales", "bark"};
    for (std::size_t n = 0; n < 5; ++n) {
        EXPECT_EQ(list[n].name, names[n]);
        EXPECT_FALSE(list[n].description.empty());
        EXPECT_GT(list[n].defaultHeight, 0.0);
        EXPECT_EQ(makeMesostructure(list[n].name).height(), list[n].defaultHeight);
    }
}

TEST(Mesostructure, RefusesUnknownNamesAndBadHeights) {
    const std::string unknown = errorMessage("tweed", {});
    EXPECT_NE(unknown.find("\"tweed\""), std::string::npos) << unknown;
    for (const auto& info : mesostructureList()) EXPECT_NE(unknown.find(info.name), std::string::npos);
    EXPECT_NE(errorMessage("weave", {-0.25, 1}).find("-0.25"), std::string::npos);
    EXPECT_NE(errorMessage("weave", {std::nan(""), 1}).find("nan"), std::string::npos);
    EXPECT_EQ(makeMesostructure("weave", {0.4, 1}).height(), 0.4);
}

TEST(Mesostructure, EveryBuiltInIsPeriodicLipschitzAndInsideItsShell) {
    for (const auto& info : mesostructureList()) {
        for (const double height : {0.0, 0.1, 0.6}) {
            SCOPED_TRACE(info.name + " at H " + std::to_string(height));
            const Mesostructure meso = makeMesostructure(info.name, {height, 7});
            const double h = meso.height();
            Sequence random;
            for (int n = 0; n < 2000; ++n) {
                const glm::dvec3 p(random.next(), random.next(), (1.4 * random.next() - 0.2) * h);
                const double d = meso.distance(p);
                // u + 1 rounds p.x by at most 2^-52; d is 1-Lipschitz, and the parts' arithmetic adds a few
                // ulps of values below 10: 1e-12 is far above both and far below any feature.
                EXPECT_NEAR(meso.distance(p + glm::dvec3(1, 0, 0)), d, 1e-12);
                EXPECT_NEAR(meso.distance(p + glm::dvec3(0, 1, 0)), d, 1e-12);
                EXPECT_NEAR(meso.distance(p + glm::dvec3(-3, 2, 0)), d, 1e-12);
                // 1-Lipschitz (hence never more than the true distance, the zero set being the surface): a
                // step of 0.01 in a random direction changes d by at most 0.01, up to rounding (1e-12).
                const glm::dvec3 step =
                    0.01 *
                    glm::normalize(glm::dvec3(random.next() - 0.5, random.next() - 0.5, random.next() - 0.5));
                EXPECT_LE(std::abs(meso.distance(p + step) - d), 0.01 + 1e-12);
                const MesostructureSample sample = meso.sample(p);
                EXPECT_EQ(sample.distance, d);
                EXPECT_GE(sample.material, 0);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_GE(sample.albedo[c], 0.0);
                    EXPECT_LE(sample.albedo[c], 1.0);
                }
            }
            // Nothing below z = 0 or above H (1 - 1.5 / 16) (the top voxel layer and a half of a 16-layer
            // grid stay empty), and something inside.
            int inside = 0;
            for (int j = 0; j < 128; ++j)
                for (int i = 0; i < 128; ++i) {
                    const double u = (i + 0.5) / 128.0, v = (j + 0.5) / 128.0;
                    EXPECT_GT(meso.distance({u, v, h * (1.0 - 1.5 / 16.0)}), 0.0) << u << ", " << v;
                    EXPECT_GT(meso.distance({u, v, -1e-9}), 0.0) << u << ", " << v;
                    inside += meso.distance({u, v, 0.5 * h}) < 0.0 ? 1 : 0;
                }
            EXPECT_GT(inside, 0);
        }
    }
}

// No point lies more than `tolerance` inside two parts (partDistance < -tolerance for both).
void expectNoInterpenetration(const Mesostructure& meso, double tolerance) {
    const double h = meso.height();
    for (int k = 0; k < 64; ++k)
        for (int j = 0; j < 96; ++j)
            for (int i = 0; i < 96; ++i) {
                const glm::dvec3 p((i + 0.5) / 96.0, (j + 0.5) / 96.0, (k + 0.5) / 64.0 * h);
                int inside = 0;
                std::string which;
                for (int n = 0; n < meso.partCount(); ++n)
                    if (meso.partDistance(n, p) < -tolerance) {
                        ++inside;
                        which += " " + meso.part(n).name;
                    }
                ASSERT_LE(inside, 1) << "at " << p.x << ", " << p.y << ", " << p.z << ":" << which;
            }
}

TEST(Mesostructure, WeaveYarnsPassOverAndUnderWithoutInterpenetrating) {
    const Mesostructure weave = makeMesostructure("weave");
    ASSERT_EQ(weave.partCount(), 4);
    // The yarns never overlap (mesostructure.cpp: an amplitude A >= 1.07 b suffices, the weave has 1.29 b;
    // sampled at 160^3, every point is at least 0.0023 outside one of any two yarns); 1e-9 is rounding.
    expectNoInterpenetration(weave, 1e-9);
    // Over and under: at the crossing (0.25, 0.25) warp 0 is on top, at (0.75, 0.25) weft 1 is.
    const auto topPart = [&](double u, double v) {
        for (int k = 400; k >= 0; --k) {
            const glm::dvec3 p(u, v, weave.height() * k / 400.0);
            if (weave.distance(p) < 0.0) return weave.part(weave.sample(p).part).name;
        }
        return std::string();
    };
    EXPECT_EQ(topPart(0.25, 0.25), "warp 0");
    EXPECT_EQ(topPart(0.75, 0.25), "weft 1");
    EXPECT_EQ(topPart(0.25, 0.75), "weft 0");
    EXPECT_EQ(topPart(0.75, 0.75), "warp 1");
    // At a crossing both yarns are there, one above the other.
    EXPECT_EQ(solidRuns(weave, 0.25, 0.25), 2);
}

TEST(Mesostructure, ChainLinksInterlockWithoutInterpenetrating) {
    const Mesostructure chain = makeMesostructure("chain");
    ASSERT_EQ(chain.partCount(), 8);
    // Tori are exact; two links come no closer than 0.016 (a link's wire through its neighbour's hole,
    // mesostructure.cpp); 1e-9 is rounding.
    expectNoInterpenetration(chain, 1e-9);
    // Link 0 lies flat at (0.125, 0.25, 0.16), R = 0.17, r = 0.03; link 1 stands at (0.375, 0.25, 0.21) in
    // the u-z plane. Link 1 crosses link 0's plane z = 0.16 at u = 0.375 - sqrt(0.17^2 - 0.05^2) = 0.2125,
    // 0.0875 from link 0's centre: inside its hole (radius R - r = 0.14). And link 0 passes through link 1's
    // hole at (0.295, 0.25, 0.16), 0.094 from link 1's centre.
    const double crossing = 0.375 - std::sqrt(0.17 * 0.17 - 0.05 * 0.05);
    EXPECT_LT(chain.partDistance(1, {crossing, 0.25, 0.16}), 0.0);
    EXPECT_GT(chain.partDistance(0, {crossing, 0.25, 0.16}), 0.0);
    EXPECT_LT(chain.partDistance(0, {0.295, 0.25, 0.16}), 0.0);
    EXPECT_GT(chain.partDistance(1, {0.295, 0.25, 0.16}), 0.0);
    // The link's own hole is open: straight down through the centre of link 0.
    EXPECT_EQ(solidRuns(chain, 0.125, 0.25), 0);
}

TEST(Mesostructure, GridHasOpenHolesAndFusedLayers) {
    const Mesostructure grid = makeMesostructure("grid");
    EXPECT_EQ(solidRuns(grid, 0.5, 0.5), 0);  // a hole, top to bottom
    EXPECT_EQ(solidRuns(grid, 0.0, 0.0), 0);
    EXPECT_EQ(solidRuns(grid, 0.25, 0.25), 1);  // a crossing: the two layers fused into one run
    EXPECT_EQ(solidRuns(grid, 0.5, 0.25), 1);   // a lower rod alone
    EXPECT_LT(grid.distance({0.5, 0.25, 0.065}), 0.0);
    EXPECT_GT(grid.distance({0.5, 0.25, 0.16}), 0.0);
    // Stretched to H = 0.5 the upper rods' axis moves from z = 0.16 to 0.32.
    const Mesostructure tall = makeMesostructure("grid", {0.5, 1});
    EXPECT_LT(tall.distance({0.25, 0.5, 0.32}), 0.0);
    EXPECT_GT(tall.distance({0.25, 0.5, 0.16}), 0.0);
}

// Share of a 64 x 64 set of vertical lines that meet the solid at least `runs` times.
double shareWithRuns(const Mesostructure& meso, int runs) {
    int count = 0;
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i)
            count += solidRuns(meso, (i + 0.5) / 64.0, (j + 0.5) / 64.0) >= runs ? 1 : 0;
    return count / 4096.0;
}

TEST(Mesostructure, ScalesOverlapAndBarkOverhangs) {
    // Not height fields. Scales: a vertical line meets the skin and then two scales, one over the other,
    // over 41% of the tile (scales 0.245 in radius on rows 0.25 apart). Bark: the inner bark and then a cap
    // over its undercut (two runs; one where the stem joins them) over 45% of the tile. A quarter is well
    // below both and far above a height field's zero.
    EXPECT_GT(shareWithRuns(makeMesostructure("scales"), 3), 0.25);
    EXPECT_GT(shareWithRuns(makeMesostructure("bark"), 2), 0.25);
    // Different seeds give different bark; the same seed the same.
    const Mesostructure a = makeMesostructure("bark", {0.0, 1});
    const Mesostructure b = makeMesostructure("bark", {0.0, 2});
    const Mesostructure c = makeMesostructure("bark", {0.0, 1});
    int differ = 0;
    for (int i = 0; i < 64; ++i) {
        const glm::dvec3 p((i + 0.5) / 64.0, 0.3, 0.15);
        differ += a.distance(p) != b.distance(p) ? 1 : 0;
        EXPECT_EQ(a.distance(p), c.distance(p));
    }
    EXPECT_GT(differ, 0);
}

}  // namespace
}  // namespace strata
