// Surface patterns: base (the paper's coarse shaped relief), metal (tread plate), scales and wood-planks.
#include "pattern_common.h"

#include <array>
#include <limits>
#include <numbers>

namespace strata::pattern {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInvSqrt2 = 1.0 / std::numbers::sqrt2;

// The meta-relief paper's "Base" (Figs. 2-3, left): a coarse relief of a few large, smooth rounded
// bumps on which finer patterns are laid. Here: 3 x 3 domes on a jittered grid, each slightly
// elliptical and of its own size and height, merged with a smooth maximum so that the valleys
// between them are rounded too, over a gentle low-frequency undulation.
class Base final : public Generator {
public:
    explicit Base(std::uint32_t seed) : mNoiseKey(streamKey(seed, 2)) {
        Rng rng(streamKey(seed, 1));
        for (int j = 0; j < kGrid; ++j)
            for (int i = 0; i < kGrid; ++i) {
                Dome& dome = mDomes[static_cast<std::size_t>(j * kGrid + i)];
                dome.center = Vec2((i + 0.5 + rng.uniform(-0.15, 0.15)) / kGrid,
                                   (j + 0.5 + rng.uniform(-0.15, 0.15)) / kGrid);
                dome.radius = rng.uniform(0.62, 0.78) / kGrid;
                dome.height = rng.uniform(0.75, 1.0);
                const double angle = rng.uniform(0.0, kPi);
                const double stretch = rng.uniform(1.0, 1.25);
                dome.axis = Vec2(std::cos(angle), std::sin(angle));
                dome.stretch = stretch;
            }
    }

    Sample evaluate(Vec2 uv) const override {
        double height = 0.0;
        for (const Dome& dome : mDomes) {
            const Vec2 d(wrapDelta(uv.x - dome.center.x), wrapDelta(uv.y - dome.center.y));
            // Elliptical distance: squeezed along the dome's axis.
            const double along = glm::dot(d, dome.axis) / dome.stretch;
            const double across = dome.axis.x * d.y - dome.axis.y * d.x;
            const double t2 = (along * along + across * across) / (dome.radius * dome.radius);
            // (1 - t^2)^2: a rounded cap that meets the ground with zero slope.
            const double bump = t2 < 1.0 ? dome.height * (1.0 - t2) * (1.0 - t2) : 0.0;
            height = smoothMax(height, bump, 0.15);
        }
        const double undulation = periodicFbm(uv, 2, 2, 3, mNoiseKey);
        height += 0.08 * undulation;

        // Clay: light on the crowns, darker in the valleys.
        const double up = clamp01(height);
        Vec3 color = glm::mix(rgb(0.42, 0.29, 0.21), rgb(0.86, 0.72, 0.56), up);
        color *= 1.0 + 0.05 * periodicFbm(uv, 8, 8, 3, mNoiseKey + 1);
        return {-height, color};
    }

private:
    struct Dome {
        Vec2 center;
        Vec2 axis;
        double radius;
        double stretch;
        double height;
    };
    static constexpr int kGrid = 3;
    std::array<Dome, kGrid * kGrid> mDomes{};
    std::uint64_t mNoiseKey;
};

// Diamond (tread) plate: raised lozenges on a flat steel plate, on a square grid, alternately
// turned +45 and -45 degrees in a checkerboard, as rolled anti-slip plate is.
class Metal final : public Generator {
public:
    explicit Metal(std::uint32_t seed)
        : mBrushKey(streamKey(seed, 1)), mDentKey(streamKey(seed, 2)), mGrimeKey(streamKey(seed, 3)) {
        Rng rng(streamKey(seed, 4));
        mOffset = Vec2(rng.uniform(), rng.uniform());
    }

