// Masonry patterns: mini-bricks (running bond), stone-bricks (irregular stones) and hex-tiles.
// All three are raised blocks with rounded edges standing in a deep joint (mortar or grout).
#include "pattern_common.h"

#include <array>

namespace strata::pattern {

namespace {

// The height profile of a block at distance `edge` (tile units) from its cell's border: the joint is
// `jointHalfWidth` deep on each side, then the block's edge rounds up over `bevel`.
double blockProfile(double edge, double jointHalfWidth, double bevel) {
    return roundedEdge((edge - jointHalfWidth) / bevel);
}

class MiniBricks final : public Generator {
public:
    explicit MiniBricks(std::uint32_t seed)
        : mBrickKey(streamKey(seed, 1)), mRoughKey(streamKey(seed, 2)), mMortarKey(streamKey(seed, 3)) {
        Rng rng(streamKey(seed, 4));
        // A random placement of the bond in the tile, so that no joint is tied to the tile's edge.
        mOffset = Vec2(rng.uniform(), rng.uniform());
    }

    Sample evaluate(Vec2 uv) const override {
        const Vec2 p = uv + mOffset;
        const double y = p.y * kRows;
        const int row = floorInt(y);
        const int wrappedRow = static_cast<int>(wrapIndex(row, kRows));
        // Running bond: every other course shifted by half a brick (kRows is even, so it repeats).
        const double x = p.x * kColumns + ((wrappedRow & 1) != 0 ? 0.5 : 0.0);
        const int column = floorInt(x);
        const int wrappedColumn = static_cast<int>(wrapIndex(column, kColumns));
        const double fx = x - column;
        const double fy = y - row;
        const double edge = std::min(std::min(fx, 1.0 - fx) / kColumns, std::min(fy, 1.0 - fy) / kRows);

        const double r0 = hashUnit(mBrickKey, wrappedColumn, wrappedRow, 0);
        const double r1 = hashUnit(mBrickKey, wrappedColumn, wrappedRow, 1);
        const double r2 = hashUnit(mBrickKey, wrappedColumn, wrappedRow, 2);
        const double rough = periodicFbm(uv, 24, 24, 3, mRoughKey);
        // Bricks stand a little proud of one another and tilt slightly; their faces are rough.
        const double tilt = 0.06 * (r1 - 0.5) * (fx - 0.5) + 0.05 * (r2 - 0.5) * (fy - 0.5);
        const double face = 0.88 + 0.12 * r0 + tilt + 0.05 * rough;
        const double brick = blockProfile(edge, kMortarHalfWidth, kBevel) * face;
        const double mortar = 0.1 + 0.06 * periodicFbm(uv, 48, 48, 2, mMortarKey);
        const double height = std::max(brick, mortar);

        Vec3 color;
        if (brick > mortar) {
            static constexpr std::array<Vec3, 4> kBrickColors{Vec3(0.62, 0.26, 0.17), Vec3(0.54, 0.21, 0.14),
                                                              Vec3(0.70, 0.36, 0.22), Vec3(0.47, 0.25, 0.18)};
            const Vec3 base = kBrickColors[static_cast<std::size_t>(r1 * 4.0)];
            const double speckle = periodicFbm(uv, 96, 96, 1, mRoughKey + 1);
            color = base * (0.9 + 0.2 * r2 + 0.12 * rough + 0.08 * speckle);
            // The rounded edges catch less light and more grime.
            color *= 0.75 + 0.25 * smoothstep(kMortarHalfWidth, kMortarHalfWidth + kBevel, edge);
        } else {
            color = rgb(0.27, 0.26, 0.24) * (0.85 + 0.3 * (mortar - 0.04) / 0.12);
        }
        return {-height, color};
    }

private:
    static constexpr int kColumns = 6;  // bricks per course; 2:1 bricks need kRows = 2 kColumns
    static constexpr int kRows = 12;
    static constexpr double kMortarHalfWidth = 0.09 / kRows;
    static constexpr double kBevel = 0.12 / kRows;
    std::uint64_t mBrickKey;
    std::uint64_t mRoughKey;
    std::uint64_t mMortarKey;
    Vec2 mOffset;
};

class StoneBricks final : public Generator {
public:
    explicit StoneBricks(std::uint32_t seed)
        : mCells(5, 6, 0.28, 0.5, streamKey(seed, 1)),
          mStoneKey(streamKey(seed, 2)),
          mBumpKey(streamKey(seed, 3)),
          mMortarKey(streamKey(seed, 4)),
          mMottleKey(streamKey(seed, 5)) {}

