// `squint eval avoid-sim [WORLD] [--runs N] [--seed S] [--duration-s T] [--out DIR]`: steering
// alone in the simulator, N seeded runs, collisions counted (issue 6 target: none in 20 runs of
// 2 minutes in obstacle-course).
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "squint/config/avoid_yaml.hpp"
#include "squint/core/error.hpp"
#include "squint/eval/avoid_sim.hpp"
#include "squint/io/atomic_output.hpp"
#include "squint/sim/world.hpp"

namespace squint::app {
namespace {

struct EvalAvoidSimOptions {
  std::string world = "obstacle-course";
  std::string options_file;
  std::string out;
  int runs = 20;
  std::uint64_t seed = 1;
  eval::AvoidSimOptions sim;
};

void Run(const EvalAvoidSimOptions& cli) {
  const config::AvoidFileOptions options =
      cli.options_file.empty() ? config::AvoidFileOptions{} : config::LoadAvoidFileOptions(cli.options_file);
  const sim::World world = sim::LoadWorld(cli.world);
  nlohmann::json runs = nlohmann::json::array();
  int collided_runs = 0;
  ProgressBar bar("avoid-sim", static_cast<std::size_t>(cli.runs));
  fmt::print("{:>5} {:>8} {:>7} {:>10} {:>9} {:>6} {:>7} {:>8} {:>13}  {}\n", "seed", "time_s", "dist_m", "decisions",
             "skipped", "stops", "stalls", "collide", "min_clear_m", "first hit");
  for (int i = 0; i < cli.runs; ++i) {
    const std::uint64_t seed = cli.seed + static_cast<std::uint64_t>(i);
    const eval::AvoidSimRun r = eval::RunAvoidSim(world, options, cli.sim, seed);
    collided_runs += r.collisions > 0;
    fmt::print("{:>5} {:>8.1f} {:>7.2f} {:>10} {:>9} {:>6} {:>7} {:>8} {:>13.3f}  {}\n", seed, r.time_s, r.distance_m,
               r.decisions, r.skipped_pairs, r.stops, r.stalls, r.collisions, r.min_clearance_m,
               r.collisions ? fmt::format("{} at {:.1f} s", r.first_hit, r.first_collision_s) : "");
    for (const auto& [status, n] : r.skipped_by_status) fmt::print("      skipped: {} x {}\n", n, status);
    runs.push_back({{"seed", seed}, {"time_s", r.time_s}, {"distance_m", r.distance_m}, {"decisions", r.decisions},
                    {"skipped_pairs", r.skipped_pairs}, {"skipped_by_status", r.skipped_by_status}, {"stops", r.stops}, {"stalls", r.stalls},
                    {"blind_blocked", r.blind_blocked}, {"collision_steps", r.collisions},
                    {"first_collision_s", r.first_collision_s}, {"first_hit", r.first_hit},
                    {"min_clearance_m", r.min_clearance_m}});
    bar.Update(static_cast<std::size_t>(i + 1));
  }
  bar.Finish();
  fmt::print("{} of {} runs without collision (target: all)\n", cli.runs - collided_runs, cli.runs);
  if (!cli.out.empty()) {
    const nlohmann::json report = {{"world", cli.world}, {"runs", runs}, {"collision_free_runs", cli.runs - collided_runs},
                                   {"duration_s", cli.sim.duration_s}, {"speed_mps", cli.sim.speed_mps},
                                   {"period_s", cli.sim.period_s}};
    io::StagedDirectory staged(cli.out);
    io::WriteFileAtomically(staged.Path() / "avoid_sim.json", report.dump(2) + "\n");
    staged.Commit();
  }
}

void Register(CLI::App& root) {
  CLI::App* ev = GetOrAddSubcommand(root, "eval", "Evaluate against ground truth");
  auto opt = std::make_shared<EvalAvoidSimOptions>();
  CLI::App* cmd = ev->add_subcommand("avoid-sim", "Steering alone in the simulator: seeded runs, collisions counted");
  cmd->add_option("WORLD", opt->world, "Built-in world or world YAML (default obstacle-course)");
  cmd->add_option("--options", opt->options_file, "Options YAML with sections `ipt:` and/or `avoid:`");
  cmd->add_option("--runs", opt->runs, "Number of runs")->check(CLI::Range(1, 1000));
  cmd->add_option("--seed", opt->seed, "Seed of the first run (run i uses seed + i)");
  cmd->add_option("--duration-s", opt->sim.duration_s, "Simulated seconds per run")->check(CLI::Range(0.1, 3600.0));
  cmd->add_option("--speed-mps", opt->sim.speed_mps, "Forward speed")->check(CLI::Range(0.01, 2.0));
  cmd->add_option("--period-s", opt->sim.period_s, "Seconds between the frames of a pair")->check(CLI::Range(0.05, 5.0));
  cmd->add_option("--out", opt->out, "Output folder: avoid_sim.json");
  cmd->add_option("--overlay-dir", opt->sim.overlay_dir, "Write one overlay PNG per decision here (debugging)");
  cmd->callback([opt] { Run(*opt); });
}

const CommandRegistrar kRegistrar(521, &Register);

}  // namespace
}  // namespace squint::app
