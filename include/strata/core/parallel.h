// The parallel loop of the whole code base (as pbrt-v4's ParallelFor): oneTBB's work-stealing scheduler
// under one interface, so that no module writes its own wrapper.
//
// parallelForChunks(begin, end, body, grain) calls body(chunkBegin, chunkEnd) on disjoint chunks that cover
// [begin, end) exactly once, from oneTBB's worker threads and the calling thread, and returns when all have
// run. Chunks hold at least `grain` indices unless fewer remain (grain >= 1; oneTBB's auto partitioner picks
// their size). Which thread runs which chunk, and the chunks' bounds, vary from run to run: a body must not
// depend on them (write to disjoint outputs, or reduce per index). An exception thrown by a body cancels
// the chunks not started yet and is rethrown to the caller. An empty range (end <= begin) calls nothing.
//
// parallelFor(begin, end, body) calls body(i) once for every i in [begin, end), the same way.
#pragma once

#include <cstdint>
#include <functional>

namespace strata {

namespace detail {
void runParallelChunks(std::int64_t begin, std::int64_t end, std::int64_t grain,
                       const std::function<void(std::int64_t, std::int64_t)>& body);
}  // namespace detail

// Index: any integer type (int, std::size_t, ...); the body gets indices of that type.
template <typename Index, typename Body>
void parallelForChunks(Index begin, Index end, const Body& body, Index grain = 1) {
    detail::runParallelChunks(static_cast<std::int64_t>(begin), static_cast<std::int64_t>(end),
                              static_cast<std::int64_t>(grain), [&body](std::int64_t from, std::int64_t to) {
                                  body(static_cast<Index>(from), static_cast<Index>(to));
                              });
}

template <typename Index, typename Body>
void parallelFor(Index begin, Index end, const Body& body) {
    parallelForChunks(begin, end, [&body](Index from, Index to) {
        for (Index i = from; i < to; ++i) body(i);
    });
}

}  // namespace strata
