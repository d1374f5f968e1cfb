// The built-in worlds: worlds/*.yaml, embedded at configure time (see the top-level CMakeLists).
#include <algorithm>
#include <string>
#include <utility>

#include "squint/sim/world.hpp"

namespace squint::sim {
namespace {

struct Entry {
  const char* name;
  const char* text;
};

const Entry kWorlds[] = {
#include "squint/sim/builtin_worlds.inc"
};

}  // namespace

std::vector<std::string> BuiltinWorldNames() {
  std::vector<std::string> names;
  for (const Entry& e : kWorlds) names.emplace_back(e.name);
  std::sort(names.begin(), names.end());
  return names;
}

std::optional<std::string> BuiltinWorldText(const std::string& name) {
  for (const Entry& e : kWorlds)
    if (name == e.name) return std::string(e.text);
  return std::nullopt;
}

}  // namespace squint::sim
