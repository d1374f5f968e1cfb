// The command line's plumbing: self-registering subcommands, and terminal progress bars.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <exception>
#include <string>

namespace squint::app {

using RegisterFn = void (*)(CLI::App& root);

// Each apps/squint/cmd_*.cpp registers its subcommand(s) with a static registrar, so adding a
// command touches one file. `order` sorts the help listing.
struct CommandRegistrar {
  CommandRegistrar(int order, RegisterFn fn);
};

// Returns the subcommand `name` of `parent`, creating it when absent (for shared parents such
// as `eval`, whose children live in different files).
CLI::App* GetOrAddSubcommand(CLI::App& parent, const std::string& name, const std::string& description);

// CLI11's PositiveNumber, with a message a person can read ("must be > 0 (got -1)"; CLI11's
// names the largest double in full).
inline const CLI::Validator kPositive(
    [](std::string& text) -> std::string {
      try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && v > 0.0 && v <= 1e300) return {};
      } catch (const std::exception&) {
      }
      return "must be a number > 0 (got '" + text + "')";
    },
    "POSITIVE");

// A progress bar on stderr, drawn only when stderr is a terminal; silent otherwise.
class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total);
  ~ProgressBar();
  void Update(std::size_t done);
  void Finish();

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  int last_percent_ = -1;
  bool finished_ = false;
};

}  // namespace squint::app
