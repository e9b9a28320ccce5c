// File-system helpers that keep Strata's promise about outputs (CONVENTIONS §6): every output is
// written to a temporary file beside its destination and renamed into place, so a failure never
// leaves a partial file, and an input is never overwritten unless the caller says so.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace strata {

// Calls write(tmpPath) to produce the file at a temporary path in dest's directory, then renames
// it to dest. If write throws, the temporary file is removed and the exception propagates.
// Throws Error(Io) if the directory does not exist or the rename fails.
void writeFileAtomic(const std::filesystem::path& dest,
                     const std::function<void(const std::filesystem::path& tmpPath)>& write);

// Writes bytes atomically (see writeFileAtomic).
void writeTextFileAtomic(const std::filesystem::path& dest, const std::string& text);

// Throws Error(Io) naming the path unless it is (a symbolic link to) a regular file: "no such file", "is a
// directory, not a file", or "not a regular file" for a FIFO, a device or a socket, which would block or
// never end.
void checkReadableFile(const std::filesystem::path& path);

// Reads a whole file (checkReadableFile first). Throws Error(Io) naming the path if it cannot be opened or
// read.
std::vector<unsigned char> readFileBytes(const std::filesystem::path& path);
std::string readTextFile(const std::filesystem::path& path);

// Throws Error(Io) if `output` is the same file as any of `inputs` (an input is never overwritten).
void refuseToOverwriteInputs(const std::filesystem::path& output,
                             const std::vector<std::filesystem::path>& inputs);

// The file name's extension with its dot, ASCII letters lower-cased: "Teapot.OBJ" -> ".obj", "a" -> "".
std::string lowerCaseExtension(const std::filesystem::path& path);

}  // namespace strata
