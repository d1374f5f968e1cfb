// `squint eval avoid SEQUENCE... [--options FILE] [--out DIR]`: scores the polar occupancy map
// and the steering against the floor contacts the label masks imply (issue 6 targets).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "squint/config/avoid_yaml.hpp"
#include "squint/eval/avoid_eval.hpp"
#include "squint/io/atomic_output.hpp"

namespace squint::app {
namespace {

struct EvalAvoidOptions {
  std::vector<std::string> sequences;
  std::string options_file;
  std::string out;
  double free_cone_deg = 10.0;
};

nlohmann::json ToJson(const eval::AvoidTotals& t) {
  return {{"frames", t.frames},
          {"sectors_in_view", t.sectors_in_view},
          {"sector_agreement", t.SectorAgreement()},
          {"true_occupied", t.true_occupied},
          {"detected_occupied", t.detected_occupied},
          {"both_occupied", t.both_occupied},
          {"stops", t.stops},
          {"true_stops", t.true_stops},
          {"moving_frames", t.moving},
          {"steer_truly_free_rate", t.SteerFreeRate()}};
}

void Run(const EvalAvoidOptions& cli) {
  const config::AvoidFileOptions options =
      cli.options_file.empty() ? config::AvoidFileOptions{} : config::LoadAvoidFileOptions(cli.options_file);
  eval::AvoidEvalOptions eo;
  eo.free_cone_deg = cli.free_cone_deg;
  std::vector<eval::AvoidFrameScore> all;
  nlohmann::json report = {{"free_cone_deg", eo.free_cone_deg}, {"sequences", nlohmann::json::array()}};
  std::string frames_csv =
      "sequence,frame,sectors_in_view,sectors_agree,true_occupied,detected_occupied,both_occupied,stop,steer_deg,"
      "true_stop,steer_truly_free\n";
  fmt::print("{:<18} {:>6} {:>7} {:>10} {:>6} {:>6} {:>7} {:>10}\n", "sequence", "pairs", "frames", "agree", "stops",
             "tstops", "moving", "truly_free");
  for (const std::string& path : cli.sequences) {
    ProgressBar bar("eval avoid " + std::filesystem::path(path).filename().string(), 1);
    const eval::AvoidSequenceScore s = eval::EvaluateAvoidSequence(
        path, options, eo, [&](std::size_t i, std::size_t n) { if (n) bar.Update(i * 1 / n); });
    bar.Finish();
    const eval::AvoidTotals t = eval::Totals(s.frames);
    fmt::print("{:<18} {:>6} {:>7} {:>9.1f}% {:>6} {:>6} {:>7} {:>9.1f}%\n", s.name, s.pairs, s.pairs_ok,
               100 * t.SectorAgreement(), t.stops, t.true_stops, t.moving, 100 * t.SteerFreeRate());
    nlohmann::json js = ToJson(t);
    js["name"] = s.name;
    js["pairs"] = s.pairs;
    js["skipped"] = s.skipped;
    report["sequences"].push_back(js);
    for (const auto& f : s.frames) {
      frames_csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", s.name, f.frame, f.sectors_in_view,
                                f.sectors_agree, f.true_occupied, f.detected_occupied, f.both_occupied, f.stop ? 1 : 0,
                                f.steer_deg ? fmt::format("{:.2f}", *f.steer_deg) : "", f.true_stop ? 1 : 0,
                                f.steer_truly_free ? (*f.steer_truly_free ? "1" : "0") : "");
      all.push_back(f);
    }
  }
  const eval::AvoidTotals t = eval::Totals(all);
  report["total"] = ToJson(t);
  fmt::print("{:<18} {:>6} {:>7} {:>9.1f}% {:>6} {:>6} {:>7} {:>9.1f}%\n", "TOTAL", "", t.frames,
             100 * t.SectorAgreement(), t.stops, t.true_stops, t.moving, 100 * t.SteerFreeRate());
  fmt::print("targets: sector agreement {:.1f}% (>= 90%: {}), steering truly free within ±{:g}° {:.1f}% of {} moving "
             "frames (>= 95%: {})\n",
             100 * t.SectorAgreement(), t.SectorAgreement() >= 0.9 ? "met" : "NOT met", eo.free_cone_deg,
             100 * t.SteerFreeRate(), t.moving, t.SteerFreeRate() >= 0.95 ? "met" : "NOT met");
  if (!cli.out.empty()) {
    io::StagedDirectory staged(cli.out);
    io::WriteFileAtomically(staged.Path() / "avoid_eval.json", report.dump(2) + "\n");
    io::WriteFileAtomically(staged.Path() / "frames.csv", frames_csv);
    staged.Commit();
  }
}

void Register(CLI::App& root) {
  CLI::App* ev = GetOrAddSubcommand(root, "eval", "Evaluate against ground truth");
  auto opt = std::make_shared<EvalAvoidOptions>();
  CLI::App* cmd = ev->add_subcommand("avoid", "Score the polar map and steering against label-mask floor contacts");
  cmd->add_option("SEQUENCES", opt->sequences, "Sequence folders with label masks and odometry")->required();
  cmd->add_option("--options", opt->options_file, "Options YAML with sections `ipt:` and/or `avoid:`");
  cmd->add_option("--out", opt->out, "Output folder: avoid_eval.json, frames.csv");
  cmd->add_option("--free-cone-deg", opt->free_cone_deg, "Half-width of the cone that must be truly free")
      ->check(CLI::Range(0.0, 90.0));
  cmd->callback([opt] { Run(*opt); });
}

const CommandRegistrar kRegistrar(520, &Register);

}  // namespace
}  // namespace squint::app