    Sample evaluate(Vec2 uv) const override {
        const Vec2 p = (uv + mOffset) * static_cast<double>(kCells);
        const int i = floorInt(p.x);
        const int j = floorInt(p.y);
        const Vec2 local = p - Vec2(i + 0.5, j + 0.5);
        // kCells is even, so the checkerboard of orientations repeats across the tile.
        const double sign = ((i + j) & 1) == 0 ? 1.0 : -1.0;
        const double along = (local.x + sign * local.y) * kInvSqrt2;
        const double across = (-sign * local.x + local.y) * kInvSqrt2;
        // A lozenge: half-width tapering from kHalfWidth in the middle to a point at the ends.
        const double s = along / kHalfLength;
        double lozenge = 0.0;
        if (std::abs(s) < 1.0) {
            const double halfWidth = kHalfWidth * (1.0 - s * s);
            const double q = across / halfWidth;
            // Round cross-section, flattened a little at the top.
            if (std::abs(q) < 1.0) lozenge = std::pow(1.0 - q * q, 0.35) * std::pow(1.0 - s * s, 0.15);
        }
        // The plate: faint rolling dents and brushing streaks along u.
        const double dents = periodicFbm(uv, 3, 3, 3, mDentKey);
        const double brush = periodicFbm(uv, 2, 128, 2, mBrushKey);
        const double plate = 0.03 * dents + 0.012 * brush;
        const double height = std::max(plate, 0.03 * dents + lozenge);

        const double grime = smoothstep(0.0, 0.8, periodicFbm(uv, 4, 4, 4, mGrimeKey));
        Vec3 color = rgb(0.52, 0.53, 0.55) * (1.0 + 0.12 * brush) * (1.0 - 0.22 * grime);
        // Lozenge tops are polished by wear; their flanks are a little darker.
        if (lozenge > 0.0)
            color = glm::mix(color * 0.9, rgb(0.78, 0.79, 0.80), smoothstep(0.5, 0.95, lozenge));
        return {-height, color};
    }

private:
    static constexpr int kCells = 6;
    static constexpr double kHalfLength = 0.5;  // in cells; neighbours' tips stay 0.3 cells apart
    static constexpr double kHalfWidth = 0.15;
    std::uint64_t mBrushKey;
    std::uint64_t mDentKey;
    std::uint64_t mGrimeKey;
    Vec2 mOffset;
};

// Overlapping scales (fish, or dragon): rows of round scales, each row shifted by half a scale and
// lying on top of the row below it, like roof shingles. A scale rises from where it emerges under
// the rims of the row above to its own free rim, which rounds off and drops to the next scale.
class Scales final : public Generator {
public:
    explicit Scales(std::uint32_t seed) : mScaleKey(streamKey(seed, 1)), mRidgeKey(streamKey(seed, 2)) {
        Rng rng(streamKey(seed, 3));
        mOffset = Vec2(rng.uniform(), rng.uniform());
    }

    Sample evaluate(Vec2 uv) const override {
        const Vec2 p = uv + mOffset;
        const int baseRow = floorInt(p.y / kRowStep);
        // The visible scale is the highest row whose disc contains p (rows further up lie on top).
        int row = std::numeric_limits<int>::min();
        Vec2 center{};
        int column = 0;
        for (int k = baseRow + 3; k >= baseRow - 2 && row == std::numeric_limits<int>::min(); --k)
            for (int c = -1; c <= 1; ++c) {
                const Vec2 centre = scaleCentre(k, c, p);
                const Vec2 d = p - centre;
                if (glm::dot(d, d) < kRadius * kRadius) {
                    row = k;
                    center = centre;
                    column = nearestColumn(k, p) + c;
                    break;
                }
            }
        if (row == std::numeric_limits<int>::min()) return {1.0, rgb(0.05, 0.08, 0.07)};

        // How far p is from the rims of the scales above (where this one emerges) and from its own rim.
        double fromAbove = std::numeric_limits<double>::max();
        for (int k = row + 1; k <= row + 2; ++k)
            for (int c = -1; c <= 1; ++c) {
                const Vec2 d = p - scaleCentre(k, c, p);
                fromAbove = std::min(fromAbove, std::sqrt(glm::dot(d, d)) - kRadius);
            }
        const Vec2 d = p - center;
        const double fromRim = kRadius - std::sqrt(glm::dot(d, d));
        const double t = fromAbove / (fromAbove + fromRim);  // 0 where it emerges, 1 at its rim
        const std::int64_t wrappedRow = wrapIndex(row, kRows);
        const std::int64_t wrappedColumn = wrapIndex(column, kColumns);
        const double r0 = hashUnit(mScaleKey, wrappedColumn, wrappedRow, 0);
        const double r1 = hashUnit(mScaleKey, wrappedColumn, wrappedRow, 1);
        // Faint radial ridges fanning out from the scale's root.
        const double angle = std::atan2(d.x, -d.y);
        const double ridges = std::sin(angle * 14.0 + 2.0 * r1) * smoothstep(0.2, 0.6, t);
        // The face rises by half the relief from root to rim; the other half is the shadow gap under
        // each rim, where the rim rounds down and the scale below rounds up out of it. Keeping the face
        // shallow keeps its normals moderate at the default depth scale.
        double height = (0.5 + 0.5 * std::pow(t, 0.8)) * (0.94 + 0.06 * r0);
        height *= roundedEdge(fromRim / (0.2 * kRadius)) * roundedEdge(fromAbove / (0.25 * kRadius));
        height += 0.012 * ridges + 0.01 * periodicFbm(uv, 32, 32, 2, mRidgeKey);

        // Green-bronze, darker at the root of each scale, with a lighter rim.
        const Vec3 dark(0.05, 0.17, 0.14);
        const Vec3 light = glm::mix(rgb(0.22, 0.52, 0.40), rgb(0.55, 0.56, 0.28), r1);
        Vec3 color = glm::mix(dark, light, smoothstep(0.0, 0.9, t)) * (0.9 + 0.2 * r0);
        color += rgb(0.12, 0.10, 0.04) * smoothstep(0.85, 1.0, t) *
                 (1.0 - smoothstep(0.0, 0.3, fromRim / kRadius));
        return {-height, color};
    }

private:
    int nearestColumn(int row, Vec2 p) const {
        const double shift = (wrapIndex(row, kRows) & 1) != 0 ? 0.5 : 0.0;
        return floorInt(p.x * kColumns - shift);
    }
    // Centre of scale (row, nearestColumn(row, p) + c), unwrapped.
    Vec2 scaleCentre(int row, int c, Vec2 p) const {
        const double shift = (wrapIndex(row, kRows) & 1) != 0 ? 0.5 : 0.0;
        const int column = nearestColumn(row, p) + c;
        return {(column + 0.5 + shift) / kColumns, (row + 0.5) * kRowStep};
    }

