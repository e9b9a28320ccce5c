// The output promises of CONVENTIONS §6: atomic writes, inputs never overwritten; and the error kinds.
#include "test_support.h"

#include "strata/core/error.h"
#include "strata/core/file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <new>
#include <stdexcept>

namespace strata {
namespace {

TEST(File, AtomicWriteAppearsWholeOrNotAtAll) {
    test::ScratchDir dir("atomic");
    writeTextFileAtomic(dir / "a.txt", "hello");
    EXPECT_EQ(readTextFile(dir / "a.txt"), "hello");
    // A writer that fails half way leaves neither the destination nor its temporary file.
    EXPECT_THROW(writeFileAtomic(dir / "b.txt",
                                 [](const std::filesystem::path& tmp) {
                                     std::ofstream(tmp) << "half";
                                     throw std::runtime_error("disk full");
                                 }),
                 std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(dir / "b.txt"));
    EXPECT_EQ(test::countEntries(dir.path()), 1);
    // A failed rewrite keeps the old content.
    EXPECT_THROW(
        writeFileAtomic(dir / "a.txt", [](const std::filesystem::path&) { throw std::runtime_error("x"); }),
        std::runtime_error);
    EXPECT_EQ(readTextFile(dir / "a.txt"), "hello");
}

TEST(File, WritingIntoAMissingDirectoryIsAnIoError) {
    test::ScratchDir dir("nodir");
    try {
        writeTextFileAtomic(dir / "missing" / "a.txt", "x");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos);
    }
}

TEST(File, ReadingNamesThePath) {
    test::ScratchDir dir("read");
    try {
        readFileBytes(dir / "nothing.png");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
        EXPECT_NE(std::string(e.what()).find("nothing.png: no such file"), std::string::npos);
    }
    EXPECT_THROW(readFileBytes(dir.path()), Error);  // a directory
}

TEST(File, AnInputIsRecognisedThroughAnotherPath) {
    test::ScratchDir dir("inputs");
    test::writeBytes(dir / "in.png", "x");
    const auto sneaky = dir / "." / "in.png";
    EXPECT_THROW(refuseToOverwriteInputs(sneaky, {dir / "in.png"}), Error);
    EXPECT_NO_THROW(refuseToOverwriteInputs(dir / "out.png", {dir / "in.png"}));  // does not exist yet
}

TEST(Error, KindsMapToTheDocumentedExitCodes) {
    EXPECT_EQ(exitCode(ErrorKind::Usage), 1);
    EXPECT_EQ(exitCode(ErrorKind::Io), 2);
    EXPECT_EQ(exitCode(ErrorKind::InvalidInput), 3);
    EXPECT_EQ(exitCode(ErrorKind::Runtime), 4);
    EXPECT_EQ(exitCode(ErrorKind::Unsupported), 5);
    EXPECT_EQ(formatNumber(0.3), "0.3");
    EXPECT_EQ(formatNumber(-1.0), "-1");
}

TEST(File, LowerCaseExtension) {
    EXPECT_EQ(lowerCaseExtension("Teapot.OBJ"), ".obj");
    EXPECT_EQ(lowerCaseExtension("dir.d/photo.JpEg"), ".jpeg");
    EXPECT_EQ(lowerCaseExtension("archive.tar.GZ"), ".gz");  // the last dot only
    EXPECT_EQ(lowerCaseExtension("README"), "");
    EXPECT_EQ(lowerCaseExtension(".hidden"), "");  // a leading dot names the file, not its extension
}

template <typename Thrower>
int exitCodeOf(const Thrower& thrower) {
    try {
        thrower();
    } catch (...) {
        return reportCurrentException("test");
    }
    return 0;
}

TEST(Error, MainReportsEachExceptionWithItsExitCode) {
    EXPECT_EQ(exitCodeOf([] { throw Error(ErrorKind::Io, "a.png: cannot read"); }), 2);
    EXPECT_EQ(exitCodeOf([] { throw Error(ErrorKind::Unsupported, "x"); }), 5);
    EXPECT_EQ(exitCodeOf([] { throw std::bad_alloc(); }), 4);
    EXPECT_EQ(exitCodeOf([] { throw std::runtime_error("x"); }), 4);
    EXPECT_EQ(exitCodeOf([] { throw 42; }), 4);
}

}  // namespace
}  // namespace strata
