// Textile patterns: fabric (plain weave), jeans (3/1 twill denim) and cushion (tufted upholstery).
#include "pattern_common.h"

#include <numbers>

namespace strata::pattern {

namespace {

constexpr double kPi = std::numbers::pi;

// A woven cloth on an n x n grid of thread crossings: warp thread i runs along v in column i, weft
// thread j along u in row j, and at crossing (i, j) the warp lies over the weft where over(i, j).
// Each thread is a tube of round cross-section whose height follows the weave: up where it passes
// over, down where it passes under, blended with a smoothstep between crossing centres. The visible
// surface is the higher of the two threads (or the floor between them).
struct WeaveHit {
    double height;  // in [-lift - 0.3 thickness, lift + thickness]
    bool warp;      // which thread is on top here (meaningless in a gap)
    bool gap;       // between threads
    int thread;     // the visible thread's index
    double along;   // coordinate along the visible thread, in crossings
    double across;  // -1 .. 1 across the visible thread
};

struct WeaveShape {
    int threads;           // per tile each way; a multiple of the weave's repeat so the tile repeats
    double warpHalfWidth;  // in crossings (a crossing is 1)
    double weftHalfWidth;
    double lift;       // how far a thread rises and sinks around its centre line
    double thickness;  // the tube's radius in height units
};

// over(i, j) for indices already wrapped to [0, threads).
template <typename Over>
WeaveHit weave(Vec2 uv, const WeaveShape& shape, Over over) {
    const int n = shape.threads;
    const double x = uv.x * n;
    const double y = uv.y * n;
    const int column = floorInt(x);
    const int row = floorInt(y);
    const auto wrapped = [n](int i) { return static_cast<int>(wrapIndex(i, n)); };
    const int warpIndex = wrapped(column);
    const int weftIndex = wrapped(row);

    // The vertical position of a thread along its length: +1 over, -1 under at crossing centres.
    const auto lift = [&](double t, auto state) {
        const double s = t - 0.5;
        const int c = floorInt(s);
        const double w = smoothstep(0.0, 1.0, s - c);
        return state(c) + (state(c + 1) - state(c)) * w;
    };
    const double warpLift = lift(y, [&](int c) { return over(warpIndex, wrapped(c)) ? 1.0 : -1.0; });
    const double weftLift = lift(x, [&](int c) { return over(wrapped(c), weftIndex) ? -1.0 : 1.0; });

    const double warpAcross = (x - column - 0.5) / shape.warpHalfWidth;
    const double weftAcross = (y - row - 0.5) / shape.weftHalfWidth;
    // The gaps between threads are only a little deeper than the lowest thread: they are small (a texel
    // at size 64), and a deep narrow hole would spend the depth range on something a small image
    // averages away.
    const double floor = -shape.lift - 0.3 * shape.thickness;
    const auto tube = [&](double across, double liftValue) {
        if (std::abs(across) >= 1.0) return floor;
        return shape.lift * liftValue + shape.thickness * std::sqrt(1.0 - across * across);
    };
    const double warpHeight = tube(warpAcross, warpLift);
    const double weftHeight = tube(weftAcross, weftLift);
    if (warpHeight <= floor && weftHeight <= floor) return {floor, true, true, 0, 0.0, 0.0};
    if (warpHeight >= weftHeight) return {warpHeight, true, false, warpIndex, y, warpAcross};
    return {weftHeight, false, false, weftIndex, x, weftAcross};
}

// Spun yarn: fibres twisted around the thread's axis show as fine ridges slanted across it.
double twistRidges(const WeaveHit& hit, double ridgesPerCrossing) {
    return std::sin(2.0 * kPi * (hit.along * ridgesPerCrossing + 0.35 * hit.across));
}

class Fabric final : public Generator {
public:
    explicit Fabric(std::uint32_t seed)
        : mFibreKey(streamKey(seed, 1)), mThreadKey(streamKey(seed, 2)), mBlotchKey(streamKey(seed, 3)) {
        // A random placement of the weave in the tile, so that no thread boundary is tied to its edge.
        Rng rng(streamKey(seed, 4));
        mOffset = Vec2(rng.uniform(), rng.uniform());
    }

