// Corridor evaluation: the calibration file round trip, the calibration fit on constructed runs
// (planted parameters recovered, singular input refused) and the report on known errors.
#include "squint/eval/corridor_eval.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "squint/config/corridor_yaml.hpp"
#include "squint/core/error.hpp"

namespace squint::eval {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("squint_corridor_eval_test_" + name);
  fs::remove_all(p);
  return p;
}

CorridorCalibrationFile NonDefaultFile() {
  CorridorCalibrationFile f;
  f.options.heading.cues[0].scale = 0.87;
  f.options.heading.cues[0].bias_deg = -1.25;
  f.options.heading.cues[4].weight = 0.0625;
  f.options.heading.cues[2].std_deg = 3.5;
  f.options.heading.filter.enabled = true;
  f.options.heading.filter.reinit_after_rejections = 7;
  f.options.distance.ttc_scale = 1.1;
  f.options.distance.alpha2 = 12.5;
  f.options.distance.beta2 = 9.5;
  f.options.distance.alpha3 = -0.0375;
  f.record.fitted_on = {"orient-1-00", "drive-3-00c"};
  f.record.heading[2].fitted = true;
  f.record.heading[2].error_std_deg = 3.5;
  f.record.heading[2].reliable_min_deg = -12.5;
  f.record.heading[2].reliable_max_deg = 10.5;
  f.record.distance[0].fitted = true;
  f.record.distance[0].sigma0_m = 0.2;
  f.record.distance[0].sigma_slope = 0.125;
  f.record.distance[1].samples = 441;
  f.record.fused_distance_rmse_m = 1.75;
  f.options.distance.fuse = {true, false, true};
  f.options.distance.fused_max_std_m = 4.25;
  return f;
}

TEST(CalibrationFile, RoundTripKeepsOptionsAndRecord) {
  const CorridorCalibrationFile f = NonDefaultFile();
  const std::string text = CalibrationFileToYaml(f);
  const CorridorCalibrationFile g = CalibrationFileFromYaml(text, "mem");
  EXPECT_EQ(config::CorridorOptionsToYaml(g.options), config::CorridorOptionsToYaml(f.options));
  EXPECT_EQ(g.record.fitted_on, f.record.fitted_on);
  EXPECT_TRUE(g.record.heading[2].fitted);
  EXPECT_DOUBLE_EQ(g.record.heading[2].error_std_deg, 3.5);
  EXPECT_DOUBLE_EQ(g.record.heading[2].reliable_min_deg, -12.5);
  EXPECT_DOUBLE_EQ(g.record.heading[2].reliable_max_deg, 10.5);
  EXPECT_DOUBLE_EQ(g.record.distance[0].sigma0_m, 0.2);
  EXPECT_DOUBLE_EQ(g.record.distance[0].sigma_slope, 0.125);
  EXPECT_EQ(g.record.distance[1].samples, 441u);
  EXPECT_DOUBLE_EQ(g.record.fused_distance_rmse_m, 1.75);
  EXPECT_FALSE(g.options.distance.fuse[1]);
  EXPECT_TRUE(g.options.distance.fuse[2]);
  EXPECT_DOUBLE_EQ(g.options.distance.fused_max_std_m, 4.25);
  // The text is written again identically (a fixed point).
  EXPECT_EQ(CalibrationFileToYaml(g), text);
}

TEST(CalibrationFile, PerceptionOptionsLoaderReadsTheSameFile) {
  // perceive/explore read --calib with config::LoadCorridorOptions: it must accept the file.
  const fs::path dir = TempDir("load");
  fs::create_directories(dir);
  SaveCalibrationFile(dir / "calib.yaml", NonDefaultFile());
  const corridor::CorridorOptions o = config::LoadCorridorOptions(dir / "calib.yaml");
  EXPECT_DOUBLE_EQ(o.heading.cues[0].scale, 0.87);
  EXPECT_DOUBLE_EQ(o.distance.alpha3, -0.0375);
  fs::remove_all(dir);
}

