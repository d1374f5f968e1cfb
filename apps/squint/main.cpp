// The `squint` command line: gathers the registered subcommands and turns errors into one line.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iostream>
#include <unistd.h>
#include <utility>
#include <vector>

#include "command.hpp"
#include "squint/core/error.hpp"

namespace squint::app {
namespace {
std::vector<std::pair<int, RegisterFn>>& Registry() {
  static std::vector<std::pair<int, RegisterFn>> registry;
  return registry;
}
}  // namespace

CommandRegistrar::CommandRegistrar(int order, RegisterFn fn) { Registry().emplace_back(order, fn); }

CLI::App* GetOrAddSubcommand(CLI::App& parent, const std::string& name, const std::string& description) {
  for (CLI::App* sub : parent.get_subcommands([](CLI::App*) { return true; }))
    if (sub->get_name() == name) return sub;
  CLI::App* sub = parent.add_subcommand(name, description);
  sub->require_subcommand(1);
  return sub;
}

ProgressBar::ProgressBar(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), enabled_(isatty(STDERR_FILENO) != 0 && total > 0) {}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Update(std::size_t done) {
  if (!enabled_ || finished_) return;
  const int percent = static_cast<int>(100.0 * std::min(done, total_) / total_);
  if (percent == last_percent_) return;
  last_percent_ = percent;
  constexpr int kWidth = 40;
  const int filled = percent * kWidth / 100;
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled, "########################################",
               kWidth - filled, "", percent);
  std::fflush(stderr);
}

void ProgressBar::Finish() {
  if (!enabled_ || finished_) return;
  Update(total_);
  std::fprintf(stderr, "\n");
  finished_ = true;
}

}  // namespace squint::app

int main(int argc, char** argv) {
  // FFmpeg's own messages about a video it cannot read would precede the one-line error; the
  // user can still ask for them by setting the variable.
  setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);
  CLI::App app{"squint: indoor exploration and obstacle avoidance with one cheap forward camera"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "squint 0.1.0");
  auto registry = squint::app::Registry();
  std::stable_sort(registry.begin(), registry.end(), [](auto& a, auto& b) { return a.first < b.first; });
  for (auto& [order, fn] : registry) fn(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const squint::Error& e) {
    std::cerr << "squint: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "squint: internal error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
