#include "strata/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace strata {

void detail::runParallelChunks(std::int64_t begin, std::int64_t end, std::int64_t grain,
                               const std::function<void(std::int64_t, std::int64_t)>& body) {
    if (end <= begin) return;
    tbb::parallel_for(
        tbb::blocked_range<std::int64_t>(begin, end, std::max<std::int64_t>(grain, 1)),
        [&body](const tbb::blocked_range<std::int64_t>& range) { body(range.begin(), range.end()); });
}

}  // namespace strata
