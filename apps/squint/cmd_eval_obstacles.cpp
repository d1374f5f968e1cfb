// `squint eval obstacles SEQUENCE... --out DIR`: ROC of the discrepancy, AUC, optimum β, and the
// paper's Table 1 per sequence (single β vs zone β + refinement, learned leave-one-sequence-out),
// as roc.png, report.json, report.md and the learned options YAML (`squint obstacles --options`).
#include <chrono>
#include <cmath>
#include <optional>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "command.hpp"
#include "squint/config/obstacles_yaml.hpp"
#include "squint/core/error.hpp"
#include "squint/eval/obstacles_eval.hpp"
#include "squint/eval/plot.hpp"
#include "squint/io/atomic_output.hpp"

namespace squint::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct EvalObstaclesOptions {
  std::vector<std::string> sequences;
  std::string out;
  std::string options_file;
  std::string detector;
  double delta = 0.5;
  std::optional<double> unclassified_cost;
  bool no_leave_one_out = false;
  bool compare_detectors = false;
};

json ScoreJson(const eval::ClassifierScore& s) {
  return {{"features", s.features},
          {"classified", s.classified},
          {"classified_per_pair", s.classified_per_pair},
          {"tp", s.confusion.tp},
          {"fp", s.confusion.fp},
          {"tn", s.confusion.tn},
          {"fn", s.confusion.fn},
          {"fp_per_feature", s.fp_per_feature},
          {"recall", s.confusion.Recall()},
          {"fall_out", s.confusion.FallOut()}};
}

json ClassifierJson(const obstacles::ClassifierOptions& c) {
  json zones = json::array();
  for (const auto& z : c.zones) {
    json j = {{"beta_m", z.beta_m}};
    j["refine_high_m"] = z.refine_high_m ? json(*z.refine_high_m) : json(nullptr);
    zones.push_back(j);
  }
  return zones;
}

std::vector<eval::SequenceSamples> Collect(const EvalObstaclesOptions& cli, const obstacles::IptOptions& options,
                                           double* ms_per_pair) {
  std::vector<eval::SequenceSamples> all;
  double seconds = 0.0;
  std::size_t pairs = 0;
  for (const auto& s : cli.sequences) {
    ProgressBar bar(fmt::format("{} {}", obstacles::DetectorName(options.features.detector), fs::path(s).filename().string()), 1);
    const auto t0 = std::chrono::steady_clock::now();
    all.push_back(eval::CollectObstacleSamples(s, options, [&](std::size_t i, std::size_t n) {
      bar.Update(n ? i * 1 / n : 1);
    }));
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    pairs += all.back().pairs;
    bar.Finish();
  }
  if (ms_per_pair) *ms_per_pair = pairs ? 1e3 * seconds / pairs : 0.0;
  return all;
}

