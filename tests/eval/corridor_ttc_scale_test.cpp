// The calibration's judge of time to contact's image scale (eval::TtcCalibrationRmse): the
// time-to-contact cue's own error on the distance fusion's frames, and the candidates' options.
#include <gtest/gtest.h>

#include <cmath>

#include "squint/eval/corridor_eval.hpp"

namespace squint::eval {
namespace {

TEST(TtcCalibrationRmse, TheCueOwnErrorOnTheFusionFrames) {
  std::vector<CorridorRun> runs(1);
  for (int i = 0; i < 100; ++i) {
    CorridorFrame f;
    const double d = 1.0 + 0.1 * i;
    f.gt.dist_end_m = d;
    f.moving_forward = true;
    if (i % 4 != 3) f.dist_filtered_raw[0] = d + (i % 2 == 0 ? 0.3 : -0.3);  // ±0.3 m, 75 answered
    f.dist_filtered_raw[1] = d + 5.0;  // Jeffrey: not judged
    runs[0].frames.push_back(f);
  }
  CorridorFrame beyond;  // beyond fusion_max_truth_m (15 m): not counted
  beyond.gt.dist_end_m = 20.0;
  beyond.moving_forward = true;
  beyond.dist_filtered_raw[0] = 60.0;
  runs[0].frames.push_back(beyond);
  CorridorFrame standing;  // not driving forward: not counted
  standing.gt.dist_end_m = 5.0;
  standing.dist_filtered_raw[0] = 50.0;
  runs[0].frames.push_back(standing);
  CorridorCalibrationFile file;
  const CueRmse r = TtcCalibrationRmse(runs, CalibrateOptions{}, file);
  EXPECT_EQ(r.frames, 100u);
  EXPECT_EQ(r.answered, 75u);
  EXPECT_NEAR(r.rmse_m, 0.3, 1e-9);
  // The fitted model applies: a scale of 2 doubles every estimate.
  file.options.distance.ttc_scale = 2.0;
  EXPECT_GT(TtcCalibrationRmse(runs, CalibrateOptions{}, file).rmse_m, 3.0);
  // No estimate: infinite.
  for (CorridorFrame& f : runs[0].frames) f.dist_filtered_raw[0].reset();
  const CueRmse none = TtcCalibrationRmse(runs, CalibrateOptions{}, file);
  EXPECT_EQ(none.answered, 0u);
  EXPECT_TRUE(std::isinf(none.rmse_m));
}

TEST(CalibrationBaseOptions, TtcGlanceScaleWrittenOnlyWhenTheBaseKeepsTheGlance) {
  CalibrateOptions fit;
  EXPECT_TRUE(fit.ttc_glance_scales.empty());  // no choice by default (session 7)
  fit.ttc_glance_scale = 1.5;
  corridor::CorridorOptions base;
  const corridor::CorridorOptions out = CalibrationBaseOptions(base, fit);
  EXPECT_EQ(out.distance.ttc_glance_scale, 1.5);
  base.distance.ttc_glance_scale = 2.0;  // the base's own scale stands
  EXPECT_EQ(CalibrationBaseOptions(base, fit).distance.ttc_glance_scale, 2.0);
  fit.ttc_glance_scales = {1.0, 5.0};
  EXPECT_NE(fit.Validate().find("ttc_glance_scales"), std::string::npos);
  fit.ttc_glance_scales = {1.0, 1.5};
  fit.ttc_glance_scale = 0.5;
  EXPECT_NE(fit.Validate().find("ttc_glance_scale"), std::string::npos);
}

}  // namespace
}  // namespace squint::eval
