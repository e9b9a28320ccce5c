#include "strata/core/error.h"
#include "strata/core/memory_budget.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <limits>

namespace strata {
namespace {

class MemoryBudget : public ::testing::Test {
protected:
    void TearDown() override { setMemoryBudget(mSaved); }
    std::uint64_t mSaved = memoryBudget();
};

TEST_F(MemoryBudget, DefaultsToHalfOfPhysicalMemory) {
    const auto physical = static_cast<std::uint64_t>(sysconf(_SC_PHYS_PAGES)) *
                          static_cast<std::uint64_t>(sysconf(_SC_PAGE_SIZE));
    EXPECT_EQ(physicalMemoryBytes(), physical);
    // mSaved is the default: no test before this one in this process changes it for good.
    EXPECT_EQ(mSaved, physical / 2);
}

TEST_F(MemoryBudget, ParsesSizesWithBinarySuffixes) {
    EXPECT_EQ(parseMemorySize("1048576"), 1048576u);
    EXPECT_EQ(parseMemorySize("100B"), 100u);
    EXPECT_EQ(parseMemorySize("64K"), 65536u);
    EXPECT_EQ(parseMemorySize("512M"), 512u << 20);
    EXPECT_EQ(parseMemorySize("512mib"), 512u << 20);
    EXPECT_EQ(parseMemorySize("4G"), std::uint64_t{4} << 30);
    EXPECT_EQ(parseMemorySize("4GB"), std::uint64_t{4} << 30);
    EXPECT_EQ(parseMemorySize("2T"), std::uint64_t{2} << 40);
    EXPECT_EQ(parseMemorySize("8388608T"), std::uint64_t{1} << 63);  // the largest accepted
}

TEST_F(MemoryBudget, MalformedSizesAreUsageErrorsNamingTheFlag) {
    const struct {
        const char* text;
        const char* why;
    } cases[] = {
        {"", "not a number"},       {"G", "not a number"},     {"-1G", "not a number"},
        {"0", "must be positive"},  {"12X", "unknown suffix"}, {"4GG", "unknown suffix"},
        {"1.5G", "unknown suffix"}, {"8388609T", "too large"}, {"99999999999999999999", "too large"}};
    for (const auto& c : cases) {
        try {
            parseMemorySize(c.text);
            ADD_FAILURE() << "accepted '" << c.text << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Usage);
            EXPECT_EQ(std::string(e.what()).rfind(std::string("--max-memory '") + c.text + "': " + c.why, 0),
                      0u)
                << e.what();
        }
    }
}

TEST_F(MemoryBudget, RefusesARequestOverTheBudgetWithAnExactMessage) {
    setMemoryBudget(std::uint64_t{512} << 20);
    EXPECT_NO_THROW(reserveOrThrow(std::uint64_t{512} << 20, "exactly the budget"));
    try {
        checkAllocation(16384, 16384, 4, 4, "x.png: a 16384 x 16384 PNG");
        ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Unsupported);
        EXPECT_STREQ(e.what(),
                     "x.png: a 16384 x 16384 PNG needs 4.00 GiB, more than the memory budget of 512 MiB "
                     "(--max-memory)");
    }
}

TEST_F(MemoryBudget, ProductsThatOverflowSaturateAndAreRefused) {
    constexpr auto kMax = std::numeric_limits<std::uint64_t>::max();
    EXPECT_EQ(saturatingMultiply(std::uint64_t{1} << 32, std::uint64_t{1} << 32), kMax);
    EXPECT_EQ(saturatingMultiply(std::uint64_t{1} << 31, std::uint64_t{1} << 32), std::uint64_t{1} << 63);
    setMemoryBudget(kMax - 1);
    // 2^62 * 2^62 would wrap to 0 and pass an unchecked product.
    EXPECT_THROW(checkAllocation(1LL << 62, 1LL << 62, 1, 1, "wrap"), Error);
    EXPECT_NO_THROW(checkAllocation(-5, 1LL << 62, 1, 1, "negative factors count as zero"));
    EXPECT_EQ(formatBytes(kMax), "more than 16 EiB");
    EXPECT_EQ(formatBytes(1000), "1000 bytes");
    EXPECT_EQ(formatBytes(std::uint64_t{48} << 20), "48 MiB");
}

}  // namespace
}  // namespace strata
