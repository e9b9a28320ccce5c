#include "strata/relief/patterns.h"

#include "pattern_common.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

namespace strata {

namespace {

using GeneratorFactory = std::unique_ptr<pattern::Generator> (*)(std::uint32_t);

struct PatternEntry {
    PatternInfo info;
    GeneratorFactory make;
};

// The order is part of the interface (`strata pattern --list`, docs/patterns.md, the contact sheet):
// the paper's Fig. 10 textures first, then the others. Append; do not reorder.
const std::vector<PatternEntry>& registry() {
    static const std::vector<PatternEntry> entries{
        {{"base", "coarse shaped relief: a few large smooth rounded bumps (the paper's Base)"},
         pattern::makeBase},
        {{"fabric", "plain-weave cloth: round threads over and under one another, fine fibre twist"},
         pattern::makeFabric},
        {{"jeans", "3/1 twill denim: indigo warp in diagonal wales over a white weft"}, pattern::makeJeans},
        {{"metal", "diamond tread plate: raised lozenges turned +-45 degrees on brushed steel"},
         pattern::makeMetal},
        {{"cushion", "tufted leather cushion: pillowy diamonds pulled down by deep buttons"},
         pattern::makeCushion},
        {{"mini-bricks", "small 2:1 bricks in running bond with deep mortar joints"},
         pattern::makeMiniBricks},
        {{"stone-bricks", "irregular rounded stones set in deep mortar"}, pattern::makeStoneBricks},
        {{"scales", "overlapping round scales in offset rows, each rising to a free rim"},
         pattern::makeScales},
        {{"hex-tiles", "hexagonal glazed ceramic tiles in grout"}, pattern::makeHexTiles},
        {{"wood-planks", "floor boards with grooves, staggered joints and growth-ring grain"},
         pattern::makeWoodPlanks},
    };
    return entries;
}

const PatternEntry* findPattern(const std::string& name) {
    const auto& entries = registry();
    const auto it = std::find_if(entries.begin(), entries.end(),
                                 [&](const PatternEntry& entry) { return entry.info.name == name; });
    return it == entries.end() ? nullptr : &*it;
}

struct DepthRange {
    double min;
    double max;
};

// Generators give depth in their own units; makePattern maps it to [0, 1] (CONVENTIONS §2) with the
// extremes found on a fixed 256 x 256 grid of texel centres, whatever the output size. Normalising
// each output by its own extremes instead would make depth depend on the resolution: a small image
// averages away narrow extremes (the holes between threads, say) and would be stretched more.
// Finer sampling may find values slightly beyond these extremes; they are clamped.
DepthRange referenceDepthRange(const pattern::Generator& generator) {
    constexpr int kGrid = 256;
    std::vector<DepthRange> rowRanges(kGrid);
    parallelFor(0, kGrid, [&](int y) {
        DepthRange range{std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest()};
        for (int x = 0; x < kGrid; ++x) {
            const double depth = generator.evaluate({(x + 0.5) / kGrid, 1.0 - (y + 0.5) / kGrid}).depth;
            range.min = std::min(range.min, depth);
            range.max = std::max(range.max, depth);
        }
        rowRanges[static_cast<std::size_t>(y)] = range;
    });
    DepthRange range = rowRanges.front();
    for (const DepthRange& row : rowRanges) {
        range.min = std::min(range.min, row.min);
        range.max = std::max(range.max, row.max);
    }
    return range;
}

std::string knownNames() {
    std::string names;
    for (const PatternInfo& info : patternList()) names += (names.empty() ? "" : ", ") + info.name;
    return names;
}

}  // namespace

const std::vector<PatternInfo>& patternList() {
    static const std::vector<PatternInfo> list = [] {
        std::vector<PatternInfo> infos;
        for (const PatternEntry& entry : registry()) infos.push_back(entry.info);
        return infos;
    }();
    return list;
}

bool isPattern(const std::string& name) {
    return findPattern(name) != nullptr;
}

ReliefTexture makePattern(const std::string& name, const PatternParams& params) {
    const PatternEntry* entry = findPattern(name);
    if (entry == nullptr)
        throw Error(ErrorKind::InvalidInput,
                    "unknown pattern '" + name + "'; known patterns: " + knownNames());
    if (params.size < kMinPatternSize || params.size > kMaxPatternSize) {
        std::ostringstream message;
        message << "pattern '" << name << "': size " << params.size << " is outside [" << kMinPatternSize
                << ", " << kMaxPatternSize << "]";
        throw Error(ErrorKind::InvalidInput, message.str());
    }
    if (!std::isfinite(params.depthScale) || params.depthScale <= 0.0) {
        std::ostringstream message;
        message << "pattern '" << name << "': depth scale " << params.depthScale << " must be positive";
        throw Error(ErrorKind::InvalidInput, message.str());
    }

    const std::unique_ptr<pattern::Generator> generator = entry->make(params.seed);
    const DepthRange range = referenceDepthRange(*generator);
    const double toUnit = range.max > range.min ? 1.0 / (range.max - range.min) : 0.0;
    const int size = params.size;
    // Each texel is the average of n x n samples of the continuous pattern over its footprint (a box
    // filter), n = 512 / size clamped to [1, 8]: every size up to 512 that divides 512 is the exact
    // area average of the same 512 x 512 point samples, so it equals resample() of a larger one, and
    // thin features (mortar, threads) show as partial depth instead of aliasing. From 512 up, one
    // sample at each texel centre. The cost is at most 512^2 evaluations below 512.
    const int n = std::clamp(512 / size, 1, 8);
    const double weight = 1.0 / (n * n);
    ReliefTexture texture;
    texture.depth = Image(size, size, 1);
    texture.color = Image(size, size, 3);
    parallelForChunks(0, size, [&](int rowBegin, int rowEnd) {
        for (int y = rowBegin; y != rowEnd; ++y)
            for (int x = 0; x < size; ++x) {
                double d = 0.0;
                pattern::Vec3 c(0.0);
                for (int sy = 0; sy < n; ++sy)
                    for (int sx = 0; sx < n; ++sx) {
                        // Texel (x, y) covers u in [x, x + 1) / W and v in (1 - (y + 1) / H, 1 - y / H].
                        const pattern::Vec2 uv((x + (sx + 0.5) / n) / size,
                                               1.0 - (y + (sy + 0.5) / n) / size);
                        const pattern::Sample sample = generator->evaluate(uv);
                        d += sample.depth;
                        c += sample.color;
                    }
                const double unitDepth = (d * weight - range.min) * toUnit;
                texture.depth.at(x, y) = static_cast<float>(std::clamp(unitDepth, 0.0, 1.0));
                for (int k = 0; k < 3; ++k)
                    texture.color.at(x, y, k) = static_cast<float>(std::clamp(c[k] * weight, 0.0, 1.0));
            }
    });
    texture.normal = normalsFromDepth(texture.depth, params.depthScale);
    texture.depthScale = params.depthScale;
    return texture;
}

}  // namespace strata
