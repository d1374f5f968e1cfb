// `squint calibrate SEQUENCE... --out calib.yaml`: fits the corridor measures' calibration (paper
// §5.1–5.2) from sequences with ground truth and writes the calibration YAML (docs/calibration.md).
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "command.hpp"
#include "squint/config/corridor_yaml.hpp"
#include "squint/core/error.hpp"
#include "squint/eval/corridor_eval.hpp"
#include "squint/io/sequence.hpp"

namespace squint::app {
namespace {

namespace fs = std::filesystem;

struct CalibrateCliOptions {
  std::vector<std::string> sequences;
  std::string out;
  std::string base;
  std::string only;
  eval::CalibrateOptions fit;
};

void Run(const CalibrateCliOptions& opt) {
  eval::CalibrateOptions fit = opt.fit;
  if (opt.only == "heading") fit.fit_distance = false;
  else if (opt.only == "distance") fit.fit_heading = false;
  if (const std::string bad = fit.Validate(); !bad.empty()) throw Error("calibrate: " + bad);
  corridor::CorridorOptions base_in;
  if (!opt.base.empty()) base_in = eval::LoadCalibrationFile(opt.base).options;

  // Read and check every input before the long part.
  std::vector<io::Sequence> seqs;
  std::vector<std::string> names;
  std::size_t total = 0;
  for (const std::string& s : opt.sequences) {
    seqs.push_back(io::Sequence::Read(s));
    eval::CheckCalibrationInputs(seqs.back(), fit.fit_heading, fit.fit_distance);
    names.push_back(fs::path(s).lexically_normal().filename().string().empty()
                        ? fs::path(s).lexically_normal().parent_path().filename().string()
                        : fs::path(s).lexically_normal().filename().string());
    total += seqs.back().Size();
  }
  std::vector<const io::Sequence*> ptrs;
  for (const io::Sequence& s : seqs) ptrs.push_back(&s);
  eval::CheckCalibrationSpread(ptrs, fit.fit_heading, fit.fit_distance);

  // Time to contact's image scale: each candidate is run and fitted, the one whose time-to-contact
  // cue has the lowest RMSE on the fusion's frames is kept (only when distance is fitted and the
  // base keeps the glance).
  std::vector<double> candidates{fit.ttc_glance_scale};
  if (fit.fit_distance && !fit.ttc_glance_scales.empty() && base_in.distance.ttc_glance_scale == 1.0)
    candidates = fit.ttc_glance_scales;
  std::optional<eval::CorridorCalibrationFile> best_file;
  eval::CueRmse best_rmse;
  double best_scale = 1.0;
  for (const double scale : candidates) {
    eval::CalibrateOptions fit_c = fit;
    fit_c.ttc_glance_scale = scale;
    const corridor::CorridorOptions base = eval::CalibrationBaseOptions(base_in, fit_c);
    // Fit from the measures' uncalibrated answers: identity scales and no bias.
    eval::CorridorRunOptions run_opt;
    run_opt.perception = base;
    for (auto& c : run_opt.perception.heading.cues) {
      c.scale = 1.0;
      c.bias_deg = 0.0;
      if (c.weight <= 0.0) c.weight = 1.0;
      c.enabled = true;
    }
    run_opt.perception.distance.ttc_scale = 1.0;
    run_opt.perception.distance.ttc_bias_m = 0.0;
    for (auto& w : run_opt.perception.distance.weights)
      if (w <= 0.0) w = 1.0;
    run_opt.perception.distance.enabled = {true, true, true};
    // Every estimate is wanted, also outside the usual validity ranges.
    run_opt.perception.heading.max_abs_heading_deg = 89.0;
    run_opt.perception.distance.min_m = 0.0;
    run_opt.perception.distance.max_m = 1e9;
    run_opt.perception.distance.valid_min_m = {0.0, 0.0, 0.0};
    run_opt.perception.distance.valid_max_m = {1e9, 1e9, 1e9};
    run_opt.gated_pass = false;

    std::vector<eval::CorridorRun> runs;
    ProgressBar bar(candidates.size() > 1 ? fmt::format("calibrate (ttc scale {:g})", scale) : std::string("calibrate"),
                    total);
    std::size_t done = 0;
    for (const io::Sequence& s : seqs) {
      runs.push_back(eval::RunCorridorSequence(s, run_opt, [&](std::size_t i) { bar.Update(done + i); }));
      done += s.Size();
    }
    bar.Finish();
    eval::CorridorCalibrationFile file = eval::FitCorridorCalibration(runs, names, base, fit_c);
    if (candidates.size() > 1) {
      const eval::CueRmse r = eval::TtcCalibrationRmse(runs, fit_c, file);
      std::cout << fmt::format("  ttc scale {:g} ({}x{}): time to contact rmse {:.3f} m on {} of {} frames\n", scale,
                               std::lround(32 * scale), std::lround(24 * scale), r.rmse_m, r.answered, r.frames);
      // Candidates answering on fewer than 95 % of the frames the best one answers on are not
      // chosen (as for the fusion's cue subsets).
      const bool covers = static_cast<double>(r.answered) >= 0.95 * static_cast<double>(best_rmse.answered);
      const bool beaten_in_cover = static_cast<double>(best_rmse.answered) < 0.95 * static_cast<double>(r.answered);
      if (!best_file || beaten_in_cover || (covers && r.rmse_m < best_rmse.rmse_m - 1e-12)) {
        best_file = std::move(file);
        best_rmse = r;
        best_scale = scale;
      }
    } else {
      best_file = std::move(file);
    }
  }
  eval::CorridorCalibrationFile& file = *best_file;
  if (candidates.size() > 1) std::cout << fmt::format("  ttc scale chosen: {:g}\n", best_scale);
  // The floor-contact options that calibration turned on (the motion test, the same-sign
  // refinement) stay only where they lower the fused distance's RMSE on these sequences
  // (eval::KeepFloorMotion): each is run off against the written options as they stand, whose
  // runs are made once and are the runs without an option that is dropped.
  struct FloorCheck {
    std::string name;
    eval::CueRmse with, without;
    bool kept = false;
  };
  std::vector<FloorCheck> floor_checks;
  eval::CorridorRunOptions written;
  written.perception = file.options;
  written.record = file.record;
  written.gated_pass = false;
  std::optional<eval::CueRmse> written_rmse;  // of `written`, once run
  const auto run_all = [&](const eval::CorridorRunOptions& ro, const std::string& what) {
    std::vector<eval::CorridorRun> runs;
    ProgressBar bar("calibrate (" + what + ")", total);
    std::size_t done = 0;
    for (const io::Sequence& s : seqs) {
      runs.push_back(eval::RunCorridorSequence(s, ro, [&](std::size_t i) { bar.Update(done + i); }));
      done += s.Size();
    }
    bar.Finish();
    return eval::FusedDistanceRmse(runs, fit);
  };
  const auto check_floor_option = [&](const std::string& name, const std::function<void(corridor::CorridorOptions&)>& off) {
    if (!written_rmse) written_rmse = run_all(written, "written options");
    eval::CorridorRunOptions without_opt = written;
    off(without_opt.perception);
    FloorCheck c{name, *written_rmse, run_all(without_opt, "without the " + name)};
    c.kept = eval::KeepFloorMotion(c.with, c.without);
    if (!c.kept) {
      off(file.options);
      written = without_opt;
      written_rmse = c.without;
    }
    floor_checks.push_back(c);
  };
  if (fit.fit_distance && file.options.distance.floor_contact.motion_window_m > 0.0 &&
      base_in.distance.floor_contact.motion_window_m == 0.0)
    check_floor_option("floor contact's motion test",
                       [](corridor::CorridorOptions& o) { o.distance.floor_contact.motion_window_m = 0.0; });
  if (fit.fit_distance && file.options.distance.floor_contact.refine_same_sign &&
      !base_in.distance.floor_contact.refine_same_sign)
    check_floor_option("floor contact's same-sign refinement",
                       [](corridor::CorridorOptions& o) { o.distance.floor_contact.refine_same_sign = false; });
  if (fit.fit_distance && file.options.distance.floor_contact.lined_wall_rel_step > 0.0 &&
      base_in.distance.floor_contact.lined_wall_rel_step == 0.0)
    check_floor_option("floor contact's lined-wall rule",
                       [](corridor::CorridorOptions& o) { o.distance.floor_contact.lined_wall_rel_step = 0.0; });
  eval::SaveCalibrationFile(opt.out, file);

  std::cout << fmt::format("calibrated on {} sequences ({} frames) -> {}\n", seqs.size(), total, opt.out);
  if (fit.fit_heading) {
    std::cout << "heading cue   scale    bias_deg  sigma_deg  rmse_deg  reliable_deg     samples\n";
    for (int c = 0; c < corridor::kHeadingCueCount; ++c) {
      const auto& h = file.record.heading[c];
      std::cout << fmt::format("  {:<10} {:7.3f}  {:8.2f}  {:9.2f}  {:8.2f}  [{:+5.1f},{:+5.1f}]  {:7}\n",
                               corridor::CueName(static_cast<corridor::HeadingCue>(c)), h.scale, h.bias_deg,
                               h.error_std_deg, h.rmse_deg, h.reliable_min_deg, h.reliable_max_deg, h.samples);
    }
  }
  if (fit.fit_distance) {
    const auto& d = file.options.distance;
    const auto& r = file.record.distance;
    std::cout << fmt::format("  ttc      scale {:.3f} (fitted {:.3f}) bias {:.2f} m (1, 0 = as is)  rmse {:.2f} m  sigma(d) = {:.2f} + {:.3f} d  n={}\n",
                             d.ttc_scale, r[0].scale, d.ttc_bias_m, r[0].rmse_m, r[0].sigma0_m, r[0].sigma_slope, r[0].samples);
    std::cout << fmt::format("  jeffrey  alpha2 {:.4g} beta2 {:.4g}  rmse {:.2f} m  sigma(d) = {:.2f} + {:.3f} d  n={}\n",
                             d.alpha2, d.beta2, r[1].rmse_m, r[1].sigma0_m, r[1].sigma_slope, r[1].samples);
    std::cout << fmt::format("  entropy  alpha3 {:.4g}  rmse {:.2f} m  sigma(d) = {:.2f} + {:.3f} d  n={}\n", d.alpha3,
                             r[2].rmse_m, r[2].sigma0_m, r[2].sigma_slope, r[2].samples);
    std::string fused;
    for (int c = 0; c < corridor::kDistanceCueCount; ++c)
      if (d.enabled[c] && d.weights[c] > 0.0 && d.fuse[c])
        fused += std::string(fused.empty() ? "" : ", ") + corridor::CueName(static_cast<corridor::DistanceCue>(c));
    std::cout << fmt::format("  fused distance: {} (rmse {:.2f} m on these sequences); none when its sigma > {:.2f} m "
                             "(0 = no limit)\n",
                             fused.empty() ? "no cue" : fused, file.record.fused_distance_rmse_m, d.fused_max_std_m);
    for (const FloorCheck& c : floor_checks)
      std::cout << fmt::format("  {}: fused rmse {:.2f} m on {} frames with it, {:.2f} m on {} without: {}\n", c.name,
                               c.with.rmse_m, c.with.answered, c.without.rmse_m, c.without.answered,
                               c.kept ? "kept" : "off");
  }
}

void Register(CLI::App& root) {
  auto opt = std::make_shared<CalibrateCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "calibrate",
      "Fit the corridor measures' calibration from sequences with ground truth (paper 5.1-5.2):\n"
      "each heading cue's scale and bias, fusion weights 1/sigma^2, reliable heading ranges,\n"
      "alpha2/beta2 (Jeffrey), alpha3 (entropy) and the time-to-contact scale. See docs/calibration.md.");
  cmd->add_option("SEQUENCE", opt->sequences, "Sequence folders with ground truth")->required();
  cmd->add_option("--out", opt->out, "Calibration YAML to write (whole or not at all)")->required();
  cmd->add_option("--base", opt->base, "Start from these options (a calibration or options YAML)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--only", opt->only, "Fit only 'heading' or only 'distance'")
      ->check(CLI::IsMember({"heading", "distance"}));
  cmd->add_option("--reliable-max-rmse-deg", opt->fit.heading.reliable_max_rmse_deg,
                  "A true-heading bin belongs to a cue's reliable range when its RMSE is at most this")
      ->capture_default_str();
  cmd->add_flag("--fit-ttc-scale", opt->fit.distance.ttc_fit_scale,
                "Apply the fitted time-to-contact scale (default: report it as a check, keep 1)");
  cmd->add_flag("--no-heading-filter{false}", opt->fit.heading_filter,
                "Keep the per-frame heading fusion in the written options (default: the heading filter over "
                "time is turned on, each cue's fitted sigma its measurement noise; docs/calibration.md)");
  cmd->add_option("--ttc-cell-px", opt->fit.ttc_cell_px,
                  "Time to contact's far-structure cells (px) written to the options when the base sets none; "
                  "0 = keep the base's (docs/calibration.md)")
      ->capture_default_str();
  cmd->add_option("--floor-motion-window-m", opt->fit.floor_motion_window_m,
                  "The floor contact's motion test over this much travel (m), written to the options when the base "
                  "sets none; 0 = keep the base's (docs/calibration.md)")
      ->capture_default_str();
  cmd->add_flag("--no-floor-same-sign{false}", opt->fit.floor_refine_same_sign,
                "Keep the base's floor-contact refinement (default: the same-sign refinement is turned on and kept "
                "where it lowers the fused RMSE on these sequences; docs/calibration.md)");
  cmd->add_option("--floor-lined-wall-rel-step", opt->fit.floor_lined_wall_rel_step,
                  "The floor contact's lined-wall rule (a step of this share of the column's strongest, where the "
                  "end wall shows lines above the horizon), written to the options when the base sets none and kept "
                  "where it lowers the fused RMSE on these sequences; 0 = keep the base's (docs/calibration.md)")
      ->capture_default_str();
  cmd->add_option("--ttc-cell-quantile", opt->fit.ttc_cell_quantile,
                  "Quantile of the cells' magnifications that is the estimate")
      ->capture_default_str();
  cmd->add_option("--ttc-cell-nearest", opt->fit.ttc_cell_nearest,
                  "Only this many cells nearest the expansion centre count (0 = all)")
      ->capture_default_str();
  CLI::Option* single_scale = cmd->add_option("--ttc-glance-scale", opt->fit.ttc_glance_scale,
                  "Time to contact's own area-averaged image, round(32 s) x round(24 s) pixels, written to the "
                  "options when the base keeps the glance, instead of choosing among --ttc-glance-scales (docs/calibration.md)")
      ->capture_default_str();
  cmd->add_option("--ttc-glance-scales", opt->fit.ttc_glance_scales,
                  "Candidate scales for time to contact's image, each run and fitted; the one whose time-to-contact "
                  "RMSE on the fusion's frames is lowest is written (none: --ttc-glance-scale alone)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_flag("--all-distance-cues{false}", opt->fit.select_distance_cues,
                "Fuse every distance cue (default: the subset whose fused estimate has the lowest RMSE on these "
                "sequences; the others are reported, not fused)");
  cmd->add_flag("--no-fused-std-limit{false}", opt->fit.fused_std_gate,
                "Give a fused distance however uncertain (default: none when its sigma exceeds the standard "
                "deviation of the true distances on these sequences)");
  cmd->add_option("--fusion-max-truth-m", opt->fit.fusion_max_truth_m,
                  "The distance fusion's cues and sigma limit are chosen on frames at most this far from the end")
      ->capture_default_str();
  cmd->add_flag("--heading-weights-from-variance", opt->fit.heading_weights_from_variance,
                "Set each heading cue's fusion weight to 1/sigma^2 of its calibrated error (the paper's rule; "
                "default: keep the base options' weights)");
  cmd->callback([opt, single_scale] {
    if (single_scale->count() > 0) opt->fit.ttc_glance_scales.clear();  // this scale, no choice
    Run(*opt);
  });
}

const CommandRegistrar kRegistrar(300, &Register);

}  // namespace
}  // namespace squint::app
