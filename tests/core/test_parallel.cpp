// strata::parallelFor and parallelForChunks (strata/core/parallel.h): every index once, chunks that cover the
// range, exceptions that reach the caller.
#include "strata/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace strata {
namespace {

TEST(Parallel, EveryIndexRunsExactlyOnce) {
    // A negative start too: the sweep pads its rows on both sides.
    std::vector<std::atomic<int>> hits(1000);
    parallelFor(-7, 993, [&](int i) { hits[static_cast<std::size_t>(i + 7)].fetch_add(1); });
    for (const auto& h : hits) EXPECT_EQ(h.load(), 1);
}

TEST(Parallel, ChunksCoverTheRangeAndKeepTheGrain) {
    constexpr std::size_t kCount = 10007;  // prime: the last chunk is a remainder
    constexpr std::size_t kGrain = 64;
    std::vector<std::atomic<int>> hits(kCount);
    std::atomic<int> small{0};
    std::atomic<std::int64_t> chunks{0};
    parallelForChunks(
        std::size_t{0}, kCount,
        [&](std::size_t first, std::size_t last) {
            ASSERT_LT(first, last);
            // oneTBB splits a range only while it holds more than `grain` indices, and into halves: no chunk
            // can hold fewer than grain / 2.
            if (last - first < kGrain / 2) small.fetch_add(1);
            for (std::size_t i = first; i < last; ++i) hits[i].fetch_add(1);
            chunks.fetch_add(1);
        },
        kGrain);
    for (const auto& h : hits) EXPECT_EQ(h.load(), 1);
    EXPECT_EQ(small.load(), 0);
    EXPECT_GE(chunks.load(), 1);
}

TEST(Parallel, EmptyRangeCallsNothing) {
    int calls = 0;
    parallelFor(5, 5, [&](int) { ++calls; });
    parallelFor(5, 2, [&](int) { ++calls; });
    EXPECT_EQ(calls, 0);
}

TEST(Parallel, AnExceptionReachesTheCaller) {
    EXPECT_THROW(parallelFor(0, 100000,
                             [](int i) {
                                 if (i == 4242) throw std::runtime_error("index 4242");
                             }),
                 std::runtime_error);
}

}  // namespace
}  // namespace strata
