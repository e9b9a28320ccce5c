// A staging directory for writing a directory of files all or nothing (texture sets, dual-depth textures):
// the files are written into it, then renamed into place; whatever is left is removed on destruction.
#pragma once

#include "strata/core/error.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <system_error>

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
};

}  // namespace strata::detail
