// Interruption loses nothing and leaves nothing (core/interrupt.h): a child process holds a staging
// directory and a temporary file, and is ended by a signal.
#include "test_support.h"

#include "strata/core/file.h"
#include "strata/core/interrupt.h"

#include "core/json_reader.h"
#include "core/staging_dir.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

namespace strata {
namespace {

namespace fs = std::filesystem;

// Forks a child that installs the cleanup, stages a directory with a file in it and starts an atomic
// write that never finishes, says so through a pipe, and waits. The parent sends `signal` and returns
// the child's wait status.
int interruptedChild(const fs::path& dir, int signal) {
    int ready[2];
    if (pipe(ready) != 0) return -1;
    const pid_t pid = fork();
    if (pid == 0) {
        close(ready[0]);
        installInterruptCleanup();
        detail::StagingDir staging(dir / "set");
        std::ofstream(staging.path() / "depth.png") << "half a picture";
        writeFileAtomic(dir / "map.png", [&](const fs::path& tmp) {
            std::ofstream(tmp) << "half";
            const char byte = 1;
            if (write(ready[1], &byte, 1) != 1) _exit(3);
            for (;;) pause();
        });
        _exit(2);  // not reached: the signal ends the process
    }
    close(ready[1]);
    char byte = 0;
    const bool childReady = read(ready[0], &byte, 1) == 1;
    close(ready[0]);
    if (!childReady) return -1;
    kill(pid, signal);
    int status = 0;
    waitpid(pid, &status, 0);
    return status;
}

TEST(Interrupt, SigintAndSigtermRemoveStagingDirectoriesAndTemporaryFiles) {
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
        test::ScratchDir dir("interrupt");
        std::ofstream(dir / "map.png") << "the previous map";
        const int status = interruptedChild(dir.path(), signal);
        // The child ends by the signal itself (the shell then reports 128 + signal), ...
        ASSERT_TRUE(WIFSIGNALED(status)) << "signal " << signal << ", status " << status;
        EXPECT_EQ(WTERMSIG(status), signal);
        // ... leaves neither its staging directory nor its temporary file, and the previous output is
        // untouched.
        EXPECT_EQ(test::countEntries(dir.path()), 1) << "signal " << signal;
        EXPECT_EQ(readTextFile(dir / "map.png"), "the previous map");
    }
}

TEST(Interrupt, StagedFilesMoveIntoPlaceInOrder) {
    test::ScratchDir dir("moveinto");
    std::vector<fs::path> written;
    {
        detail::StagingDir staging(dir / "out");
        // Beside the output, so that the renames stay on its file system (a volume mounted at the
        // output's directory works).
        EXPECT_EQ(staging.path().parent_path(), dir.path());
        std::ofstream(staging.path() / "a.txt") << "a";
        std::ofstream(staging.path() / "strata.json") << "{}";
        written = staging.moveInto(dir / "out", {"a.txt", "strata.json"});
    }
    ASSERT_EQ(written.size(), 2u);
    EXPECT_EQ(written[1], dir / "out" / "strata.json");
    EXPECT_EQ(readTextFile(dir / "out" / "a.txt"), "a");
    EXPECT_EQ(test::countEntries(dir.path()), 1);  // the staging directory is gone
}

TEST(JsonStrict, DuplicateKeysAreErrorsThatNameTheKeyPath) {
    const auto message = [](const std::string& text) {
        try {
            detail::parseJsonStrict(text, "m.json");
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(message(R"({"a": 1, "a": 2})"), "m.json: a: duplicate key");
    EXPECT_EQ(message(R"({"layers": [{"size": 64}, {"size": 64, "x": {"k": 1, "k": 2}}]})"),
              "m.json: layers[1].x.k: duplicate key");
    EXPECT_EQ(message(R"({"layers": [[1, 2], {"s": 1, "s": 1}]})"), "m.json: layers[1].s: duplicate key");
    // The same key in two objects is no duplicate.
    EXPECT_EQ(message(R"({"a": {"k": 1}, "b": {"k": 1}, "k": [{"k": 1}, {"k": 2}]})"), "no error");
    // A number out of double's range is an error with the file's name, not a bare parser message.
    EXPECT_NE(message(R"({"tiling": 1e400})").find("m.json: not valid JSON: "), std::string::npos);
}

TEST(File, DirectoriesDevicesAndFifosAreNotReadAsFiles) {
    test::ScratchDir dir("special");
    const auto ioError = [](const fs::path& path) {
        try {
            readFileBytes(path);
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Io);
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(ioError(dir / "none"), (dir / "none").string() + ": no such file");
    EXPECT_EQ(ioError(dir.path()), dir.path().string() + ": is a directory, not a file");
    // /dev/zero never ends and a FIFO blocks: both are refused before they are opened.
    EXPECT_EQ(ioError("/dev/zero"), "/dev/zero: not a regular file (a device, a FIFO or a socket)");
    ASSERT_EQ(mkfifo((dir / "fifo").c_str(), 0600), 0);
    EXPECT_EQ(ioError(dir / "fifo"),
              (dir / "fifo").string() + ": not a regular file (a device, a FIFO or a socket)");
    // Writing onto a directory names it, instead of "cannot move into place: Success".
    fs::create_directory(dir / "out.png");
    try {
        writeTextFileAtomic(dir / "out.png", "x");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
        EXPECT_EQ(std::string(e.what()),
                  (dir / "out.png").string() + ": is a directory; name a file to write");
    }
    EXPECT_EQ(test::countEntries(dir.path()), 2);  // the fifo and the directory: no temporary left
}

}  // namespace
}  // namespace strata
