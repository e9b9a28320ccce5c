// Nothing a user or a file can do costs more than it should or loses data: interruption, messages and
// exit codes of odd inputs, absurd values. Every case names its exit code (docs/cli.md) and its message.
#include "test_support.h"

#include "strata/core/file.h"
#include "strata/image/image_io.h"
#include "strata/relief/texture_set.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <limits>
#include <thread>

extern char** environ;

namespace strata {
namespace {

namespace fs = std::filesystem;
using test::runCli;

using test::quoted;

// Asserts the exit code and that the output holds `message`.
void expectFailure(const std::string& args, int exitCode, const std::string& message) {
    const auto result = runCli(args);
    EXPECT_EQ(result.exitCode, exitCode) << args << "\n" << result.output;
    EXPECT_NE(result.output.find(message), std::string::npos) << args << "\n" << result.output;
}

bool hasStagingEntry(const fs::path& dir) {
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().filename().string().find(".staging") != std::string::npos) return true;
    return false;
}

// Starts `strata pattern stone-bricks --size 4096 -o DIR/big` (seconds of PNG writing), waits until its
// staging directory exists, sends `signal`, and returns the wait status (-1 if the staging directory never
// appeared before the process ended).
int interruptWhileStaging(const fs::path& dir, int signal) {
    const std::string out = (dir / "big").string();
    const char* argv[] = {STRATA_CLI_PATH, "pattern", "stone-bricks", "--size",
                          "4096",          "-o",      out.c_str(),    nullptr};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    const int spawned =
        posix_spawn(&pid, STRATA_CLI_PATH, &actions, nullptr, const_cast<char**>(argv), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) return -1;
    int status = 0;
    for (;;) {
        if (hasStagingEntry(dir)) {
            kill(pid, signal);
            waitpid(pid, &status, 0);
            return status;
        }
        if (waitpid(pid, &status, WNOHANG) == pid) return -1;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

TEST(CliRobustness, AnInterruptedWriteLeavesNoStagingDirectoryAndKeepsThePreviousSet) {
    // SIGINT here; SIGTERM and SIGHUP take the same path (Interrupt.* in the core suite).
    const int signal = SIGINT;
    test::ScratchDir dir("cli-interrupt");
    ASSERT_EQ(runCli("pattern base --size 64 -o " + quoted(dir / "big")).exitCode, 0);
    const std::string previousSidecar = readTextFile(dir / "big" / "strata.json");
    const std::string previousDepth = readTextFile(dir / "big" / "depth.png");
    const int status = interruptWhileStaging(dir.path(), signal);
    ASSERT_NE(status, -1) << "the staging directory was never seen";
    // Ended by the signal (the shell's 130 / 143), ...
    ASSERT_TRUE(WIFSIGNALED(status)) << status;
    EXPECT_EQ(WTERMSIG(status), signal);
    // ... nothing staged is left, and the previous set is whole: the 4096² maps move in together with
    // their sidecar or not at all.
    EXPECT_FALSE(hasStagingEntry(dir.path()));
    EXPECT_EQ(test::countEntries(dir.path()), 1);
    EXPECT_EQ(readTextFile(dir / "big" / "strata.json"), previousSidecar);
    EXPECT_EQ(readTextFile(dir / "big" / "depth.png"), previousDepth);
}

TEST(CliRobustness, ParseErrorsCarryTheStrataPrefixAndNameTheFlag) {
    expectFailure("pattern base --size 10 -o x", 1,
                  "strata: error: --size: Value 10 not in range 64 to 4096");
    expectFailure("render --frobnicate", 1,
                  "strata: error: The following argument was not expected: --frobnicate");
    // A flag's range error names the flag and is a usage error (exit 1); the scene key's is exit 3.
    expectFailure("render --gdm weave --tiling 1e12 -o x.png", 1,
                  "strata: error: --tiling: must be in (0, 4096], got 1e+12");
    expectFailure("render --gdm weave --depth-scale 50 -o x.png", 1,
                  "strata: error: --depth-scale: must be in (0, 10], got 50");
    test::ScratchDir dir("cli-scene-range");
    test::writeBytes(dir / "s.json", R"({"gdm": "weave", "tiling": 1e12})");
    expectFailure("render " + quoted(dir / "s.json") + " -o " + quoted(dir / "x.png"), 3,
                  "s.json: tiling: must be in (0, 4096], got 1e+12");
    EXPECT_EQ(test::countEntries(dir.path()), 1);
}

TEST(CliRobustness, PathsThatAreNotFilesAreNamedAsSuch) {
    test::ScratchDir dir("cli-paths");
    ASSERT_EQ(runCli("pattern base --size 64 -o " + quoted(dir / "set")).exitCode, 0);
    // An output that is an existing directory: exit 2, not "cannot move the finished file into place:
    // Success".
    fs::create_directory(dir / "ao.png");
    expectFailure("ao " + quoted(dir / "set") + " -o " + quoted(dir / "ao.png"), 2,
                  (dir / "ao.png").string() + ": is a directory; name a file to write");
    // A directory that is no texture set, a device that never ends, a FIFO that would block: exit 2.
    fs::create_directory(dir / "empty");
    expectFailure("info " + quoted(dir / "empty"), 2,
                  (dir / "empty").string() + ": not a texture set (it has no strata.json)");
    expectFailure("info /dev/zero", 2, "/dev/zero: not a regular file (a device, a FIFO or a socket)");
    ASSERT_EQ(mkfifo((dir / "fifo.png").c_str(), 0600), 0);
    expectFailure("info " + quoted(dir / "fifo.png"), 2,
                  (dir / "fifo.png").string() + ": not a regular file (a device, a FIFO or a socket)");
    EXPECT_EQ(test::countEntries(dir.path()), 4);  // set, ao.png/, empty/, fifo.png: nothing written
}

// Seeds are unsigned 32-bit everywhere: a negative seed is refused, not wrapped and printed as -1, and the
// largest is recorded as given.
TEST(CliRobustness, SeedsAreUnsigned32BitEverywhere) {
    test::ScratchDir dir("cli-seeds");
    expectFailure("pattern base --size 64 --seed -1 -o " + quoted(dir / "a"), 1,
                  "strata: error: Could not convert: --seed = -1");
    expectFailure("meso weave --seed -1 -o " + quoted(dir / "b"), 1,
                  "strata: error: Could not convert: --seed = -1");
    test::writeBytes(dir / "m.json",
                     R"({"resolution": 64, "layers": [{"pattern": "base", "size": 64, "seed": -1}]})");
    expectFailure("compose " + quoted(dir / "m.json") + " -o " + quoted(dir / "c"), 3,
                  "m.json: layers[0].seed: must be in [0, 4294967295], got -1");
    const auto largest = runCli("pattern base --size 64 --seed 4294967295 -o " + quoted(dir / "d"));
    ASSERT_EQ(largest.exitCode, 0) << largest.output;
    EXPECT_EQ(readSidecar(dir / "d")["source"]["seed"].get<std::uint64_t>(), 4294967295u);
    EXPECT_EQ(test::countEntries(dir.path()), 2);  // m.json and d
}

// Staging happens beside the target, so a set written onto another filesystem (a Docker volume, tmpfs)
// is renamed into place, not copied across devices ("Invalid cross-device link").
TEST(CliRobustness, ASetWrittenOntoAnotherFilesystemArrivesWhole) {
    test::ScratchDir dir("cli-cross-device");
    struct stat here {};
    struct stat shm {};
    if (stat(dir.path().c_str(), &here) != 0 || stat("/dev/shm", &shm) != 0 || here.st_dev == shm.st_dev ||
        access("/dev/shm", W_OK) != 0)
        GTEST_SKIP() << "no writable /dev/shm on another filesystem than " << dir.path();
    const fs::path target = fs::path("/dev/shm") / ("strata-test-cross-device-" + std::to_string(getpid()));
    const auto result = runCli("pattern base --size 64 -o " + quoted(target / "set"));
    EXPECT_EQ(result.exitCode, 0) << result.output;
    EXPECT_TRUE(fs::exists(target / "set" / "strata.json"));
    const auto ao =
        runCli("ao " + quoted(target / "set") + " --directions 4 -o " + quoted(target / "ao.png"));
    EXPECT_EQ(ao.exitCode, 0) << ao.output;
    EXPECT_TRUE(fs::exists(target / "ao.png"));
    EXPECT_FALSE(hasStagingEntry(target));
    std::error_code ec;
    fs::remove_all(target, ec);
}

// Values that are not numbers are errors naming where they are, through the CLI as in the readers: NaN in an
// EXR normal map (read as (0, 0, 0) normals before), inf in an OBJ vertex (read as 0 before).
TEST(CliRobustness, NonFiniteValuesAreExit3NamingTheirPlace) {
    test::ScratchDir dir("cli-non-finite");
    Image normals(64, 64, 3, 0.5f);
    normals.at(5, 2, 1) = std::numeric_limits<float>::quiet_NaN();
    writeExr(dir / "n.exr", normals);
    writePng(dir / "d.png", Image(64, 64, 1, 0.25f));
    expectFailure(
        "import --depth " + quoted(dir / "d.png") + " --normal " + quoted(dir / "n.exr") + " -o " +
            quoted(dir / "set"),
        3,
        "strata: error: " + (dir / "n.exr").string() +
            ": EXR channel G holds nan at column 5, row 2 (row 0 is the top); only finite values are read");
    test::writeBytes(dir / "q.obj",
                     "v 0 0 0\nv 1 0 inf\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "f 1/1 2/2 3/3 4/4\n");
    expectFailure(
        "render --mesh " + quoted(dir / "q.obj") + " --size 64x64 -o " + quoted(dir / "r.png"), 3,
        "strata: error: " + (dir / "q.obj").string() + ": line 2: 'v' value 'inf' is not a finite number");
    EXPECT_EQ(test::countEntries(dir.path()), 3);  // n.exr, d.png, q.obj: nothing written
}

TEST(CliRobustness, InfoDecodesTheWholeImage) {
    test::ScratchDir dir("cli-info-corrupt");
    ASSERT_EQ(runCli("pattern base --size 64 -o " + quoted(dir / "set")).exitCode, 0);
    const std::string png = readTextFile(dir / "set" / "depth.png");
    // The header is intact, the data cut short: the header alone would describe it as fine.
    test::writeBytes(dir / "cut.png", png.substr(0, png.size() / 2));
    expectFailure("info " + quoted(dir / "cut.png"), 3, "cut.png: corrupt or truncated PNG");
    const auto whole = runCli("info " + quoted(dir / "set" / "depth.png"));
    EXPECT_EQ(whole.exitCode, 0) << whole.output;
}

TEST(CliRobustness, MaterialJsonRejectsDuplicatesOverflowsAndAbsurdValues) {
    test::ScratchDir dir("cli-material-values");
    const auto compose = [&](const std::string& json, int exitCode, const std::string& message) {
        test::writeBytes(dir / "m.json", json);
        expectFailure("compose " + quoted(dir / "m.json") + " -o " + quoted(dir / "out"), exitCode, message);
        EXPECT_FALSE(fs::exists(dir / "out"));
    };
    compose(R"({"layers": [{"pattern": "base", "size": 64, "size": 128}]})", 3,
            "m.json: layers[0].size: duplicate key");
    compose(R"({"layers": [{"pattern": "base", "size": 64, "tiling": 1e400}]})", 3,
            "m.json: not valid JSON: [json.exception.out_of_range.406] number overflow parsing '1e400'");
    compose(R"({"layers": [{"pattern": "base", "size": 64, "tiling": 1e12}]})", 3,
            "m.json: layers[0].tiling: must be in (0, 4096], got 1e+12");
    compose(R"({"layers": [{"pattern": "base", "size": 64, "weight_depth": 1e308}]})", 3,
            "m.json: layers[0].weight_depth: must be <= 1e6, got 1e+308");
    compose(R"({"layers": [{"pattern": "base", "size": 64, "weight_normal": 1e308}]})", 3,
            "m.json: layers[0].weight_normal: must be <= 1e6, got 1e+308");
    compose(R"({"depth_scale": 50, "layers": [{"pattern": "base", "size": 64}]})", 3,
            "m.json: depth_scale: must be in (0, 10], got 50");
    std::string many = R"({"layers": [)";
    for (int i = 0; i < 1000; ++i) many += std::string(i ? "," : "") + R"({"pattern": "base", "size": 64})";
    compose(many + "]}", 3, "m.json: layers: at most 64 layers, got 1000");
}

TEST(CliRobustness, DepthScalesThatOneCommandWritesAnotherRenders) {
    test::ScratchDir dir("cli-depth-scale");
    ASSERT_EQ(runCli("pattern base --size 64 -o " + quoted(dir / "set")).exitCode, 0);
    // Every writer takes (0, 10], as render does.
    expectFailure("import --depth " + quoted(dir / "set" / "depth.png") + " --depth-scale 50 -o " +
                      quoted(dir / "imported"),
                  1, "strata: error: --depth-scale: must be in (0, 10], got 50");
    expectFailure("pattern base --size 64 --depth-scale 50 -o " + quoted(dir / "deep"), 1,
                  "strata: error: --depth-scale: must be in (0, 10], got 50");
    // A set written by hand (or by an older version) with S = 50 is named as such when read.
    std::string sidecar = readTextFile(dir / "set" / "strata.json");
    const std::size_t at = sidecar.find("\"depth_scale\": 0.08");
    ASSERT_NE(at, std::string::npos) << sidecar;
    sidecar.replace(at, std::string("\"depth_scale\": 0.08").size(), "\"depth_scale\": 50");
    test::writeBytes(dir / "set" / "strata.json", sidecar);
    expectFailure("ao " + quoted(dir / "set") + " -o " + quoted(dir / "ao.png"), 3,
                  "strata.json: \"depth_scale\" must be in (0, 10], got 50");
    EXPECT_EQ(test::countEntries(dir.path()), 1);
}

TEST(CliRobustness, CheckNormalThatCannotTellIsExit3) {
    test::ScratchDir dir("cli-check-normal");
    ASSERT_EQ(runCli("pattern scales --size 64 -o " + quoted(dir / "set")).exitCode, 0);
    const auto found = runCli("import --check-normal " + quoted(dir / "set" / "normal.png") + " --depth " +
                              quoted(dir / "set" / "depth.png"));
    EXPECT_EQ(found.exitCode, 0) << found.output;
    EXPECT_NE(found.output.find("OpenGL (green up)"), std::string::npos) << found.output;
    // The depth map given as a height map: x is opposite, nothing to tell by. (The normal map itself given as
    // the depth map is refused earlier, also exit 3, as a normal map read as depth: test_cli_normals.cpp.)
    expectFailure("import --check-normal " + quoted(dir / "set" / "normal.png") + " --height " +
                      quoted(dir / "set" / "depth.png"),
                  3, "normal.png: cannot tell the convention: unknown: x is opposite");
}

}  // namespace
}  // namespace strata
