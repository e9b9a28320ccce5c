#include "strata/core/file.h"

#include "strata/core/error.h"
#include "strata/core/interrupt.h"

#include <unistd.h>
#include <atomic>
#include <cctype>
#include <fstream>
#include <iterator>
#include <system_error>

namespace fs = std::filesystem;

namespace strata {

namespace {

fs::path temporaryPathFor(const fs::path& dest) {
    static std::atomic<unsigned> counter{0};
    const fs::path dir = dest.has_parent_path() ? dest.parent_path() : fs::path(".");
    // Keep the extension last so libraries that look at it (tinyexr, libpng do not, but be safe) still see
    // it.
    return dir / ("." + dest.stem().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                  std::to_string(counter++) + dest.extension().string());
}

}  // namespace

void writeFileAtomic(const fs::path& dest, const std::function<void(const fs::path&)>& write) {
    const fs::path dir = dest.has_parent_path() ? dest.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw Error(ErrorKind::Io, dest.string() + ": the directory " + dir.string() + " does not exist");
    if (fs::is_directory(dest, ec))
        throw Error(ErrorKind::Io, dest.string() + ": is a directory; name a file to write");
    const fs::path tmp = temporaryPathFor(dest);
    const InterruptCleanup cleanup(tmp);
    try {
        write(tmp);
    } catch (...) {
        fs::remove(tmp, ec);
        throw;
    }
    const InterruptDeferral deferral;  // the finished file moves in, or the temporary goes
    fs::rename(tmp, dest, ec);
    if (ec) {
        const std::string reason = ec.message();  // before remove() reuses ec
        fs::remove(tmp, ec);
        throw Error(ErrorKind::Io, dest.string() + ": cannot move the finished file into place: " + reason);
    }
}

void writeTextFileAtomic(const fs::path& dest, const std::string& text) {
    writeFileAtomic(dest, [&](const fs::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.close();
        if (!out) throw Error(ErrorKind::Io, dest.string() + ": cannot write");
    });
}

void checkReadableFile(const fs::path& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);  // follows symbolic links
    if (!fs::exists(status)) throw Error(ErrorKind::Io, path.string() + ": no such file");
    if (fs::is_directory(status)) throw Error(ErrorKind::Io, path.string() + ": is a directory, not a file");
    // A FIFO would block, and a device such as /dev/zero never ends: only regular files are read.
    if (!fs::is_regular_file(status))
        throw Error(ErrorKind::Io, path.string() + ": not a regular file (a device, a FIFO or a socket)");
}

std::vector<unsigned char> readFileBytes(const fs::path& path) {
    checkReadableFile(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::Io, path.string() + ": cannot open for reading");
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw Error(ErrorKind::Io, path.string() + ": read error");
    return bytes;
}

std::string readTextFile(const fs::path& path) {
    const auto bytes = readFileBytes(path);
    return std::string(bytes.begin(), bytes.end());
}

void refuseToOverwriteInputs(const fs::path& output, const std::vector<fs::path>& inputs) {
    std::error_code ec;
    if (!fs::exists(output, ec)) return;
    for (const auto& input : inputs) {
        if (fs::exists(input, ec) && fs::equivalent(output, input, ec))
            throw Error(ErrorKind::Io, output.string() + ": refusing to overwrite an input file");
    }
}

std::string lowerCaseExtension(const fs::path& path) {
    std::string extension = path.extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return extension;
}

}  // namespace strata