    Sample evaluate(Vec2 uv) const override {
        const WeaveHit hit = weave(uv + mOffset, kShape, [](int i, int j) { return ((i + j) & 1) == 0; });
        const double fuzz = periodicFbm(uv, 32, 32, 2, mFibreKey);
        double height = hit.height + 0.05 * fuzz;
        if (!hit.gap) height += 0.045 * twistRidges(hit, 3.0);
        const double top = kShape.lift + kShape.thickness;
        const double shade = 0.5 + 0.5 * clamp01((height + top) / (2.0 * top));
        Vec3 color = rgb(0.16, 0.14, 0.12);  // the dark gaps between threads
        if (!hit.gap) {
            // Threads of one colour each way, each thread a little lighter or darker (uneven dyeing).
            const double variation = 0.92 + 0.14 * hashUnit(mThreadKey, hit.warp ? 0 : 1, hit.thread);
            const Vec3 base = hit.warp ? rgb(0.83, 0.77, 0.64) : rgb(0.62, 0.44, 0.33);
            color = base * (variation * shade);
        }
        color *= 1.0 + 0.06 * periodicFbm(uv, 4, 4, 3, mBlotchKey);
        return {-height, color};
    }

private:
    static constexpr WeaveShape kShape{12, 0.40, 0.44, 0.45, 0.38};
    std::uint64_t mFibreKey;
    std::uint64_t mThreadKey;
    std::uint64_t mBlotchKey;
    Vec2 mOffset;
};

class Jeans final : public Generator {
public:
    explicit Jeans(std::uint32_t seed)
        : mFibreKey(streamKey(seed, 1)),
          mThreadKey(streamKey(seed, 2)),
          mFadeKey(streamKey(seed, 3)),
          mSlubKey(streamKey(seed, 4)) {
        Rng rng(streamKey(seed, 5));
        mOffset = Vec2(rng.uniform(), rng.uniform());
    }

    Sample evaluate(Vec2 uv) const override {
        // 3/1 twill: warp i passes over three wefts, then under one, one weft later than warp i - 1.
        // The shift by one per thread is what draws denim's diagonal wales.
        const WeaveHit hit =
            weave(uv + mOffset, kShape, [](int i, int j) { return wrapIndex(j - i, 4) != 3; });
        const double fuzz = periodicFbm(uv, 40, 40, 2, mFibreKey);
        double height = hit.height + 0.05 * fuzz;
        if (!hit.gap) height += 0.04 * twistRidges(hit, 2.0);
        const double top = kShape.lift + kShape.thickness;
        const double up = clamp01((height + top) / (2.0 * top));
        Vec3 color = rgb(0.05, 0.07, 0.13);
        if (!hit.gap) {
            if (hit.warp) {
                // Indigo warp, ring-dyed: the tops of the threads wear lighter. Slubs (thicker,
                // lighter stretches of yarn) come as noise along each thread.
                const double slub = periodicNoise(hit.along * 0.5, hit.thread * 7.31, kShape.threads / 2,
                                                  kShape.threads * 8, mSlubKey);
                const double variation = 0.9 + 0.2 * hashUnit(mThreadKey, 0, hit.thread) + 0.12 * slub;
                color = glm::mix(rgb(0.06, 0.10, 0.25), rgb(0.27, 0.39, 0.62), up) * variation;
            } else {
                color = rgb(0.74, 0.73, 0.68) * (0.45 + 0.45 * up);
            }
        }
        // Wear: broad lighter patches, as on washed denim.
        const double fade = smoothstep(0.1, 0.7, periodicFbm(uv, 3, 3, 3, mFadeKey));
        color = glm::mix(color, color * 1.35 + rgb(0.03, 0.03, 0.03), 0.4 * fade);
        return {-height, color};
    }

private:
    static constexpr WeaveShape kShape{20, 0.47, 0.40, 0.40, 0.40};
    std::uint64_t mFibreKey;
    std::uint64_t mThreadKey;
    std::uint64_t mFadeKey;
    std::uint64_t mSlubKey;
    Vec2 mOffset;
};

// Tufted (Chesterfield) upholstery. Buttons sit on a diamond lattice: with x = u * kColumns and
// y = v * kRows, in rotated coordinates a = x + y, b = x - y the buttons are the integer points, and
// each diamond between four buttons (a unit square in (a, b)) is stuffed into a pillow. The diamonds
// are 1/4 of the tile wide and 1/3 high, the proportions of buttoned upholstery.
class Cushion final : public Generator {
public:
    explicit Cushion(std::uint32_t seed)
        : mCellKey(streamKey(seed, 1)), mGrainKey(streamKey(seed, 2)), mToneKey(streamKey(seed, 3)) {}