    Sample evaluate(Vec2 uv) const override {
        // The stone borders wander a little (a domain warp of the Voronoi lookup), so that they are
        // not straight lines.
        const Vec2 warp(periodicFbm(uv, 8, 8, 2, mBumpKey + 7), periodicFbm(uv, 8, 8, 2, mBumpKey + 8));
        const CellHit cell = mCells.nearest(uv + 0.012 * warp);
        const double r0 = hashUnit(mStoneKey, cell.column, cell.row, 0);
        const double r1 = hashUnit(mStoneKey, cell.column, cell.row, 1);
        const double r2 = hashUnit(mStoneKey, cell.column, cell.row, 2);
        const double r3 = hashUnit(mStoneKey, cell.column, cell.row, 3);
        const double bumps = periodicFbm(uv, 6, 6, 4, mBumpKey);
        // A rounded stone: its edge falls off over a wide bevel, its face tilts and undulates.
        const double tilt = 2.0 * ((r1 - 0.5) * cell.offset.x + (r2 - 0.5) * cell.offset.y);
        const double face = 0.8 + 0.2 * r0 + tilt + 0.12 * bumps;
        const double stone = blockProfile(cell.edgeDistance, kMortarHalfWidth, kBevel) * face;
        const double mortarNoise = periodicFbm(uv, 40, 40, 3, mMortarKey);
        const double mortar = 0.08 + 0.06 * mortarNoise;
        const double height = std::max(stone, mortar);

        Vec3 color;
        if (stone > mortar) {
            // Greys with a warm or cool cast per stone, mottled.
            const Vec3 warm(0.62, 0.55, 0.46);
            const Vec3 cool(0.50, 0.52, 0.53);
            const double mottle = periodicFbm(uv, 16, 16, 4, mMottleKey);
            color = glm::mix(cool, warm, r3) * (0.78 + 0.35 * r0 + 0.18 * mottle + 0.15 * bumps);
            color *= 0.7 + 0.3 * smoothstep(kMortarHalfWidth, kMortarHalfWidth + kBevel, cell.edgeDistance);
        } else {
            color = rgb(0.21, 0.20, 0.18) * (0.85 + 0.4 * mortarNoise);
        }
        return {-height, color};
    }

private:
    static constexpr double kMortarHalfWidth = 0.009;
    static constexpr double kBevel = 0.035;
    CellLattice mCells;
    std::uint64_t mStoneKey;
    std::uint64_t mBumpKey;
    std::uint64_t mMortarKey;
    std::uint64_t mMottleKey;
};

// Hexagonal ceramic tiles: the Voronoi cells of a 7 x 8 lattice with odd rows shifted by half a cell,
// which are hexagons 1% off regular (a regular hexagon needs rows / columns = 2 / sqrt(3) = 1.155;
// 8 / 7 = 1.143 is the closest small ratio with an even row count).
class HexTiles final : public Generator {
public:
    explicit HexTiles(std::uint32_t seed)
        : mCells(7, 8, 0.0, 0.5, streamKey(seed, 1)),
          mTileKey(streamKey(seed, 2)),
          mGlazeKey(streamKey(seed, 3)),
          mGroutKey(streamKey(seed, 4)) {
        Rng rng(streamKey(seed, 5));
        mOffset = Vec2(rng.uniform(), rng.uniform());
    }

    Sample evaluate(Vec2 uv) const override {
        const CellHit cell = mCells.nearest(glm::fract(uv + mOffset));
        const double r0 = hashUnit(mTileKey, cell.column, cell.row, 0);
        const double r1 = hashUnit(mTileKey, cell.column, cell.row, 1);
        const double r2 = hashUnit(mTileKey, cell.column, cell.row, 2);
        const double r3 = hashUnit(mTileKey, cell.column, cell.row, 3);
        const double glaze = periodicFbm(uv, 12, 12, 3, mGlazeKey);
        // Set tiles sit almost level: small height and tilt differences, a glazed (smooth) face.
        const double tilt = 0.5 * ((r1 - 0.5) * cell.offset.x + (r2 - 0.5) * cell.offset.y);
        const double face = 0.93 + 0.07 * r0 + tilt + 0.01 * glaze;
        const double tile = blockProfile(cell.edgeDistance, kGroutHalfWidth, kBevel) * face;
        const double groutNoise = periodicFbm(uv, 56, 56, 2, mGroutKey);
        const double grout = 0.12 + 0.04 * groutNoise;
        const double height = std::max(tile, grout);

        Vec3 color;
        if (tile > grout) {
            // Mostly cream tiles with a scatter of teal and terracotta ones.
            Vec3 base = rgb(0.86, 0.83, 0.76);
            if (r3 < 0.2)
                base = rgb(0.16, 0.46, 0.50);
            else if (r3 < 0.35)
                base = rgb(0.72, 0.38, 0.24);
            color = base * (0.93 + 0.1 * r0 + 0.06 * glaze);
            color *= 0.72 + 0.28 * smoothstep(kGroutHalfWidth, kGroutHalfWidth + kBevel, cell.edgeDistance);
        } else {
            color = rgb(0.33, 0.32, 0.30) * (0.9 + 0.3 * groutNoise);
        }
        return {-height, color};
    }

private:
    static constexpr double kGroutHalfWidth = 0.0075;
    static constexpr double kBevel = 0.012;
    CellLattice mCells;
    std::uint64_t mTileKey;
    std::uint64_t mGlazeKey;
    std::uint64_t mGroutKey;
    Vec2 mOffset;
};

}  // namespace

std::unique_ptr<Generator> makeMiniBricks(std::uint32_t seed) {
    return std::make_unique<MiniBricks>(seed);
}
std::unique_ptr<Generator> makeStoneBricks(std::uint32_t seed) {
    return std::make_unique<StoneBricks>(seed);
}
std::unique_ptr<Generator> makeHexTiles(std::uint32_t seed) {
    return std::make_unique<HexTiles>(seed);
}

}  // namespace strata::pattern