TEST(CalibrationFile, BadRecordIsRefusedWithKey) {
  std::string text = CalibrationFileToYaml(NonDefaultFile());
  const std::size_t at = text.find("sigma0_m: 0.2");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 13, "sigma0_m: abc");
  try {
    CalibrationFileFromYaml(text, "calib.yaml");
    FAIL() << "accepted a bad value";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("calib.yaml: 'distance.ttc.sigma0_m'"), std::string::npos) << e.what();
  }
}

// Runs whose raw values follow the paper's models with planted constants.
std::vector<CorridorRun> PlantedRuns() {
  std::vector<CorridorRun> runs(2);
  for (int r = 0; r < 2; ++r) {
    for (int i = 0; i < 41; ++i) {  // a sweep: cue k reads (truth - bias_k) / scale_k
      CorridorFrame f;
      f.gt.heading_deg = -20.0 + i;
      for (int k = 0; k < corridor::kHeadingCueCount; ++k)
        f.heading_camera_deg[k] = (*f.gt.heading_deg - (k - 2) * 0.5) / (0.8 + 0.1 * k);
      runs[r].frames.push_back(f);
    }
    for (int i = 0; i < 140; ++i) {  // a drive from 14.3 m to 0.4 m
      CorridorFrame f;
      const double d = 14.3 - 0.1 * i;
      f.gt.heading_deg = 0.0;
      f.gt.dist_end_m = d;
      f.moving_forward = true;
      f.dist_filtered_raw[0] = d / 1.2;      // ttc scale 1.2 (the fit uses the median-filtered raw values)
      f.dist_filtered_raw[1] = (9.0 - d) / 0.5;      // β2 = 9, α2 = 0.5
      f.dist_filtered_raw[2] = -0.02 / d;            // α3 = −0.02
      runs[r].frames.push_back(f);
    }
  }
  return runs;
}

