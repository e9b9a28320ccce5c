// The shaders' loops on the CPU (include/strata/trace/shader_loops.h): the fetches.
#include "strata/trace/shader_loops.h"

#include "strata/core/check.h"

#include <cmath>

namespace strata {

namespace {

// textureGather of the depth at the centre of cell `cell` (unwrapped, integer-valued), in GL's frame (row j
// is image row H - 1 - j): x = (i, j+1), y = (i+1, j+1), z = (i+1, j), w = (i, j).
shared::vec4 gatherCell(const Image& depth, shared::vec2 cell) {
    const int i = static_cast<int>(std::floor(cell.x));
    const int j = static_cast<int>(std::floor(cell.y));
    const int h = depth.height();
    const auto texel = [&](int x, int y) { return depth.atWrapped(x, h - 1 - y); };
    return {texel(i, j + 1), texel(i + 1, j + 1), texel(i + 1, j), texel(i, j)};
}

shared::vec2 sizeOf(const Image& image) {
    return {static_cast<float>(image.width()), static_cast<float>(image.height())};
}

}  // namespace

bool CpuReliefSearch::reliefBelow(shared::vec2 uv, float depth, bool strict) {
    ++mFetches;
    const double d = mTracer->depthAt(static_cast<double>(uv.x), static_cast<double>(uv.y));
    return strict ? static_cast<double>(depth) > d : static_cast<double>(depth) >= d;
}

CpuMaxMipTraversal::CpuMaxMipTraversal(const std::vector<Image>& levels, const Image& depth)
    : mLevels(&levels), mDepth(&depth) {
    STRATA_CHECK(!levels.empty());
    STRATA_CHECK_EQ(levels[0].width(), depth.width());
    STRATA_CHECK_EQ(levels[0].height(), depth.height());
}

shared::vec2 CpuMaxMipTraversal::reliefSize() {
    return sizeOf(*mDepth);
}

int CpuMaxMipTraversal::maxMipLevels() {
    return static_cast<int>(mLevels->size());
}

float CpuMaxMipTraversal::maxMipNode(shared::ivec2 texel, int level) {
    ++mFetches;
    return (*mLevels)[static_cast<std::size_t>(level)].atWrapped(texel.x, texel.y);
}

shared::vec4 CpuMaxMipTraversal::cellCorners(shared::vec2 cell, shared::vec2 /*size*/) {
    ++mFetches;
    return gatherCell(*mDepth, cell);
}

CpuConeStepping::CpuConeStepping(const Image& coneTexels, float maxRatio, const Image& depth)
    : mCone(&coneTexels), mMaxRatio(maxRatio), mDepth(&depth) {
    STRATA_CHECK_EQ(coneTexels.width(), depth.width());
    STRATA_CHECK_EQ(coneTexels.height(), depth.height());
    STRATA_CHECK_EQ(coneTexels.channels(), 2);
}

shared::vec2 CpuConeStepping::reliefSize() {
    return sizeOf(*mDepth);
}

shared::vec2 CpuConeStepping::coneTexel(shared::ivec2 texel) {
    ++mFetches;
    return {mCone->atWrapped(texel.x, texel.y, 0), mCone->atWrapped(texel.x, texel.y, 1)};
}

float CpuConeStepping::coneMaxRatio() {
    return mMaxRatio;
}

shared::vec4 CpuConeStepping::cellCorners(shared::vec2 cell, shared::vec2 /*size*/) {
    ++mFetches;
    return gatherCell(*mDepth, cell);
}

}  // namespace strata
