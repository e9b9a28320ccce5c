#include "strata/core/error.h"
#include "strata/core/check.h"

#include <cstdio>
#include <cstdlib>
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
}  // namespace strata