void WriteRocPlot(const fs::path& path, const eval::ObstacleEvalReport& r) {
  std::vector<eval::PlotSeries> series;
  for (const auto& s : r.sequences) {
    eval::PlotSeries p;
    p.label = fmt::format("{} (AUC {:.3f})", s.name, s.auc);
    for (const auto& pt : s.roc.points) p.x.push_back(pt.fall_out), p.y.push_back(pt.recall);
    p.line_width_px = 1;
    series.push_back(std::move(p));
  }
  eval::PlotSeries pooled;
  pooled.label = fmt::format("all (AUC {:.3f})", r.pooled_roc.auc);
  pooled.rgb = std::array<std::uint8_t, 3>{0, 0, 0};
  pooled.line_width_px = 3;
  for (const auto& pt : r.pooled_roc.points) pooled.x.push_back(pt.fall_out), pooled.y.push_back(pt.recall);
  series.push_back(std::move(pooled));
  series.push_back({"chance", {0, 1}, {0, 1}, eval::PlotStyle::kLine, std::array<std::uint8_t, 3>{150, 150, 150}, 1, 3, true});
  series.push_back({fmt::format("single beta {:.0f} mm", r.optimum_beta_m * 1e3),
                    {r.pooled_at_optimum.FallOut()},
                    {r.pooled_at_optimum.Recall()},
                    eval::PlotStyle::kScatter,
                    std::array<std::uint8_t, 3>{214, 39, 40},
                    2,
                    7});
  series.push_back({"zone beta + refinement (held out)",
                    {r.pooled_zone.confusion.FallOut()},
                    {r.pooled_zone.confusion.Recall()},
                    eval::PlotStyle::kScatter,
                    std::array<std::uint8_t, 3>{44, 160, 44},
                    2,
                    7});
  eval::PlotOptions opt;
  opt.title = "IPT obstacle classification: ROC of the discrepancy D";
  opt.x_label = "fall-out FP/(FP+TN)";
  opt.y_label = "recall TP/(TP+FN)";
  opt.x_min = 0.0, opt.x_max = 1.0, opt.y_min = 0.0, opt.y_max = 1.0;
  opt.width_px = 900, opt.height_px = 700;
  eval::WritePlotPng(path, series, opt);
}

std::string Markdown(const eval::ObstacleEvalReport& r, const std::string& detector) {
  std::ostringstream md;
  md << "# IPT obstacle detection (" << detector << ")\n\n";
  md << fmt::format("Optimum single beta (FP + delta*FN over all sequences): {:.1f} mm; pooled AUC {:.3f}; mean AUC {:.3f} "
                    "(the paper's D of eq. 4: mean AUC {:.3f}).\n",
                    r.optimum_beta_m * 1e3, r.pooled_roc.auc, r.mean_auc, r.mean_auc_plain);
  md << (r.leave_one_out ? "Classifier columns: beta learned on the OTHER sequences (leave-one-out).\n\n"
                         : "Classifier columns: beta learned on ALL sequences (training figures).\n\n");
  md << "| sequence | pairs ok | features | AUC | AUC below horizon | beta | FP/N | fall-out | recall | FP/N zone+ref | "
        "fall-out zone+ref | recall zone+ref | classified/pair |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& s : r.sequences)
    md << fmt::format("| {} | {}/{} | {} | {:.3f} | {:.3f} | {:.1f} mm | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.1f} |\n",
                      s.name, s.pairs_ok, s.pairs, s.features, s.auc, s.auc_below_horizon, s.single_beta_m * 1e3,
                      s.single.fp_per_feature, s.single.confusion.FallOut(), s.single.confusion.Recall(),
                      s.zone.fp_per_feature, s.zone.confusion.FallOut(), s.zone.confusion.Recall(),
                      s.zone.classified_per_pair);
  md << fmt::format("| **all** | | {} | {:.3f} | {:.3f} | | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.1f} |\n",
                    r.pooled_single.features, r.pooled_roc.auc, r.pooled_auc_below_horizon, r.pooled_single.fp_per_feature,
                    r.pooled_single.confusion.FallOut(), r.pooled_single.confusion.Recall(), r.pooled_zone.fp_per_feature,
                    r.pooled_zone.confusion.FallOut(), r.pooled_zone.confusion.Recall(), r.pooled_zone.classified_per_pair);
  return md.str();
}