    Sample evaluate(Vec2 uv) const override {
        const double x = uv.x * kColumns;
        const double y = uv.y * kRows;
        const double a = x + y;
        const double b = x - y;
        const double cellA = floorFast(a);
        const double cellB = floorFast(b);
        // The pillow: zero along the diamond's edges (the folds between buttons), full in its middle.
        const double pillow = std::sqrt(std::sin(kPi * (a - cellA)) * std::sin(kPi * (b - cellB)));
        // Per-diamond stuffing. The diamond's centre (x, y) = ((A + B + 1) / 2, (A - B) / 2) names it
        // uniquely once 2x and 2y are wrapped to the tile.
        const auto ia = static_cast<std::int64_t>(cellA);
        const auto ib = static_cast<std::int64_t>(cellB);
        const double plump = 0.85 + 0.2 * hashUnit(mCellKey, wrapIndex(ia + ib + 1, 2 * kColumns),
                                                   wrapIndex(ia - ib, 2 * kRows));

        // The nearest button, and the dimple the tuft pulls into the cushion around it (tile units).
        const double buttonA = floorFast(a + 0.5);
        const double buttonB = floorFast(b + 0.5);
        const Vec2 toButton((x - 0.5 * (buttonA + buttonB)) / kColumns,
                            (y - 0.5 * (buttonA - buttonB)) / kRows);
        const double r = std::sqrt(glm::dot(toButton, toButton));
        const double dimple = std::exp(-(r * r) / (kDimpleRadius * kDimpleRadius));
        double height = 0.3 + 0.7 * plump * pillow;
        height = height * (1.0 - dimple) - 0.5 * dimple;
        const double grain = periodicFbm(uv, 48, 48, 2, mGrainKey);
        height += 0.012 * grain;
        bool button = false;
        if (r < kButtonRadius) {
            const double cap = -0.38 + 0.2 * std::sqrt(1.0 - (r / kButtonRadius) * (r / kButtonRadius));
            if (cap > height) {
                height = cap;
                button = true;
            }
        }

        // Oxblood leather, darker where it folds in; the buttons are covered in the same leather.
        const double up = clamp01((height + 0.5) / 1.5);
        Vec3 color = glm::mix(rgb(0.12, 0.03, 0.025), rgb(0.60, 0.17, 0.12), std::pow(up, 0.8));
        color *= 1.0 + 0.08 * periodicFbm(uv, 6, 6, 3, mToneKey) + 0.05 * grain;
        if (button) color = rgb(0.30, 0.07, 0.05) * (0.7 + 0.6 * (height + 0.38) / 0.2);
        return {-height, color};
    }

private:
    static constexpr int kColumns = 4;  // buttons per row
    static constexpr int kRows = 3;     // rows of buttons, counting only the unshifted ones
    static constexpr double kDimpleRadius = 0.06;
    static constexpr double kButtonRadius = 0.02;
    std::uint64_t mCellKey;
    std::uint64_t mGrainKey;
    std::uint64_t mToneKey;
};

}  // namespace

std::unique_ptr<Generator> makeFabric(std::uint32_t seed) {
    return std::make_unique<Fabric>(seed);
}
std::unique_ptr<Generator> makeJeans(std::uint32_t seed) {
    return std::make_unique<Jeans>(seed);
}
std::unique_ptr<Generator> makeCushion(std::uint32_t seed) {
    return std::make_unique<Cushion>(seed);
}

}  // namespace strata::pattern
