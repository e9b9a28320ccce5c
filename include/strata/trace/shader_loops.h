// The shaders' intersection loops on the CPU: the very loops of shaders/shared/relief_search.h, maxmip.h and
// cone.h, compiled as C++ (float, as the GPU runs them), with fetches that read strata Images and count
// themselves. bench_techniques and bench_render count the shaders' texture fetches with them, and
// tests/trace/test_shader_loops.cpp runs them against the exact tracer (heightfield_tracer.h).
//
// Rays are those of the shaders (shared/relief_search.h): entry dp at depth 0, (u, v) travel ds from depth 0
// to depth 1, both in tile coordinates; results are depths in [0, 1]. Frame of the fetches: the GL textures'
// (strata/relief/max_mip.h): cell coordinates c = uv * size - 0.5, row 0 at v = 0, i.e. image row H - 1.
// The fetches read the values they are given as they are; a GL texture holds them rounded to 16 bits
// (uploadMaterial), so pass 16-bit values (quantizeUnorm16) to read what the shader reads.
//
// One fetch is one texture read of the shader: reliefBelow (one read of the height field), maxMipNode
// (texelFetch), coneTexel (texelFetch), cellCorners (textureGather). textureSize and uniforms do not count.
// Each object keeps references to the images and the tracer it is given: they must outlive it. Not thread
// safe (the counter): one object per thread.
#pragma once

#include "shared/cone.h"
#include "shared/maxmip.h"
#include "shared/relief_search.h"
#include "strata/image/image.h"
#include "strata/trace/heightfield_tracer.h"

#include <vector>

namespace strata {

// shared::ReliefSearch (reliefIntersect, reliefLit) reading the exact bilinear height field:
// reliefBelow compares the depth with HeightFieldTracer::depthAt (double) at uv.
class CpuReliefSearch final : public shared::ReliefSearch {
public:
    explicit CpuReliefSearch(const HeightFieldTracer& tracer) : mTracer(&tracer) {}

    bool reliefBelow(shared::vec2 uv, float depth, bool strict) override;

    int fetches() const { return mFetches; }
    void resetFetches() { mFetches = 0; }

private:
    const HeightFieldTracer* mTracer;
    int mFetches = 0;
};

// shared::MaxMipTraversal (maxMipIntersect). levels: the maximum mipmap, maxMipPyramid(depth) (its frame);
// depth: the depth map (1 channel, rows top first as Image stores them), power-of-two sides.
class CpuMaxMipTraversal final : public shared::MaxMipTraversal {
public:
    CpuMaxMipTraversal(const std::vector<Image>& levels, const Image& depth);

    shared::vec2 reliefSize() override;
    int maxMipLevels() override;
    float maxMipNode(shared::ivec2 texel, int level) override;
    shared::vec4 cellCorners(shared::vec2 cell, shared::vec2 size) override;

    int fetches() const { return mFetches; }
    void resetFetches() { mFetches = 0; }

private:
    const std::vector<Image>* mLevels;
    const Image* mDepth;
    int mFetches = 0;
};

// shared::ConeStepping (coneIntersect). coneTexels and maxRatio: packConeMap(depth)'s texels (2 channels,
// its frame) and maxRatio; depth: the depth map (1 channel, rows top first), any size.
class CpuConeStepping final : public shared::ConeStepping {
public:
    CpuConeStepping(const Image& coneTexels, float maxRatio, const Image& depth);

    shared::vec2 reliefSize() override;
    shared::vec2 coneTexel(shared::ivec2 texel) override;
    float coneMaxRatio() override;
    shared::vec4 cellCorners(shared::vec2 cell, shared::vec2 size) override;

    int fetches() const { return mFetches; }
    void resetFetches() { mFetches = 0; }

private:
    const Image* mCone;
    float mMaxRatio;
    const Image* mDepth;
    int mFetches = 0;
};

}  // namespace strata