void Run(const EvalObstaclesOptions& cli) {
  obstacles::IptOptions options;
  if (!cli.options_file.empty()) options = config::LoadIptOptions(cli.options_file);
  if (!cli.detector.empty() && !obstacles::ParseDetector(cli.detector, &options.features.detector))
    throw Error("--detector must be sift, orb, akaze or klt (got '" + cli.detector + "')");
  if (!(cli.delta >= 0.0)) throw Error("--delta must not be negative");
  if (cli.unclassified_cost && !(*cli.unclassified_cost >= 0.0 && std::isfinite(*cli.unclassified_cost)))
    throw Error("--unclassified-cost must be a finite number not below 0");
  eval::ObstacleEvalOptions eval_options;
  eval_options.learning.delta = cli.delta;
  if (cli.unclassified_cost) eval_options.learning.unclassified_cost = *cli.unclassified_cost;
  eval_options.leave_one_out = !cli.no_leave_one_out;

  io::StagedDirectory out(cli.out);
  double ms_per_pair = 0.0;
  const auto samples = Collect(cli, options, &ms_per_pair);
  const eval::ObstacleEvalReport r = eval::EvaluateObstacles(samples, options, eval_options);

  json j;
  j["detector"] = obstacles::DetectorName(options.features.detector);
  j["delta"] = cli.delta;
  j["unclassified_cost"] = eval_options.learning.unclassified_cost;
  j["leave_one_out"] = r.leave_one_out;
  j["optimum_beta_m"] = r.optimum_beta_m;
  j["pooled"] = {{"auc", r.pooled_roc.auc},
                 {"auc_below_horizon", r.pooled_auc_below_horizon},
                 {"mean_auc", r.mean_auc},
                 {"mean_auc_plain_discrepancy", r.mean_auc_plain},
                 {"mirror_aware", options.mirror_aware},
                 {"recall_at_optimum_beta", r.pooled_at_optimum.Recall()},
                 {"fall_out_at_optimum_beta", r.pooled_at_optimum.FallOut()},
                 {"single_beta_held_out", ScoreJson(r.pooled_single)},
                 {"zone_beta_refinement_held_out", ScoreJson(r.pooled_zone)},
                 {"ms_per_pair_wall", ms_per_pair}};
  j["zone_thresholds_all"] = ClassifierJson(r.zone_classifier_all);
  j["sequences"] = json::array();
  for (std::size_t k = 0; k < r.sequences.size(); ++k) {
    const auto& s = r.sequences[k];
    j["sequences"].push_back({{"name", s.name},
                              {"pairs", s.pairs},
                              {"pairs_ok", s.pairs_ok},
                              {"skipped", s.skipped},
                              {"features", s.features},
                              {"features_per_pair", s.pairs_ok ? static_cast<double>(s.features) / s.pairs_ok : 0.0},
                              {"mean_matches", samples[k].mean_matches},
                              {"auc", s.auc},
                              {"auc_below_horizon", s.auc_below_horizon},
                              {"auc_plain_discrepancy", s.auc_plain},
                              {"single_beta_m", s.single_beta_m},
                              {"single_beta", ScoreJson(s.single)},
                              {"zone_thresholds", ClassifierJson(s.zone_classifier)},
                              {"zone_beta_refinement", ScoreJson(s.zone)}});
  }
  if (cli.compare_detectors) {
    json cmp = json::array();
    for (obstacles::Detector d :
         {obstacles::Detector::kSift, obstacles::Detector::kOrb, obstacles::Detector::kAkaze, obstacles::Detector::kKlt}) {
      obstacles::IptOptions o = options;
      o.features.detector = d;
      double ms = 0.0;
      const auto s = Collect(cli, o, &ms);
      const auto rr = eval::EvaluateObstacles(s, o, eval_options);
      std::size_t pairs_ok = 0, features = 0;
      for (const auto& q : s) pairs_ok += q.pairs_ok, features += q.samples.size();
      cmp.push_back({{"detector", obstacles::DetectorName(d)},
                     {"mean_auc", rr.mean_auc},
                     {"mean_auc_plain_discrepancy", rr.mean_auc_plain},
                     {"pooled_auc", rr.pooled_roc.auc},
                     {"features_per_pair", pairs_ok ? static_cast<double>(features) / pairs_ok : 0.0},
                     {"pairs_ok", pairs_ok},
                     {"zone_fall_out", rr.pooled_zone.confusion.FallOut()},
                     {"zone_recall", rr.pooled_zone.confusion.Recall()},
                     {"zone_classified_per_pair", rr.pooled_zone.classified_per_pair},
                     {"ms_per_pair_wall", ms}});
    }
    j["detector_comparison"] = cmp;
  }
  {
    // Every tracked feature with its truth, for further analysis.
    std::ostringstream csv;
    csv << "sequence,frame,u,v,zone,discrepancy_m,signed_discrepancy_m,obstacle,previous_u,previous_v,"
           "motion_epipolar_px,plain_discrepancy_m\n";
    for (const auto& seq : samples)
      for (const auto& s : seq.samples) {
        csv << seq.name << ',' << s.frame << ',' << fmt::format("{:.2f},{:.2f},{}", s.u, s.v, s.zone) << ',';
        if (s.discrepancy_m) csv << fmt::format("{:.5f}", *s.discrepancy_m);
        csv << ',';
        if (s.signed_discrepancy_m) csv << fmt::format("{:.5f}", *s.signed_discrepancy_m);
        csv << ',' << (s.obstacle ? 1 : 0)
            << fmt::format(",{:.2f},{:.2f},{:.3f},", s.previous_u, s.previous_v, s.motion_epipolar_px);
        if (s.plain_discrepancy_m) csv << fmt::format("{:.5f}", *s.plain_discrepancy_m);
        csv << '\n';
      }
    io::WriteFileAtomically(out.Path() / "samples.csv", csv.str());
  }
  io::WriteFileAtomically(out.Path() / "report.json", j.dump(2) + "\n");
  io::WriteFileAtomically(out.Path() / "report.md", Markdown(r, obstacles::DetectorName(options.features.detector)));
  WriteRocPlot(out.Path() / "roc.png", r);
  obstacles::IptOptions learned = options;
  learned.classifier = r.zone_classifier_all;
  learned.classifier.zone_beta = true;
  learned.classifier.refinement = true;
  config::SaveIptOptions(out.Path() / "obstacles_options.yaml", learned);
  out.Commit();
  spdlog::info("eval obstacles: mean AUC {:.3f} (plain D {:.3f}), optimum beta {:.1f} mm; zone beta + refinement (held out): fall-out "
               "{:.3f}, recall {:.3f}, {:.1f} classified per pair -> {}",
               r.mean_auc, r.mean_auc_plain, r.optimum_beta_m * 1e3, r.pooled_zone.confusion.FallOut(), r.pooled_zone.confusion.Recall(),
               r.pooled_zone.classified_per_pair, cli.out);
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<EvalObstaclesOptions>();
  CLI::App* eval = GetOrAddSubcommand(root, "eval", "Evaluate perception against ground truth");
  CLI::App* cmd = eval->add_subcommand("obstacles", "ROC/AUC and Table 1 of IPT obstacle classification on labelled sequences");
  cmd->add_option("SEQUENCE", opt->sequences, "Sequence folders with label masks and odometry")->required();
  cmd->add_option("--out", opt->out, "Output folder (roc.png, report.json, report.md, obstacles_options.yaml)")->required();
  cmd->add_option("--options", opt->options_file, "Options YAML to start from");
  cmd->add_option("--detector", opt->detector, "Feature detector: sift (default), orb, akaze or klt");
  cmd->add_option("--delta", opt->delta, "Weight of false negatives in FP + delta*FN (paper: 0.5)");
  cmd->add_option("--unclassified-cost", opt->unclassified_cost,
                  "lambda: cost of leaving a feature unclassified, relative to one false positive (default 0.15)");
  cmd->add_flag("--no-leave-one-out", opt->no_leave_one_out, "Learn beta on all sequences (training figures)");
  cmd->add_flag("--compare-detectors", opt->compare_detectors, "Also run every detector and add a comparison table");
  cmd->callback([opt] { Run(*opt); });
}

const CommandRegistrar kRegistrar(610, &Register);

}  // namespace
}  // namespace squint::app
