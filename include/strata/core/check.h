// Contract checks for bugs inside Strata (not for bad input: that is strata::Error).
// A failed check prints the expression, the values involved and the place, then aborts.
// They stay on in release builds: they guard cheap invariants, never per-texel work.
#pragma once

#include <sstream>
#include <string>

namespace strata::detail {

[[noreturn]] void checkFailed(const char* file, int line, const std::string& what);

template <typename A, typename B>
[[noreturn]] void checkOpFailed(const char* file, int line, const char* expr, const A& a, const B& b) {
    std::ostringstream out;
    out << expr << " with values " << a << " and " << b;
    checkFailed(file, line, out.str());
}

}  // namespace strata::detail

#define STRATA_CHECK(cond)                                                     \
    do {                                                                       \
        if (!(cond)) ::strata::detail::checkFailed(__FILE__, __LINE__, #cond); \
    } while (false)

#define STRATA_CHECK_OP(a, op, b)                                                                       \
    do {                                                                                                \
        const auto& strataA_ = (a);                                                                     \
        const auto& strataB_ = (b);                                                                     \
        if (!(strataA_ op strataB_))                                                                    \
            ::strata::detail::checkOpFailed(__FILE__, __LINE__, #a " " #op " " #b, strataA_, strataB_); \
    } while (false)

#define STRATA_CHECK_EQ(a, b) STRATA_CHECK_OP(a, ==, b)
#define STRATA_CHECK_NE(a, b) STRATA_CHECK_OP(a, !=, b)
#define STRATA_CHECK_LT(a, b) STRATA_CHECK_OP(a, <, b)
#define STRATA_CHECK_LE(a, b) STRATA_CHECK_OP(a, <=, b)
#define STRATA_CHECK_GT(a, b) STRATA_CHECK_OP(a, >, b)
#define STRATA_CHECK_GE(a, b) STRATA_CHECK_OP(a, >=, b)
