// SQUINT_ENSURE's failure path.
#include "squint/core/error.hpp"

#include <stdexcept>

namespace squint::detail {

void EnsureFailed(const char* expr, const char* file, int line, const std::string& msg) {
  throw std::logic_error(std::string(file) + ":" + std::to_string(line) + ": ensure failed: " + expr +
                         (msg.empty() ? "" : " (" + msg + ")"));
}

}  // namespace squint::detail
