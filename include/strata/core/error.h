// Strata's error model, in two tiers (see CODE_STYLE.md):
//  - strata::Error: a failure that comes from outside the code (a file, user input, a parameter).
//    It carries a kind that the CLI maps to its documented exit code, and a message that names
//    what failed, where, and which value. Library code throws it; it never prints and carries on.
//  - STRATA_CHECK*(): a broken contract inside the code (see check.h). Those abort.
#pragma once

#include <stdexcept>
#include <string>

namespace strata {

// The kinds of failure, with the `strata` CLI exit code of each (docs/cli.md lists them).
enum class ErrorKind {
    Usage = 1,         // the command line is wrong: unknown flag, missing argument
    Io = 2,            // a file or directory cannot be read or written
    InvalidInput = 3,  // read, but its content is wrong: a corrupt image, a bad JSON key, a negative weight
    Runtime = 4,       // something failed while working on valid input
    Unsupported = 5,   // a valid input that Strata does not handle: an image format variant, a bit depth
};

// The exit code the CLI returns for an error of this kind.
constexpr int exitCode(ErrorKind kind) {
    return static_cast<int>(kind);
}

const char* toString(ErrorKind kind);

// A number as an error message shows it: the shortest usual form ("0.3", "-1", "nan", "inf").
std::string formatNumber(double value);

class Error : public std::runtime_error {
public:
    Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), mKind(kind) {}
    ErrorKind kind() const { return mKind; }

private:
    ErrorKind mKind;
};

// For a program's main(), inside `catch (...)`: prints "<program>: error: <message>" to stderr for the
// exception in flight and returns its exit code: an Error's kind's, Runtime for std::bad_alloc ("out of
// memory") and for any other exception.
int reportCurrentException(const char* program) noexcept;

}  // namespace strata
