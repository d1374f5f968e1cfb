// `squint eval corridor SEQUENCE... [--calib FILE] --out DIR`: corridor perception against ground
// truth, reproducing the paper's Figs. 8, 9, 10 and 13 as DIR/report.json and PNG plots.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "command.hpp"
#include "squint/core/error.hpp"
#include "squint/eval/corridor_eval.hpp"
#include "squint/io/sequence.hpp"

namespace squint::app {
namespace {

namespace fs = std::filesystem;

struct EvalCorridorCliOptions {
  std::vector<std::string> sequences;
  std::string calib;
  std::string out;
  bool no_plots = false;
  eval::CorridorEvalOptions eval;
};

std::string NameOf(const std::string& s) {
  const fs::path p = fs::path(s).lexically_normal();
  return p.filename().empty() ? p.parent_path().filename().string() : p.filename().string();
}

void Run(const EvalCorridorCliOptions& opt) {
  eval::CorridorEvalOptions eo = opt.eval;
  eo.plots = !opt.no_plots;
  if (const std::string bad = eo.Validate(); !bad.empty()) throw Error("eval corridor: " + bad);
  eval::CorridorRunOptions run_opt;
  std::vector<std::string> warnings;
  if (!opt.calib.empty()) {
    const eval::CorridorCalibrationFile file = eval::LoadCalibrationFile(opt.calib);
    run_opt.perception = file.options;
    run_opt.record = file.record;
    if (file.record.fitted_on.empty())
      warnings.push_back(opt.calib + " does not record which sequences it was fitted on");
  }
  std::vector<io::Sequence> seqs;
  std::size_t total = 0;
  for (const std::string& s : opt.sequences) {
    seqs.push_back(io::Sequence::Read(s));
    total += seqs.back().Size();
    const std::string name = NameOf(s);
    const auto& fitted = run_opt.record.fitted_on;
    if (std::find(fitted.begin(), fitted.end(), name) != fitted.end())
      warnings.push_back("sequence '" + name + "' was also used to fit " + opt.calib +
                         ": its results are not a test of the calibration");
  }
  for (const std::string& w : warnings) std::cerr << "squint: warning: " << w << "\n";
  std::vector<eval::CorridorRun> runs;
  ProgressBar bar("eval corridor", total);
  std::size_t done = 0;
  for (const io::Sequence& s : seqs) {
    runs.push_back(eval::RunCorridorSequence(s, run_opt, [&](std::size_t i) { bar.Update(done + i); }));
    done += s.Size();
  }
  bar.Finish();
  const std::string text = eval::WriteCorridorReport(runs, opt.out, eo, warnings, opt.calib);
  const nlohmann::json r = nlohmann::json::parse(text);
  std::cout << fmt::format("{} sequences, {} frames -> {}/report.json\n", seqs.size(), total, opt.out);
  if (r.contains("heading") && !r["heading"].empty()) {
    std::cout << (run_opt.perception.heading.filter.enabled
                      ? "fused heading: the heading filter over time (fused_instant: the per-frame fusion)\n"
                      : "fused heading: the per-frame fusion (the options do not enable the heading filter)\n");
    std::cout << "heading          rmse_deg  coverage  right_sign(|h|>=5)\n";
    for (auto& [k, v] : r["heading"].items())
      std::cout << fmt::format("  {:<14} {:8.2f}  {:8.3f}  {:.3f} of {}\n", k, v["rmse_deg"].get<double>(),
                               v["coverage"].get<double>(), v["right_sign"]["fraction"].get<double>(),
                               v["right_sign"]["frames"].get<std::size_t>());
  }
  if (r.contains("distance") && !r["distance"].empty()) {
    std::cout << "distance         rmse_m   coverage  per range (rmse_m, coverage)\n";
    for (auto& [k, v] : r["distance"].items()) {
      std::string ranges;
      for (auto& g : v["ranges"])
        ranges += fmt::format("  {:g}-{:g} m: {:.2f} ({:.2f})", g["min_m"].get<double>(), g["max_m"].get<double>(),
                              g["rmse_m"].get<double>(), g["coverage"].get<double>());
      std::cout << fmt::format("  {:<14} {:7.2f}  {:8.3f} {}\n", k, v["rmse_m"].get<double>(),
                               v["coverage"].get<double>(), ranges);
    }
  }
  const auto& rp = r["rapid_perception"];
  std::cout << fmt::format("rapid perception: {:.1f}% of frames skipped", 100.0 * rp["fraction_skipped"].get<double>());
  if (rp.contains("heading_rmse_every_frame_deg"))
    std::cout << fmt::format("; fused heading RMSE: every frame {:.2f} deg, processed frames (gated) {:.2f} deg, "
                             "held between processed {:.2f} deg",
                             rp["heading_rmse_every_frame_deg"].get<double>(),
                             rp["heading_rmse_processed_frames_gated_deg"].get<double>(),
                             rp["heading_rmse_held_between_processed_deg"].get<double>());
  std::cout << "\n";
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<EvalCorridorCliOptions>();
  CLI::App* eval_cmd = GetOrAddSubcommand(root, "eval", "Evaluate perception and exploration against ground truth");
  CLI::App* cmd = eval_cmd->add_subcommand(
      "corridor",
      "Corridor perception against ground truth: heading RMSE, mean +-2 sigma and right sign per 1 deg\n"
      "(paper Figs. 8, 9), distance-to-end RMSE per 1 m (Fig. 10), rapid perception (Fig. 13); per cue,\n"
      "for the weighted average ('fused') and the Kalman filter ('kalman'). Writes DIR/report.json + PNGs.");
  cmd->add_option("SEQUENCE", opt->sequences, "Sequence folders with ground truth")->required();
  cmd->add_option("--calib", opt->calib, "Calibration YAML from `squint calibrate`")->check(CLI::ExistingFile);
  cmd->add_option("--out", opt->out, "Output folder (written whole or not at all)")->required();
  cmd->add_flag("--no-plots", opt->no_plots, "Write report.json only");
  cmd->callback([opt] { Run(*opt); });
}

const CommandRegistrar kRegistrar(510, &Register);

}  // namespace
}  // namespace squint::app
