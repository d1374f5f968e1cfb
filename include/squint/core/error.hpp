// Errors: a typed error for bad user input, and SQUINT_ENSURE for programmer-only preconditions.
#pragma once

#include <stdexcept>
#include <string>

namespace squint {

// Bad input from a user: a file, a flag, a frame. The CLI prints what() as one line and exits
// non-zero. Messages name the file (and row or entry) that is wrong.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
[[noreturn]] void EnsureFailed(const char* expr, const char* file, int line, const std::string& msg);
}  // namespace detail

}  // namespace squint

// Preconditions that only a programmer can break (never user input): throws std::logic_error.
#define SQUINT_ENSURE(cond, msg)                                              \
  do {                                                                        \
    if (!(cond)) ::squint::detail::EnsureFailed(#cond, __FILE__, __LINE__, (msg)); \
  } while (0)
