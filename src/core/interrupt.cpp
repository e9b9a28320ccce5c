#include "strata/core/interrupt.h"

#include <pthread.h>
#include <signal.h>

#include <map>
#include <mutex>
#include <shared_mutex>
#include <system_error>
#include <thread>

namespace fs = std::filesystem;

namespace strata {

namespace {

struct Registry {
    std::shared_mutex commit;  // shared by the renames of InterruptDeferral, exclusive for the cleanup
    std::mutex mutex;
    std::map<std::uint64_t, fs::path> paths;
    std::uint64_t next = 0;
};

Registry& registry() {
    static Registry* instance = new Registry;  // never destroyed: the waiting thread may outlive main()
    return *instance;
}

sigset_t interruptSignals() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    return set;
}

[[noreturn]] void waitForInterrupt() {
    const sigset_t set = interruptSignals();
    int signal = 0;
    while (sigwait(&set, &signal) != 0) {
    }
    Registry& r = registry();
    // Held until the process ends: nothing registers, and no owner renames a half-written output away,
    // while the paths are removed.
    r.commit.lock();
    r.mutex.lock();
    for (const auto& [id, path] : r.paths) {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    // End by the signal itself, with its default action, so that the parent sees how the process ended.
    ::signal(signal, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, signal);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    ::raise(signal);
    for (;;) pause();  // the default action of the three signals ends the process
}

}  // namespace

void installInterruptCleanup() {
    static std::once_flag once;
    std::call_once(once, [] {
        const sigset_t set = interruptSignals();
        pthread_sigmask(SIG_BLOCK, &set, nullptr);
        std::thread(waitForInterrupt).detach();
    });
}

InterruptCleanup::InterruptCleanup(const fs::path& path) {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    mId = r.next++;
    r.paths.emplace(mId, path);
}

InterruptCleanup::~InterruptCleanup() {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    r.paths.erase(mId);
}

InterruptDeferral::InterruptDeferral() {
    registry().commit.lock_shared();
}

InterruptDeferral::~InterruptDeferral() {
    registry().commit.unlock_shared();
}

}  // namespace strata
