// The corridor options YAML (`--calib`): round trip of every member, partial files over defaults,
// and one clear error for unknown keys, wrong types and invalid values.
#include "squint/config/corridor_yaml.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "squint/core/error.hpp"

namespace squint::config {
namespace {

using corridor::CorridorOptions;

TEST(CorridorYaml, RoundTripKeepsEveryMember) {
  CorridorOptions o;
  o.sampling = corridor::GlanceSampling::kArea;
  o.heading.cues[3].weight = 0.123456789;
  o.heading.cues[4].scale = 1.1;
  o.heading.cues[0].bias_deg = -2.5;
  o.heading.cues[2].enabled = false;
  o.heading.slice_width_px = 5;
  o.heading.agreement_deg = 7.25;
  o.heading.min_consensus_cues = 3;
  o.heading.max_abs_heading_deg = 33.0;
  o.heading.fuse_curves = false;
  o.heading.symmetry_significance = false;
  o.heading.phase_line_vote = false;
  o.heading.phase_min_vertical_deg = 12.5;
  o.heading.phase_min_horizon_rows = 3.5;
  o.heading.cues[1].std_deg = 11.25;
  o.heading.filter.enabled = true;
  o.heading.filter.process_std_deg = 0.45;
  o.heading.filter.process_std_deg_per_sqrt_s = 0.375;
  o.heading.filter.odom_noise_fraction = 0.125;
  o.heading.filter.no_odom_std_deg = 2.5;
  o.heading.filter.gate_chi2 = 6.25;
  o.heading.filter.reinit_after_rejections = 13;
  o.distance.weights = {3.0, 0.5, 0.25};
  o.distance.enabled[1] = false;
  o.distance.alpha2 = 123.5;
  o.distance.beta2 = 17.0;
  o.distance.alpha3 = 0.07;
  o.distance.ttc_scale = 0.9;
  o.distance.ttc_bias_m = 0.3;
  o.distance.min_m = 0.2;
  o.distance.max_m = 40.0;
  o.distance.valid_min_m = {0.5, 1.0, 2.0};
  o.distance.valid_max_m = {9.0, 20.0, 30.0};
  o.distance.error_growth_per_m = {0.1, 0.2, 0.3};
  o.distance.median_frames = 7;
  o.distance.ttc_max_baseline_frames = 12;
  o.distance.ttc_baseline_fraction = 0.07;
  o.distance.ttc_centre_at_horizon = false;
  o.distance.ttc_gain_compensation = true;
  o.distance.ttc_cell_px = 5.0;
  o.distance.ttc_cell_quantile = 0.3;
  o.distance.ttc_cell_min_count = 4;
  o.distance.ttc_cell_max_se_fraction = 0.6;
  o.distance.ttc_cell_min_expansion = 0.03;
  o.distance.ttc_cell_nearest = 5;
  o.distance.ttc_cell_nearest_at_min_window = true;
  o.distance.floor_contact.enabled = false;
  o.distance.floor_contact.half_width_deg = 3.5;
  o.distance.floor_contact.min_step = 7.25;
  o.distance.floor_contact.min_column_fraction = 0.75;
  o.distance.floor_contact.min_m = 0.5;
  o.distance.floor_contact.max_m = 12.5;
  o.distance.floor_contact.motion_window_m = 1.75;
  o.distance.floor_contact.motion_tol_rows = 0.75;
  o.distance.floor_contact.motion_min_fraction = 0.6;
  o.distance.floor_contact.motion_min_readings = 7;
  o.distance.floor_contact.refine_same_sign = true;
  o.distance.floor_contact.lined_wall_rel_step = 0.625;
  o.distance.floor_contact.overrides_fusion = false;
  o.distance.floor_contact.agreement_ratio = 0.25;
  o.gate.threshold = 0.02;
  o.gate.enabled = false;
  o.gate.compare_with_last_processed = false;
  o.gate.max_skipped_frames = 5;
  const std::string text = CorridorOptionsToYaml(o);
  const CorridorOptions back = CorridorOptionsFromYaml(text, "test.yaml");
  EXPECT_EQ(CorridorOptionsToYaml(back), text);
  EXPECT_EQ(back.sampling, o.sampling);
  EXPECT_EQ(back.heading.cues[3].weight, o.heading.cues[3].weight);
  EXPECT_EQ(back.heading.cues[4].scale, 1.1);
  EXPECT_EQ(back.heading.cues[0].bias_deg, -2.5);
  EXPECT_FALSE(back.heading.cues[2].enabled);
  EXPECT_EQ(back.heading.slice_width_px, 5);
  EXPECT_EQ(back.heading.min_consensus_cues, 3);
  EXPECT_FALSE(back.heading.fuse_curves);
  EXPECT_FALSE(back.heading.symmetry_significance);
  EXPECT_FALSE(back.heading.phase_line_vote);
  EXPECT_EQ(back.heading.phase_min_vertical_deg, 12.5);
  EXPECT_EQ(back.heading.phase_min_horizon_rows, 3.5);
  EXPECT_EQ(back.heading.cues[1].std_deg, 11.25);
  EXPECT_EQ(back.heading.cues[0].std_deg, CorridorOptions{}.heading.cues[0].std_deg);
  EXPECT_TRUE(back.heading.filter.enabled);
  EXPECT_EQ(back.heading.filter.process_std_deg, 0.45);
  EXPECT_EQ(back.heading.filter.process_std_deg_per_sqrt_s, 0.375);
  EXPECT_EQ(back.heading.filter.odom_noise_fraction, 0.125);
  EXPECT_EQ(back.heading.filter.no_odom_std_deg, 2.5);
  EXPECT_EQ(back.heading.filter.gate_chi2, 6.25);
  EXPECT_EQ(back.heading.filter.reinit_after_rejections, 13);
  EXPECT_EQ(back.distance.weights, o.distance.weights);
  EXPECT_EQ(back.distance.enabled, o.distance.enabled);
  EXPECT_EQ(back.distance.alpha2, 123.5);
  EXPECT_EQ(back.distance.max_m, 40.0);
  EXPECT_EQ(back.distance.valid_min_m, o.distance.valid_min_m);
  EXPECT_EQ(back.distance.valid_max_m, o.distance.valid_max_m);
  EXPECT_EQ(back.distance.error_growth_per_m, o.distance.error_growth_per_m);
  EXPECT_EQ(back.distance.median_frames, 7);
  EXPECT_EQ(back.distance.ttc_max_baseline_frames, 12);
  EXPECT_EQ(back.distance.ttc_baseline_fraction, 0.07);
  EXPECT_FALSE(back.distance.ttc_centre_at_horizon);
  EXPECT_TRUE(back.distance.ttc_gain_compensation);
  EXPECT_EQ(back.distance.ttc_cell_px, 5.0);
  EXPECT_EQ(back.distance.ttc_cell_quantile, 0.3);
  EXPECT_EQ(back.distance.ttc_cell_min_count, 4);
  EXPECT_EQ(back.distance.ttc_cell_max_se_fraction, 0.6);
  EXPECT_EQ(back.distance.ttc_cell_min_expansion, 0.03);
  EXPECT_EQ(back.distance.ttc_cell_nearest, 5);
  EXPECT_TRUE(back.distance.ttc_cell_nearest_at_min_window);
  EXPECT_FALSE(back.distance.floor_contact.enabled);
  EXPECT_EQ(back.distance.floor_contact.motion_window_m, 1.75);
  EXPECT_EQ(back.distance.floor_contact.motion_tol_rows, 0.75);
  EXPECT_EQ(back.distance.floor_contact.motion_min_fraction, 0.6);
  EXPECT_EQ(back.distance.floor_contact.motion_min_readings, 7);
  EXPECT_TRUE(back.distance.floor_contact.refine_same_sign);
  EXPECT_EQ(back.distance.floor_contact.lined_wall_rel_step, 0.625);
  EXPECT_EQ(back.distance.floor_contact.half_width_deg, 3.5);
  EXPECT_EQ(back.distance.floor_contact.min_step, 7.25);
  EXPECT_EQ(back.distance.floor_contact.min_column_fraction, 0.75);
  EXPECT_EQ(back.distance.floor_contact.min_m, 0.5);
  EXPECT_EQ(back.distance.floor_contact.max_m, 12.5);
  EXPECT_FALSE(back.distance.floor_contact.overrides_fusion);
  EXPECT_EQ(back.distance.floor_contact.agreement_ratio, 0.25);
  EXPECT_EQ(back.gate.threshold, 0.02);
  EXPECT_FALSE(back.gate.enabled);
  EXPECT_FALSE(back.gate.compare_with_last_processed);
  EXPECT_EQ(back.gate.max_skipped_frames, 5);
}

TEST(CorridorYaml, PartialFileKeepsDefaults) {
  const CorridorOptions o = CorridorOptionsFromYaml("heading:\n  cues:\n    bright: {bias_deg: 1.5}\n", "p.yaml");
  const CorridorOptions d;
  EXPECT_EQ(o.heading.cues[4].bias_deg, 1.5);
  EXPECT_EQ(o.heading.cues[4].weight, d.heading.cues[4].weight);
  EXPECT_EQ(o.distance.alpha2, d.distance.alpha2);
  EXPECT_EQ(CorridorOptionsToYaml(CorridorOptionsFromYaml("", "empty.yaml")), CorridorOptionsToYaml(d));
}

TEST(CorridorYaml, BadInputIsOneClearError) {
  auto message = [](const std::string& text) {
    try {
      CorridorOptionsFromYaml(text, "calib.yaml");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("heading: {slice_widht_px: 3}").find("unknown key 'heading.slice_widht_px'"), std::string::npos);
  EXPECT_NE(message("distance: {alpha2: abc}").find("'distance.alpha2' has a value of the wrong type"), std::string::npos);
  EXPECT_NE(message("gate: {threshold: -1}").find("gate.threshold must be >= 0"), std::string::npos);
  EXPECT_NE(message("glance: {sampling: bilinear}").find("point or area"), std::string::npos);
  EXPECT_NE(message("heading: {filter: {enable: true}}").find("unknown key 'heading.filter.enable'"), std::string::npos);
  EXPECT_NE(message("heading: {filter: {process_std_deg_per_sqrt_s: -0.1}}").find("heading.filter.process_std_deg_per_sqrt_s must be >= 0"), std::string::npos);
  EXPECT_NE(message("heading: {filter: {gate_chi2: 0}}").find("heading.filter.gate_chi2 must be > 0"), std::string::npos);
  EXPECT_NE(message("heading: {filter: {reinit_after_rejections: 1.5}}").find("'heading.filter.reinit_after_rejections' has a value of the wrong type"), std::string::npos);
  EXPECT_NE(message("heading: {cues: {phase: {std_deg: -1}}}").find("heading.cues.phase.std_deg must be > 0"), std::string::npos);
  EXPECT_NE(message("heading: [1, 2").find("not valid YAML"), std::string::npos);
  EXPECT_NE(message("distance: {floor_contact: {lined_wall_rel_step: 2}}").find("lined_wall_rel_step must be in [0, 1]"),
            std::string::npos);
  for (const std::string& m : {message("x: 1"), message("gate: {threshold: -1}")})
    EXPECT_EQ(m.rfind("calib.yaml: ", 0), 0u) << m;
  EXPECT_THROW(LoadCorridorOptions("/nonexistent/calib.yaml"), Error);
}

TEST(CorridorYaml, SaveAndLoadFile) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "squint_corridor_yaml_test.yaml";
  CorridorOptions o;
  o.distance.alpha3 = 0.11;
  SaveCorridorOptions(path, o);
  EXPECT_EQ(LoadCorridorOptions(path).distance.alpha3, 0.11);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace squint::config
