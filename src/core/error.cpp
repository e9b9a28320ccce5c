#include "strata/core/error.h"

#include "strata/core/check.h"

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <new>
#include <sstream>

namespace strata {

const char* toString(ErrorKind kind) {
    switch (kind) {
        case ErrorKind::Usage:
            return "usage error";
        case ErrorKind::Io:
            return "I/O error";
        case ErrorKind::InvalidInput:
            return "invalid input";
        case ErrorKind::Runtime:
            return "runtime error";
        case ErrorKind::Unsupported:
            return "unsupported";
    }
    return "error";
}

std::string formatNumber(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

namespace detail {

void checkFailed(const char* file, int line, const std::string& what) {
    std::fprintf(stderr, "strata: internal check failed at %s:%d: %s\n", file, line, what.c_str());
    std::abort();
}

}  // namespace detail
int reportCurrentException(const char* program) noexcept {
    const auto report = [program](const char* message, ErrorKind kind) {
        std::cerr << program << ": error: " << message << "\n";
        return exitCode(kind);
    };
    try {
        throw;
    } catch (const Error& e) {
        return report(e.what(), e.kind());
    } catch (const std::bad_alloc&) {
        return report("out of memory", ErrorKind::Runtime);
    } catch (const std::exception& e) {
        return report(e.what(), ErrorKind::Runtime);
    } catch (...) {
        return report("unknown failure", ErrorKind::Runtime);
    }
}

}  // namespace strata
