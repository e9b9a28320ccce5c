// Interruption loses nothing and leaves nothing: the temporary files and staging directories that Strata
// writes outputs through (writeFileAtomic, texture sets, dual-depth textures, GDM assets) register here
// while they exist, and SIGINT, SIGTERM or SIGHUP remove them before the process ends.
//
// An application calls installInterruptCleanup() first thing in main(), before it starts any thread: the
// three signals are then blocked in every thread, and one thread of this module waits for them with
// sigwait() (no work runs in a signal handler). On a signal it removes every registered path, then ends
// the process by that signal with its default action, so the shell sees the usual status (130 for
// SIGINT, 143 for SIGTERM). Outputs already renamed into place are complete and stay; an output that was
// being replaced keeps its previous content. A library that never installs it is unaffected: the
// registration only records paths.
#pragma once

#include <cstdint>
#include <filesystem>

namespace strata {

// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread (and so in every thread it starts later) and
// starts the thread that waits for them. Idempotent. Call before any other thread exists.
void installInterruptCleanup();

// A path removed (recursively) if the process is interrupted while this object lives. Registration and
// removal are thread-safe; the destructor only unregisters (the owner removes the path as usual).
class InterruptCleanup {
public:
    explicit InterruptCleanup(const std::filesystem::path& path);
    ~InterruptCleanup();
    InterruptCleanup(const InterruptCleanup&) = delete;
    InterruptCleanup& operator=(const InterruptCleanup&) = delete;

private:
    std::uint64_t mId;
};

// While one lives, an interruption waits: for the few renames that move a staged set into place, so
// that a signal leaves the old set or the new one, never a mix. Keep its scope to renames.
class InterruptDeferral {
public:
    InterruptDeferral();
    ~InterruptDeferral();
    InterruptDeferral(const InterruptDeferral&) = delete;
    InterruptDeferral& operator=(const InterruptDeferral&) = delete;
};

}  // namespace strata
