// `squint explore`: autonomous exploration of a simulated building in closed loop (the README's
// main job), and `squint eval explore`: seeded starts per world, a table and one map per world.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "command.hpp"
#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/eval/explore_run.hpp"
#include "squint/eval/plot.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/sim/world.hpp"

namespace squint::app {
namespace {

struct ExploreCliOptions {
  std::string world = "default";
  double minutes = 45.0;
  std::uint64_t seed = 1;
  std::string out = "explore-out";
};

void RunExploreCommand(const ExploreCliOptions& opt) {
  const sim::World world = sim::LoadWorld(opt.world);
  eval::ExploreRunOptions run_opt;
  run_opt.minutes = opt.minutes;
  run_opt.seed = opt.seed;
  if (std::string e = run_opt.Validate(); !e.empty()) throw Error("explore: --minutes/--seed: " + e);
  io::StagedDirectory staged(opt.out);
  ProgressBar bar("explore " + world.name, 1000);
  const eval::ExploreRunResult run =
      eval::RunExplore(world, run_opt, [&](double f) { bar.Update(static_cast<std::size_t>(f * 1000.0)); });
  bar.Finish();
  eval::WriteExploreOutputs(staged.Path(), world, run);
  staged.Commit();
  const eval::ExploreSummary& s = run.summary;
  std::cout << s.outcome << "\n";
  std::printf("sim %.0f s, wall %.1f s, perception CPU %.2f s (%.3f%% of simulated time), %ld/%ld frames fully processed\n",
              s.sim_seconds, s.wall_seconds, s.perception_cpu_seconds, 100.0 * s.perception_cpu_seconds / s.sim_seconds,
              s.frames_fully_processed, s.frames);
  std::cout << "wrote " << (std::filesystem::path(opt.out) / "summary.json").string() << ", map.png, trace.csv, events.csv\n";
}

struct EvalExploreOptions {
  std::vector<std::string> worlds;
  int starts = 10;
  double minutes = 5.0;
  std::uint64_t seed = 1;
  std::string out = "explore-eval";
};

std::string Fixed(double v, int d) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", d, v);
  return b;
}

void RunEvalExplore(const EvalExploreOptions& opt) {
  std::vector<std::string> names = opt.worlds;
  if (names.empty()) names = sim::BuiltinWorldNames();
  std::vector<sim::World> worlds;
  for (const std::string& n : names) worlds.push_back(sim::LoadWorld(n));
  io::StagedDirectory staged(opt.out);
  ProgressBar bar("eval explore", names.size() * static_cast<std::size_t>(opt.starts));
  std::size_t done = 0;
  std::string table =
      "| world | start | x, y, yaw | minutes | distance m | coverage | ends | turns | collisions | outcome |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  std::string csv = "world,start,x_m,y_m,yaw_deg,sim_seconds,distance_m,coverage,ends_detected,turns,collisions,proceeded\n";
  int total_collisions = 0, runs = 0, clean = 0;
  for (const sim::World& world : worlds) {
    const std::vector<Pose2> starts = eval::SeededStarts(world, opt.starts, opt.seed);
    for (int i = 0; i < static_cast<int>(starts.size()); ++i) {
      eval::ExploreRunOptions ro;
      ro.minutes = opt.minutes;
      ro.seed = opt.seed + static_cast<std::uint64_t>(i);
      ro.start = starts[i];
      ro.keep_trace = false;
      if (std::string e = ro.Validate(); !e.empty()) throw Error("eval explore: " + e);
      const eval::ExploreRunResult run = eval::RunExplore(world, ro);
      const eval::ExploreSummary& s = run.summary;
      const std::string kind = i == 0 ? "world start" : i == 1 ? "facing a wall" : i == 2 ? "close to a wall" : "random";
      table += "| " + world.name + " | " + std::to_string(i) + " " + kind + " | " + Fixed(starts[i].x, 1) + ", " +
               Fixed(starts[i].y, 1) + ", " + Fixed(RadToDeg(starts[i].yaw), 0) + " | " + Fixed(s.sim_seconds / 60.0, 1) +
               " | " + Fixed(s.distance_m, 0) + " | " + Fixed(s.coverage, 2) + " | " + std::to_string(s.ends_detected) +
               " | " + std::to_string(s.turns) + " | " + std::to_string(s.collisions) + " | " +
               (s.proceeded ? "explored" : "could not proceed") + " |\n";
      csv += world.name + "," + std::to_string(i) + "," + Fixed(starts[i].x, 3) + "," + Fixed(starts[i].y, 3) + "," +
             Fixed(RadToDeg(starts[i].yaw), 2) + "," + Fixed(s.sim_seconds, 1) + "," + Fixed(s.distance_m, 2) + "," +
             Fixed(s.coverage, 4) + "," + std::to_string(s.ends_detected) + "," + std::to_string(s.turns) + "," +
             std::to_string(s.collisions) + "," + (s.proceeded ? "1" : "0") + "\n";
      total_collisions += s.collisions;
      ++runs;
      if (s.collisions == 0) ++clean;
      if (i == 0) eval::WritePng(staged.Path() / ("map-" + world.name + ".png"), eval::DrawExploreMap(world, run));
      bar.Update(++done);
    }
  }
  bar.Finish();
  const std::string footer = "\n" + std::to_string(clean) + " of " + std::to_string(runs) +
                             " runs without collision (" + std::to_string(total_collisions) + " collisions in all)\n";
  io::WriteFileAtomically(staged.Path() / "table.md", table + footer);
  io::WriteFileAtomically(staged.Path() / "runs.csv", csv);
  staged.Commit();
  std::cout << table << footer;
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<ExploreCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "explore", "Explore a simulated building in closed loop from the camera (and wheel odometry) alone");
  cmd->add_option("--world", opt->world, "Built-in world name or world YAML file")->capture_default_str();
  cmd->add_option("--minutes", opt->minutes, "Simulated minutes (the run is bounded by this)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--seed", opt->seed, "Seed for odometry and sensor noise")->capture_default_str();
  cmd->add_option("--out", opt->out, "Output folder: summary.json, map.png, trace.csv, events.csv")->capture_default_str();
  cmd->callback([opt] { RunExploreCommand(*opt); });

  auto eopt = std::make_shared<EvalExploreOptions>();
  CLI::App* eval_cmd = GetOrAddSubcommand(root, "eval", "Evaluate against ground truth and write reports");
  CLI::App* ex = eval_cmd->add_subcommand("explore", "Seeded starts per world (incl. facing and close to a wall): table and maps");
  ex->add_option("--world", eopt->worlds, "World name or file (repeatable); default: every built-in world");
  ex->add_option("--starts", eopt->starts, "Starts per world")->capture_default_str()->check(CLI::Range(1, 1000));
  ex->add_option("--minutes", eopt->minutes, "Simulated minutes per start")->capture_default_str()->check(CLI::PositiveNumber);
  ex->add_option("--seed", eopt->seed, "Seed of the start poses and noise")->capture_default_str();
  ex->add_option("--out", eopt->out, "Output folder: table.md, runs.csv, map-WORLD.png")->capture_default_str();
  ex->callback([eopt] { RunEvalExplore(*eopt); });
}

const CommandRegistrar kRegistrar(300, &Register);

}  // namespace
}  // namespace squint::app
