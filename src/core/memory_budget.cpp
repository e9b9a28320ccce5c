#include "strata/core/memory_budget.h"

#include "strata/core/check.h"
#include "strata/core/error.h"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cstdio>
#include <limits>

namespace strata {

namespace {

constexpr std::uint64_t kFallbackBudget = std::uint64_t{4} << 30;

std::uint64_t defaultBudget() {
    const std::uint64_t physical = physicalMemoryBytes();
    return physical > 0 ? physical / 2 : kFallbackBudget;
}

std::atomic<std::uint64_t>& budgetStorage() {
    static std::atomic<std::uint64_t> budget{defaultBudget()};
    return budget;
}

std::atomic<std::uint64_t>& trackedStorage() {
    static std::atomic<std::uint64_t> tracked{0};
    return tracked;
}

[[noreturn]] void refuse(std::uint64_t bytes, std::uint64_t held, const std::string& what) {
    std::string message = what + " needs " + formatBytes(bytes);
    if (held > 0)
        message += "; with " + formatBytes(held) + " of images already held, that is";
    else
        message += ",";
    throw Error(ErrorKind::Unsupported, message + " more than the memory budget of " +
                                            formatBytes(memoryBudget()) + " (--max-memory)");
}

// held + bytes > budget, without wrapping.
bool over(std::uint64_t held, std::uint64_t bytes, std::uint64_t budget) {
    return bytes > budget || held > budget - bytes;
}

}  // namespace

std::uint64_t physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long pageSize = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || pageSize <= 0) return 0;
    return saturatingMultiply(static_cast<std::uint64_t>(pages), static_cast<std::uint64_t>(pageSize));
}

std::uint64_t memoryBudget() {
    return budgetStorage().load(std::memory_order_relaxed);
}

void setMemoryBudget(std::uint64_t bytes) {
    STRATA_CHECK(bytes > 0);
    budgetStorage().store(bytes, std::memory_order_relaxed);
}

std::uint64_t saturatingMultiply(std::uint64_t a, std::uint64_t b) {
    std::uint64_t product = 0;
    if (__builtin_mul_overflow(a, b, &product)) return std::numeric_limits<std::uint64_t>::max();
    return product;
}

std::uint64_t parseMemorySize(const std::string& text, const std::string& flag) {
    const auto bad = [&](const char* why) {
        throw Error(ErrorKind::Usage, flag + " '" + text + "': " + why +
                                          " (expected a size such as 512M or 4G: a positive integer "
                                          "with an optional K, M, G or T suffix)");
    };
    std::size_t i = 0;
    std::uint64_t value = 0;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) {
        const auto digit = static_cast<std::uint64_t>(text[i] - '0');
        if (value > (std::numeric_limits<std::uint64_t>::max() - digit) / 10) bad("too large");
        value = value * 10 + digit;
        ++i;
    }
    if (i == 0) bad("not a number");
    std::string suffix;
    for (; i < text.size(); ++i)
        suffix += static_cast<char>(std::toupper(static_cast<unsigned char>(text[i])));
    int shift = 0;
    if (!suffix.empty()) {
        switch (suffix[0]) {
            case 'K':
                shift = 10;
                break;
            case 'M':
                shift = 20;
                break;
            case 'G':
                shift = 30;
                break;
            case 'T':
                shift = 40;
                break;
            case 'B':
                break;
            default:
                bad("unknown suffix");
        }
        // "B" alone, or K/M/G/T followed by nothing, "B" or "iB".
        const std::string rest = suffix.substr(1);
        if (suffix[0] == 'B' ? !rest.empty() : !(rest.empty() || rest == "B" || rest == "IB"))
            bad("unknown suffix");
    }
    if (value == 0) bad("must be positive");
    if (value > (std::uint64_t{1} << 63) >> shift) bad("too large");
    return value << shift;
}

std::string formatBytes(std::uint64_t bytes) {
    char text[64];
    if (bytes == std::numeric_limits<std::uint64_t>::max()) return "more than 16 EiB";
    if (bytes >= (std::uint64_t{1} << 30))
        std::snprintf(text, sizeof text, "%.2f GiB", static_cast<double>(bytes) / 1073741824.0);
    else if (bytes >= (std::uint64_t{1} << 20))
        std::snprintf(text, sizeof text, "%.0f MiB", static_cast<double>(bytes) / 1048576.0);
    else
        std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
    return text;
}

void reserveOrThrow(std::uint64_t bytes, const std::string& what) {
    const std::uint64_t held = trackedBytes();
    if (over(held, bytes, memoryBudget())) refuse(bytes, held, what);
}

std::uint64_t trackedBytes() {
    return trackedStorage().load(std::memory_order_relaxed);
}

bool tryAcquireTracked(std::uint64_t bytes) {
    std::atomic<std::uint64_t>& tracked = trackedStorage();
    std::uint64_t held = tracked.load(std::memory_order_relaxed);
    do {
        if (over(held, bytes, memoryBudget())) return false;
    } while (!tracked.compare_exchange_weak(held, held + bytes, std::memory_order_relaxed));
    return true;
}

void releaseTracked(std::uint64_t bytes) noexcept {
    trackedStorage().fetch_sub(bytes, std::memory_order_relaxed);
}

void checkAllocation(long long width, long long height, long long channels, long long bytesPerSample,
                     const std::string& what) {
    const auto factor = [](long long v) { return v > 0 ? static_cast<std::uint64_t>(v) : std::uint64_t{0}; };
    const std::uint64_t bytes =
        saturatingMultiply(saturatingMultiply(factor(width), factor(height)),
                           saturatingMultiply(factor(channels), factor(bytesPerSample)));
    reserveOrThrow(bytes, what);
}

}  // namespace strata
