// The memory budget counts every live strata::Image (include/strata/core/memory_budget.h): pixels are
// tracked from allocation to release, copies included, and a new image is refused when it would take the
// total over the budget.
#include "strata/core/error.h"
#include "strata/core/memory_budget.h"
#include "strata/image/image.h"

#include <gtest/gtest.h>

#include <optional>

namespace strata {
namespace {

class ImageBudget : public ::testing::Test {
protected:
    void TearDown() override { setMemoryBudget(mSaved); }
    std::uint64_t mSaved = memoryBudget();
};

constexpr std::uint64_t kMiB = std::uint64_t{1} << 20;

TEST_F(ImageBudget, EveryLiveImageCountsUntilItIsReleased) {
    const std::uint64_t before = trackedBytes();
    {
        const Image a(512, 512, 1);  // 1 MiB of floats
        EXPECT_EQ(trackedBytes(), before + kMiB);
        Image copy = a;
        EXPECT_EQ(trackedBytes(), before + 2 * kMiB);
        const Image moved = std::move(copy);
        EXPECT_EQ(moved.width(), 512);
        EXPECT_EQ(trackedBytes(), before + 2 * kMiB) << "a move allocates nothing";
    }
    EXPECT_EQ(trackedBytes(), before);
}

TEST_F(ImageBudget, ANewImageIsRefusedWhenTheImagesHeldLeaveNoRoom) {
    const std::uint64_t before = trackedBytes();
    setMemoryBudget(before + 3 * kMiB);
    std::optional<Image> held(std::in_place, 1024, 512, 1);  // 2 MiB
    try {
        const Image more(512, 1024, 1);  // 2 MiB more: 4 MiB in all, over 3 MiB
        ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Unsupported);
        EXPECT_EQ(std::string(e.what()),
                  "a 512 x 1024 image of 1 channel needs 2 MiB; with " + formatBytes(before + 2 * kMiB) +
                      " of images already held, that is more than the memory budget of " +
                      formatBytes(before + 3 * kMiB) + " (--max-memory)");
    }
    EXPECT_EQ(trackedBytes(), before + 2 * kMiB) << "the refused image holds nothing";
    // A copy is counted too, so it cannot slip past the budget either.
    EXPECT_THROW({ const Image copy = *held; }, Error);
    held.reset();
    EXPECT_NO_THROW({ const Image fits(512, 1024, 1); });
    EXPECT_EQ(trackedBytes(), before);
}

}  // namespace
}  // namespace strata
