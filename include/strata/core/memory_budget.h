// The process-wide memory budget (docs/images.md, docs/cli.md --max-memory).
//
// Every reader checks the sizes a file's header declares against the budget before it allocates
// anything proportional to them, and so does every strata::Image allocation, so that a tiny hostile
// file (a 69-byte PNG claiming 16384^2 RGBA16) or a large --size fails at once instead of using
// gigabytes. The budget bounds what the process holds in images: every strata::Image's pixels are
// tracked from allocation to release, and a request (a reader's decoded image and decoder buffers, a
// new image) is refused when it would take the tracked total over the budget. Memory that is not
// image pixels (meshes, GDM volumes, GL objects, the libraries) is checked per request where it is
// sized from input (mesh accessors, OBJ files), not tracked.
//
// Default: half the machine's physical memory (sysconf(_SC_PHYS_PAGES) * _SC_PAGE_SIZE); 4 GiB when
// that cannot be read. Set with setMemoryBudget (the CLI's --max-memory SIZE).
//
// A request over the budget throws strata::Error(ErrorKind::Unsupported) (exit code 5):
//   "<what> needs 4.00 GiB, more than the memory budget of 512 MiB (--max-memory)".
#pragma once

#include <cstdint>
#include <string>

namespace strata {

// Physical memory in bytes, 0 when unknown.
std::uint64_t physicalMemoryBytes();

// The current budget in bytes (the default until setMemoryBudget is called).
std::uint64_t memoryBudget();

// Sets the budget; bytes must be > 0 (checked).
void setMemoryBudget(std::uint64_t bytes);

// Parses a size as --max-memory takes it: a positive integer with an optional suffix K, M, G or T
// (binary: 1K = 1024 bytes; an optional trailing "B" or "iB" is accepted, case-insensitive), e.g.
// "512M", "4G", "1048576". Throws Error(Usage) naming `flag` and the text when malformed, zero or
// above 2^63 bytes.
std::uint64_t parseMemorySize(const std::string& text, const std::string& flag = "--max-memory");

// "512 MiB", "4.00 GiB", "1000 bytes": how the budget messages show a size.
std::string formatBytes(std::uint64_t bytes);

// Throws Error(Unsupported) when `bytes` on top of trackedBytes() exceeds the budget. `what` names the
// request and its source ("file.png: a 16384 x 16384 RGBA16 PNG"). Tracks nothing itself.
void reserveOrThrow(std::uint64_t bytes, const std::string& what);

// Bytes held in tracked buffers now: the pixels of every live strata::Image.
std::uint64_t trackedBytes();

// Adds `bytes` to the tracked total when they fit the budget on top of it, atomically (two threads cannot
// both pass the check with room for one), and returns true; returns false and adds nothing otherwise (the
// caller throws with reserveOrThrow's message, so that the hot path formats no text). Pair with
// releaseTracked.
bool tryAcquireTracked(std::uint64_t bytes);
// Removes bytes added by tryAcquireTracked.
void releaseTracked(std::uint64_t bytes) noexcept;

// width * height * channels * bytesPerSample, computed without overflow (a product beyond 2^64
// saturates and is always refused), then reserveOrThrow. Negative factors count as zero.
void checkAllocation(long long width, long long height, long long channels, long long bytesPerSample,
                     const std::string& what);

// a * b, saturating at UINT64_MAX instead of wrapping.
std::uint64_t saturatingMultiply(std::uint64_t a, std::uint64_t b);

}  // namespace strata