    static constexpr int kColumns = 8;
    static constexpr int kRows = 2 * kColumns;  // even, so the half-scale shift of odd rows repeats
    static constexpr double kRowStep = 1.0 / kRows;
    static constexpr double kRadius = 0.62 / kColumns;
    std::uint64_t mScaleKey;
    std::uint64_t mRidgeKey;
    Vec2 mOffset;
};

// Floor boards: eight rows of planks running along u, each a tile long and cut at a random place,
// with grooves between them and a flat-sawn growth-ring grain that wanders along the plank.
class WoodPlanks final : public Generator {
public:
    explicit WoodPlanks(std::uint32_t seed)
        : mPlankKey(streamKey(seed, 1)), mGrainKey(streamKey(seed, 2)), mStreakKey(streamKey(seed, 3)) {
        Rng rng(streamKey(seed, 4));
        for (double& cut : mCuts) cut = rng.uniform();
        mOffsetV = rng.uniform();
    }

    Sample evaluate(Vec2 uv) const override {
        const double y = (uv.y + mOffsetV) * kRows;
        const int rowUnwrapped = floorInt(y);
        const auto row = static_cast<int>(wrapIndex(rowUnwrapped, kRows));
        const double across = y - rowUnwrapped;  // 0 .. 1 across the plank
        // Position along the plank from its cut; everything below is a function of it, so it repeats.
        const double along = fract(uv.x - mCuts[static_cast<std::size_t>(row)]);
        const double edge = std::min(std::min(along, 1.0 - along), std::min(across, 1.0 - across) / kRows);

        const double r0 = hashUnit(mPlankKey, row, 0);
        const double r1 = hashUnit(mPlankKey, row, 1);
        const double r2 = hashUnit(mPlankKey, row, 2);
        // Growth rings: stripes along the plank whose position across it is bent by low-frequency noise,
        // sampled at a per-plank offset so that no two planks share a grain.
        const Vec2 grainPoint(along, across / kRows + r0);
        const double bend = periodicFbm(grainPoint, 2, 10, 3, mGrainKey);
        const double ring = fract(across * (5.0 + 5.0 * r1) + 1.8 * bend + 10.0 * r2);
        // Late wood (the dark, hard line of each ring) stands a little proud after wear.
        const double lateWood = smoothstep(0.62, 0.82, ring) * (1.0 - smoothstep(0.88, 1.0, ring));
        const double streaks = periodicFbm(Vec2(along, uv.y), 4, 128, 2, mStreakKey);

        const double face = 0.92 + 0.05 * r0 + 0.03 * lateWood + 0.01 * streaks;
        const double plank = roundedEdge((edge - kGrooveHalfWidth) / kBevel) * face;
        const double height = std::max(plank, 0.05);

        Vec3 color;
        if (plank > 0.05) {
            const Vec3 tone = glm::mix(rgb(0.60, 0.40, 0.24), rgb(0.80, 0.60, 0.38), r0);
            color = tone * (1.0 - 0.3 * lateWood) * (0.94 + 0.08 * streaks + 0.12 * (r1 - 0.5));
            color *= 0.75 + 0.25 * smoothstep(kGrooveHalfWidth, kGrooveHalfWidth + kBevel, edge);
        } else {
            color = rgb(0.16, 0.10, 0.06);
        }
        return {-height, color};
    }

private:
    static constexpr int kRows = 8;
    static constexpr double kGrooveHalfWidth = 0.005;
    static constexpr double kBevel = 0.008;
    std::array<double, kRows> mCuts{};
    double mOffsetV = 0.0;
    std::uint64_t mPlankKey;
    std::uint64_t mGrainKey;
    std::uint64_t mStreakKey;
};

}  // namespace

std::unique_ptr<Generator> makeBase(std::uint32_t seed) {
    return std::make_unique<Base>(seed);
}
std::unique_ptr<Generator> makeMetal(std::uint32_t seed) {
    return std::make_unique<Metal>(seed);
}
std::unique_ptr<Generator> makeScales(std::uint32_t seed) {
    return std::make_unique<Scales>(seed);
}
std::unique_ptr<Generator> makeWoodPlanks(std::uint32_t seed) {
    return std::make_unique<WoodPlanks>(seed);
}

}  // namespace strata::pattern