TEST(FitCorridorCalibration, RecoversPlantedParameters) {
  CalibrateOptions free_scale;
  free_scale.heading.fit_scale = true;  // the default fits a bias only (scale 1)
  free_scale.distance.ttc_fit_scale = true;  // the default only checks the time-to-contact scale
  const CorridorCalibrationFile f = FitCorridorCalibration(PlantedRuns(), {"a", "b"}, {}, free_scale);
  for (int k = 0; k < corridor::kHeadingCueCount; ++k) {
    EXPECT_NEAR(f.options.heading.cues[k].scale, 0.8 + 0.1 * k, 1e-9) << k;
    EXPECT_NEAR(f.options.heading.cues[k].bias_deg, (k - 2) * 0.5, 1e-9) << k;
    EXPECT_TRUE(f.record.heading[k].fitted);
  }
  EXPECT_NEAR(f.options.distance.ttc_scale, 1.2, 1e-9);
  EXPECT_NEAR(f.record.distance[0].scale, 1.2, 1e-9);
  // By default the fitted scale is recorded as the check and the options keep 1.
  const CorridorCalibrationFile checked = FitCorridorCalibration(PlantedRuns(), {"a", "b"}, {}, CalibrateOptions{});
  EXPECT_EQ(checked.options.distance.ttc_scale, 1.0);
  EXPECT_NEAR(checked.record.distance[0].scale, 1.2, 1e-9);
  EXPECT_NEAR(f.options.distance.alpha2, 0.5, 1e-9);
  EXPECT_NEAR(f.options.distance.beta2, 9.0, 1e-9);
  EXPECT_NEAR(f.options.distance.alpha3, -0.02, 1e-12);
  EXPECT_EQ(f.record.fitted_on, (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(f.options.Validate().empty());
}

TEST(FitCorridorCalibration, FusionWeightsFromVarianceOnlyWhenAskedAndNeverForSwitchedOffCues) {
  corridor::CorridorOptions base;
  base.heading.cues[1].weight = 0.0;  // switched off: stays off
  base.distance.enabled[2] = false;
  const corridor::CorridorOptions before = base;
  const CorridorCalibrationFile kept = FitCorridorCalibration(PlantedRuns(), {}, base, {});
  CalibrateOptions variance;
  variance.heading_weights_from_variance = true;
  const CorridorCalibrationFile fitted = FitCorridorCalibration(PlantedRuns(), {}, base, variance);
  for (int k = 0; k < corridor::kHeadingCueCount; ++k) {
    EXPECT_EQ(kept.options.heading.cues[k].weight, before.heading.cues[k].weight) << k;
    const double sigma = fitted.record.heading[k].error_std_deg;
    const double expected = before.heading.cues[k].weight > 0.0 ? 1.0 / (sigma * sigma) : 0.0;
    EXPECT_DOUBLE_EQ(fitted.options.heading.cues[k].weight, expected) << k;
  }
  // Distance: weight 1/σ0², growth slope/σ0 for enabled cues; the disabled one is untouched.
  for (int c = 0; c < 2; ++c) {
    const DistanceCueCalibration& d = kept.record.distance[c];
    const double s0 = std::max(d.sigma0_m, 0.05);
    EXPECT_DOUBLE_EQ(kept.options.distance.weights[c], 1.0 / (s0 * s0)) << c;
    EXPECT_DOUBLE_EQ(kept.options.distance.error_growth_per_m[c], d.sigma_slope / s0) << c;
  }
  EXPECT_EQ(kept.options.distance.weights[2], before.distance.weights[2]);
  EXPECT_FALSE(kept.options.distance.enabled[2]);
}

// Frames whose cue inputs give known estimates under identity-like models (ttc: d = input;
// Jeffrey with α2 = −1, β2 = 0: d = J; entropy with α3 = 1: d = 1 / |ΔH|).
CorridorCalibrationFile KnownModels() {
  CorridorCalibrationFile f;
  f.options.distance.alpha2 = -1.0;
  f.options.distance.beta2 = 0.0;
  f.options.distance.alpha3 = 1.0;
  f.options.distance.weights = {1.0, 1.0, 1.0};
  return f;
}

TEST(ChooseDistanceFusion, KeepsTheLowestRmseSubsetWithinFifteenMetres) {
  std::vector<CorridorRun> runs(1);
  for (int i = 0; i < 100; ++i) {
    CorridorFrame f;
    const double d = 1.0 + 0.1 * i;
    f.gt.dist_end_m = d;
    f.moving_forward = true;
    f.dist_filtered_raw[0] = d + (i % 2 == 0 ? 0.2 : -0.2);  // ttc: ±0.2 m
    f.dist_filtered_raw[1] = d + 1.0;                       // Jeffrey: +1 m
    f.dist_filtered_raw[2] = 1.0;                           // entropy: always 1 m
    runs[0].frames.push_back(f);
  }
  CorridorFrame standing;  // not driving forward: not counted
  standing.gt.dist_end_m = 50.0;
  standing.dist_filtered_raw = {std::optional(90.0), std::optional(90.0), std::optional(0.01)};
  runs[0].frames.push_back(standing);
  CorridorFrame beyond;  // driving, but beyond fusion_max_truth_m (15 m): not counted either
  beyond.gt.dist_end_m = 20.0;
  beyond.moving_forward = true;
  beyond.dist_filtered_raw = {std::optional(60.0), std::optional(21.0), std::optional(0.05)};
  runs[0].frames.push_back(beyond);
  CorridorCalibrationFile f = KnownModels();
  ChooseDistanceFusion(runs, CalibrateOptions{}, f);
  // ttc alone (0.2 m) beats ttc + Jeffrey (0.4 / 0.6 m) and every subset with entropy.
  EXPECT_TRUE(f.options.distance.fuse[0]);
  EXPECT_FALSE(f.options.distance.fuse[1]);
  EXPECT_FALSE(f.options.distance.fuse[2]);
  EXPECT_NEAR(f.record.fused_distance_rmse_m, 0.2, 1e-9);
  // Every frame has a time-to-contact estimate with σ 1 m, below the truth's spread: the limit
  // would drop nothing, so it is not written.
  EXPECT_EQ(f.options.distance.fused_max_std_m, 0.0);

  // A cue that answers on half the frames only is not chosen alone, however good there (0.2 m);
  // with Jeffrey (1 m alone) it is: 0.4 m on the frames where both answer, 1 m on the others.
  for (std::size_t i = 0; i < runs[0].frames.size(); i += 2) runs[0].frames[i].dist_filtered_raw[0].reset();
  CorridorCalibrationFile g = KnownModels();
  g.options.distance.enabled[2] = false;  // a switched-off cue is never chosen
  CalibrateOptions no_gate;
  no_gate.fused_std_gate = false;
  ChooseDistanceFusion(runs, no_gate, g);
  EXPECT_TRUE(g.options.distance.fuse[0]);
  EXPECT_TRUE(g.options.distance.fuse[1]);
  EXPECT_NEAR(g.record.fused_distance_rmse_m, std::sqrt(0.5 * 1.0 + 0.5 * 0.4 * 0.4), 1e-9);
  EXPECT_TRUE(g.options.distance.fuse[2]);  // untouched: not available to choose
  EXPECT_EQ(g.options.distance.fused_max_std_m, 0.0);

  // Equal cues: the larger subset.
  std::vector<CorridorRun> same(1);
  for (int i = 0; i < 20; ++i) {
    CorridorFrame e;
    e.gt.dist_end_m = 1.0 + i;
    e.moving_forward = true;
    e.dist_filtered_raw[0] = e.dist_filtered_raw[1] = 1.0 + i;
    e.dist_filtered_raw[2] = 1.0 / (1.0 + i);
    same[0].frames.push_back(e);
  }
  CorridorCalibrationFile h = KnownModels();
  ChooseDistanceFusion(same, CalibrateOptions{}, h);
  EXPECT_TRUE(h.options.distance.fuse[0]);
  EXPECT_TRUE(h.options.distance.fuse[1]);
  EXPECT_TRUE(h.options.distance.fuse[2]);
  EXPECT_NEAR(h.record.fused_distance_rmse_m, 0.0, 1e-9);
}

TEST(ChooseDistanceFusion, SigmaLimitIsTheTruthSpreadWhenItLowersTheErrorWithEnoughCoverage) {
  // ttc exact (σ 1 m) except on `missing` of 100 frames; Jeffrey 10 m long (σ 5 m) on all. The
  // truth's spread (1 … 10.9 m) is 2.9 m: Jeffrey alone is above it, with ttc the σ is 0.98 m.
  auto runs_missing = [](int missing) {
    std::vector<CorridorRun> runs(1);
    for (int i = 0; i < 100; ++i) {
      CorridorFrame f;
      const double d = 1.0 + 0.1 * i;
      f.gt.dist_end_m = d;
      f.moving_forward = true;
      if (i >= missing) f.dist_filtered_raw[0] = d;
      f.dist_filtered_raw[1] = d + 10.0;
      runs[0].frames.push_back(f);
    }
    return runs;
  };
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < 100; ++i) sum += 1.0 + 0.1 * i, sum2 += (1.0 + 0.1 * i) * (1.0 + 0.1 * i);
  const double spread = std::sqrt(sum2 / 100.0 - (sum / 100.0) * (sum / 100.0));
  CalibrateOptions all_cues;
  all_cues.select_distance_cues = false;
  CorridorCalibrationFile f = KnownModels();
  f.options.distance.weights = {1.0, 1.0 / 25.0, 1.0};
  CorridorCalibrationFile g = f;
  ChooseDistanceFusion(runs_missing(5), all_cues, f);
  EXPECT_NEAR(f.options.distance.fused_max_std_m, spread, 1e-9);
  EXPECT_EQ(f.options.distance.fuse, (std::array<bool, 3>{true, true, true}));  // not chosen: kept
  // 20 frames without ttc: the limit would leave 80 % < 90 % of the frames, so none.
  ChooseDistanceFusion(runs_missing(20), all_cues, g);
  EXPECT_EQ(g.options.distance.fused_max_std_m, 0.0);
  CalibrateOptions low = all_cues;
  low.min_fused_coverage = 0.8;
  CorridorCalibrationFile h = KnownModels();
  h.options.distance.weights = {1.0, 1.0 / 25.0, 1.0};
  ChooseDistanceFusion(runs_missing(20), low, h);
  EXPECT_NEAR(h.options.distance.fused_max_std_m, spread, 1e-9);
  low.fusion_max_truth_m = 0.0;
  EXPECT_NE(low.Validate().find("fusion_max_truth_m"), std::string::npos);
}

TEST(FitCorridorCalibration, TurnsTheHeadingFilterOnWithEachCuesSigmaUnlessAskedNotTo) {
  const CorridorCalibrationFile on = FitCorridorCalibration(PlantedRuns(), {}, {}, {});
  EXPECT_TRUE(on.options.heading.filter.enabled);
  for (int k = 0; k < corridor::kHeadingCueCount; ++k) {
    EXPECT_GE(on.record.heading[k].error_std_deg, 0.5) << k;
    EXPECT_EQ(on.options.heading.cues[k].std_deg, on.record.heading[k].error_std_deg) << k;
  }
  CalibrateOptions no_filter;
  no_filter.heading_filter = false;
  const CorridorCalibrationFile off = FitCorridorCalibration(PlantedRuns(), {}, {}, no_filter);
  EXPECT_FALSE(off.options.heading.filter.enabled);
  for (int k = 0; k < corridor::kHeadingCueCount; ++k)
    EXPECT_EQ(off.options.heading.cues[k].std_deg, on.options.heading.cues[k].std_deg) << k;
  // A distance-only calibration leaves the base options' heading filter as it was.
  CalibrateOptions distance_only;
  distance_only.fit_heading = false;
  EXPECT_FALSE(FitCorridorCalibration(PlantedRuns(), {}, {}, distance_only).options.heading.filter.enabled);
}

TEST(CalibrationBaseOptions, TurnsTheFarStructureCellsOnUnlessTheBaseSetsThemOrNoDistanceIsFitted) {
  const corridor::CorridorOptions defaults;
  EXPECT_EQ(defaults.distance.ttc_cell_px, 0.0);  // the Perceiver's default: off
  const corridor::CorridorOptions on = CalibrationBaseOptions(defaults, {});
  EXPECT_EQ(on.distance.ttc_cell_px, 6.0);
  EXPECT_EQ(on.distance.ttc_cell_quantile, 0.5);
  EXPECT_EQ(on.distance.ttc_cell_nearest, 8);
  EXPECT_TRUE(on.Validate().empty());
  corridor::CorridorOptions mine;
  mine.distance.ttc_cell_px = 4.0;
  mine.distance.ttc_cell_quantile = 0.3;
  const corridor::CorridorOptions kept = CalibrationBaseOptions(mine, {});
  EXPECT_EQ(kept.distance.ttc_cell_px, 4.0);
  EXPECT_EQ(kept.distance.ttc_cell_quantile, 0.3);
  CalibrateOptions none;
  none.ttc_cell_px = 0.0;
  EXPECT_EQ(CalibrationBaseOptions(defaults, none).distance.ttc_cell_px, 0.0);
  CalibrateOptions heading_only;
  heading_only.fit_distance = false;
  EXPECT_EQ(CalibrationBaseOptions(defaults, heading_only).distance.ttc_cell_px, 0.0);
  CalibrateOptions bad;
  bad.ttc_cell_px = 2.0;
  EXPECT_FALSE(bad.Validate().empty());
  bad.ttc_cell_px = 6.0;
  bad.ttc_cell_quantile = 1.5;
  EXPECT_FALSE(bad.Validate().empty());
  bad.ttc_cell_quantile = 0.5;
  bad.ttc_cell_nearest = -1;
  EXPECT_FALSE(bad.Validate().empty());
  // The written options carry the cells through the file.
  CorridorCalibrationFile file;
  file.options = on;
  const CorridorCalibrationFile back = CalibrationFileFromYaml(CalibrationFileToYaml(file), "mem");
  EXPECT_EQ(back.options.distance.ttc_cell_px, 6.0);
  EXPECT_EQ(back.options.distance.ttc_cell_quantile, 0.5);
  EXPECT_EQ(back.options.distance.ttc_cell_nearest, 8);
}

TEST(CalibrationBaseOptions, TurnsTheFloorMotionTestAndSameSignRefinementOnUnlessTheBaseSetsThemOrNoDistanceIsFitted) {
  const corridor::CorridorOptions defaults;
  EXPECT_EQ(defaults.distance.floor_contact.motion_window_m, 0.0);  // the Perceiver's default: off
  const corridor::CorridorOptions on = CalibrationBaseOptions(defaults, {});
  EXPECT_EQ(on.distance.floor_contact.motion_window_m, 2.0);
  EXPECT_TRUE(on.Validate().empty());
  corridor::CorridorOptions mine;
  mine.distance.floor_contact.motion_window_m = 1.5;
  EXPECT_EQ(CalibrationBaseOptions(mine, {}).distance.floor_contact.motion_window_m, 1.5);
  CalibrateOptions none;
  none.floor_motion_window_m = 0.0;
  EXPECT_EQ(CalibrationBaseOptions(defaults, none).distance.floor_contact.motion_window_m, 0.0);
  CalibrateOptions heading_only;
  heading_only.fit_distance = false;
  EXPECT_EQ(CalibrationBaseOptions(defaults, heading_only).distance.floor_contact.motion_window_m, 0.0);
  EXPECT_FALSE(defaults.distance.floor_contact.refine_same_sign);  // the Perceiver's default
  EXPECT_TRUE(on.distance.floor_contact.refine_same_sign);
  CalibrateOptions keep_base;
  keep_base.floor_refine_same_sign = false;
  EXPECT_FALSE(CalibrationBaseOptions(defaults, keep_base).distance.floor_contact.refine_same_sign);
  EXPECT_FALSE(CalibrationBaseOptions(defaults, heading_only).distance.floor_contact.refine_same_sign);
  CalibrateOptions bad;
  bad.floor_motion_window_m = -1.0;
  EXPECT_NE(bad.Validate().find("floor_motion_window_m"), std::string::npos);
  // The lined-wall rule: 0.5 unless the base sets one or asks to keep the base's.
  EXPECT_EQ(defaults.distance.floor_contact.lined_wall_rel_step, 0.0);  // the Perceiver's default
  EXPECT_EQ(on.distance.floor_contact.lined_wall_rel_step, 0.5);
  corridor::CorridorOptions mine_lined;
  mine_lined.distance.floor_contact.lined_wall_rel_step = 0.7;
  EXPECT_EQ(CalibrationBaseOptions(mine_lined, {}).distance.floor_contact.lined_wall_rel_step, 0.7);
  CalibrateOptions keep_lined;
  keep_lined.floor_lined_wall_rel_step = 0.0;
  EXPECT_EQ(CalibrationBaseOptions(defaults, keep_lined).distance.floor_contact.lined_wall_rel_step, 0.0);
  EXPECT_EQ(CalibrationBaseOptions(defaults, heading_only).distance.floor_contact.lined_wall_rel_step, 0.0);
  CalibrateOptions bad_lined;
  bad_lined.floor_lined_wall_rel_step = 1.5;
  EXPECT_NE(bad_lined.Validate().find("floor_lined_wall_rel_step"), std::string::npos);
  CorridorCalibrationFile file;
  file.options = on;
  const CorridorCalibrationFile back = CalibrationFileFromYaml(CalibrationFileToYaml(file), "mem");
  EXPECT_EQ(back.options.distance.floor_contact.motion_window_m, 2.0);
}

// The fused distance's RMSE over the judged frames (driving forward, truth within the window and
// up to fusion_max_truth_m): frames off by 1 m and 3 m give sqrt(5); a frame without a fused
// distance counts in `frames`, not in `answered`; a frame beyond 15 m or standing is not judged.
TEST(FusedDistanceRmse, JudgesTheFusionFramesOnly) {
  std::vector<CorridorRun> runs(1);
  auto add = [&runs](double truth, std::optional<double> fused, bool forward) {
    CorridorFrame f;
    f.gt.dist_end_m = truth;
    f.fused_dist_m = fused;
    f.moving_forward = forward;
    runs[0].frames.push_back(f);
  };
  add(10.0, 11.0, true);
  add(5.0, 2.0, true);
  add(4.0, std::nullopt, true);
  add(20.0, 0.0, true);   // beyond fusion_max_truth_m (15 m)
  add(6.0, 60.0, false);  // standing
  const CueRmse r = FusedDistanceRmse(runs, CalibrateOptions{});
  EXPECT_EQ(r.frames, 3u);
  EXPECT_EQ(r.answered, 2u);
  EXPECT_NEAR(r.rmse_m, std::sqrt(5.0), 1e-12);
  EXPECT_TRUE(std::isinf(FusedDistanceRmse({}, CalibrateOptions{}).rmse_m));
}

TEST(KeepFloorMotion, OnlyWhenItLowersTheFusedRmseWithoutLosingFrames) {
  const CueRmse without{2.0, 90, 100};
  EXPECT_TRUE(KeepFloorMotion({1.5, 90, 100}, without));
  EXPECT_FALSE(KeepFloorMotion({2.0, 90, 100}, without));  // no gain
  EXPECT_FALSE(KeepFloorMotion({2.5, 90, 100}, without));
  EXPECT_FALSE(KeepFloorMotion({1.0, 89, 100}, without));  // fewer frames answered
}

TEST(FitCorridorCalibration, RefusesRunsWithoutTruthOrWithOneHeading) {
  std::vector<CorridorRun> runs = PlantedRuns();
  for (auto& r : runs)
    for (auto& f : r.frames) f.gt.heading_deg = 3.0;  // all headings equal
  EXPECT_THROW(FitCorridorCalibration(runs, {}, {}, {}), Error);
  CalibrateOptions only_distance;
  only_distance.fit_heading = false;
  EXPECT_NO_THROW(FitCorridorCalibration(runs, {}, {}, only_distance));
  for (auto& r : runs)
    for (auto& f : r.frames) f.gt.dist_end_m = 4.0;  // one distance only
  EXPECT_THROW(FitCorridorCalibration(runs, {}, {}, only_distance), Error);
  for (auto& r : runs)
    for (auto& f : r.frames) f.gt.dist_end_m.reset();
  EXPECT_THROW(FitCorridorCalibration(runs, {}, {}, only_distance), Error);
}

TEST(CorridorReport, KnownErrorsGiveKnownNumbersAndFiles) {
  CorridorRun run;
  run.name = "constructed";
  for (int i = 0; i < 100; ++i) {
    CorridorFrame f;
    f.index = static_cast<std::size_t>(i);
    f.gt.heading_deg = -10.0 + 0.2 * i;
    f.fused_heading_deg = *f.gt.heading_deg + (i % 2 ? 2.0 : -2.0);  // RMSE exactly 2
    f.kalman_heading_deg = *f.gt.heading_deg;
    f.fused_instant_heading_deg = *f.gt.heading_deg + 3.0;  // RMSE exactly 3
    f.gt.dist_end_m = 10.0 - 0.1 * i;
    f.moving_forward = true;
    f.fused_dist_m = i < 50 ? std::optional<double>(*f.gt.dist_end_m + 1.0) : std::nullopt;
    f.gated_processed = i % 4 == 0;
    f.gate_change = 0.001 * (i % 10);
    f.gated_heading_deg = f.gated_processed ? f.fused_heading_deg : std::nullopt;
    run.frames.push_back(f);
  }
  const fs::path dir = TempDir("report");
  CorridorEvalOptions o;
  o.plot_width_px = 320;
  o.plot_height_px = 240;
  const std::string text = WriteCorridorReport({run}, dir, o, {"a warning"}, "");
  const nlohmann::json r = nlohmann::json::parse(text);
  EXPECT_NEAR(r["heading"]["fused"]["rmse_deg"].get<double>(), 2.0, 1e-12);
  EXPECT_NEAR(r["heading"]["kalman"]["rmse_deg"].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(r["heading"]["fused_instant"]["rmse_deg"].get<double>(), 3.0, 1e-12);
  EXPECT_NEAR(r["distance"]["fused"]["rmse_m"].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(r["distance"]["fused"]["coverage"].get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(r["rapid_perception"]["fraction_processed"].get<double>(), 0.25, 1e-12);
  EXPECT_EQ(r["rapid_perception"]["sequences"][0]["processed_per_block"],
            (nlohmann::json{13, 12}));
  EXPECT_EQ(r["warnings"][0], "a warning");
  EXPECT_TRUE(fs::exists(dir / "report.json"));
  EXPECT_TRUE(fs::exists(dir / "heading_fused.png"));
  EXPECT_TRUE(fs::exists(dir / "sign_fused.png"));
  EXPECT_TRUE(fs::exists(dir / "distance_fused.png"));
  EXPECT_TRUE(fs::exists(dir / "rapid_processed.png"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace squint::eval
