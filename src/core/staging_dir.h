// A staging directory for writing a directory of files all or nothing (texture sets, dual-depth textures):
// the files are written into it, then renamed into place; whatever is left is removed on destruction.
#pragma once

#include "strata/core/error.h"
#include "strata/core/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace strata::detail {

class StagingDir {
public:
    // Beside `dir`, under the nearest directory at or above its parent that exists: the final renames stay
    // on one file system, and no directory is created before every file is complete. Throws Error(Io)
    // naming `dir` if the staging directory cannot be made.
    explicit StagingDir(const std::filesystem::path& dir) {
        static std::atomic<unsigned> counter{0};
        std::string name = ".";
        name += dir.filename().string();
        name += ".staging" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
        mPath = existingAncestor(dir) / name;
        // Registered before it exists: a signal that comes as it is made still removes it.
        mCleanup = std::make_unique<InterruptCleanup>(mPath);
        std::error_code ec;
        std::filesystem::create_directories(mPath, ec);
        if (ec)
            throw Error(ErrorKind::Io,
                        dir.string() + ": cannot create a staging directory beside it: " + ec.message());
    }
    ~StagingDir() {
        std::error_code ec;
        std::filesystem::remove_all(mPath, ec);
    }
    StagingDir(const StagingDir&) = delete;
    StagingDir& operator=(const StagingDir&) = delete;
    const std::filesystem::path& path() const { return mPath; }

    // Creates `dir` if needed, runs `beforeMoves` (e.g. removing files of an older version), and renames
    // the staged files `names` into it in that order (the sidecar that names the others last). An
    // interruption waits until every rename is done (InterruptDeferral), so a signal never leaves half a
    // set. Throws Error(Io) "<dir>: cannot create the output directory: ..." or "<dir>/<name>: cannot
    // move into place: ...". Returns the paths written.
    std::vector<std::filesystem::path> moveInto(const std::filesystem::path& dir,
                                                const std::vector<std::string>& names,
                                                const std::function<void()>& beforeMoves = {}) const {
        const InterruptDeferral deferral;
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec)
            throw Error(ErrorKind::Io,
                        dir.string() + ": cannot create the output directory: " + ec.message());
        if (beforeMoves) beforeMoves();
        std::vector<std::filesystem::path> written;
        for (const std::string& name : names) {
            std::filesystem::rename(mPath / name, dir / name, ec);
            if (ec)
                throw Error(ErrorKind::Io,
                            (dir / name).string() + ": cannot move into place: " + ec.message());
            written.push_back(dir / name);
        }
        return written;
    }

private:
    static std::filesystem::path existingAncestor(const std::filesystem::path& dir) {
        std::error_code ec;
        std::filesystem::path parent = std::filesystem::absolute(dir, ec).parent_path();
        while (!parent.empty() && !std::filesystem::is_directory(parent, ec) &&
               parent != parent.parent_path())
            parent = parent.parent_path();
        return parent.empty() ? std::filesystem::path(".") : parent;
    }

    std::filesystem::path mPath;
    std::unique_ptr<InterruptCleanup> mCleanup;  // after mPath: unregistered before the removal
};

}  // namespace strata::detail
