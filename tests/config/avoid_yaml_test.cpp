// Tests of the avoidance options YAML: round trip, the shared file with `ipt:`, named errors.
#include "squint/config/avoid_yaml.hpp"

#include <gtest/gtest.h>

#include "squint/core/error.hpp"

namespace squint::config {
namespace {

std::string ErrorOf(const std::string& text) {
  try {
    AvoidOptionsFromYaml(text, "opts.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

TEST(AvoidYamlTest, RoundTripKeepsEveryMember) {
  obstacles::AvoidOptions o;
  o.edges.sigma_px = 1.7;
  o.edges.low_threshold = 12.5;
  o.edges.high_threshold = 33.25;
  o.outline.window_width_px = 7;
  o.outline.window_height_px = 21;
  o.outline.ground_stop_radius_px = 3;
  o.outline.max_gap_rows = 2;
  o.edges.base_edges = false;
  o.outline.base_trace = false;
  o.outline.base_below_features = false;
  o.outline.base_max_rise_px = 3;
  o.outline.base_min_step = 12.5;
  o.polar.roi_radius_m = 2.25;
  o.polar.sector_deg = 4.5;
  o.polar.min_contacts = 3;
  o.polar.free_needs_ground = true;
  o.polar.min_ground_features = 2;
  o.polar.min_ground_range_m = 0.9;
  o.gap.robot_radius_m = 0.31;
  o.gap.margin_m = 0.07;
  o.memory.decisions = 6;
  o.memory.radius_m = 1.25;
  const obstacles::AvoidOptions back = AvoidOptionsFromYaml(AvoidOptionsToYaml(o), "round-trip");
  EXPECT_EQ(back.edges.sigma_px, o.edges.sigma_px);
  EXPECT_EQ(back.edges.low_threshold, o.edges.low_threshold);
  EXPECT_EQ(back.edges.high_threshold, o.edges.high_threshold);
  EXPECT_EQ(back.outline.window_width_px, o.outline.window_width_px);
  EXPECT_EQ(back.outline.window_height_px, o.outline.window_height_px);
  EXPECT_EQ(back.outline.ground_stop_radius_px, o.outline.ground_stop_radius_px);
  EXPECT_EQ(back.outline.max_gap_rows, o.outline.max_gap_rows);
  EXPECT_EQ(back.polar.roi_radius_m, o.polar.roi_radius_m);
  EXPECT_EQ(back.polar.sector_deg, o.polar.sector_deg);
  EXPECT_EQ(back.polar.min_contacts, o.polar.min_contacts);
  EXPECT_EQ(back.polar.free_needs_ground, o.polar.free_needs_ground);
  EXPECT_EQ(back.polar.min_ground_features, o.polar.min_ground_features);
  EXPECT_EQ(back.polar.min_ground_range_m, o.polar.min_ground_range_m);
  EXPECT_EQ(back.gap.robot_radius_m, o.gap.robot_radius_m);
  EXPECT_EQ(back.gap.margin_m, o.gap.margin_m);
  EXPECT_EQ(back.memory.decisions, o.memory.decisions);
  EXPECT_EQ(back.memory.radius_m, o.memory.radius_m);
  EXPECT_EQ(back.edges.base_edges, o.edges.base_edges);
  EXPECT_EQ(back.outline.base_trace, o.outline.base_trace);
  EXPECT_EQ(back.outline.base_below_features, o.outline.base_below_features);
  EXPECT_EQ(back.outline.base_max_rise_px, o.outline.base_max_rise_px);
  EXPECT_EQ(back.outline.base_min_step, o.outline.base_min_step);
  EXPECT_EQ(AvoidOptionsToYaml(back), AvoidOptionsToYaml(o));
}

TEST(AvoidYamlTest, AbsentKeysKeepDefaultsAndTheIptSectionIsIgnored) {
  const auto o = AvoidOptionsFromYaml("ipt:\n  whatever: 1\navoid:\n  polar: {roi_radius_m: 2.0}\n", "f");
  EXPECT_EQ(o.polar.roi_radius_m, 2.0);
  EXPECT_EQ(o.polar.sector_deg, obstacles::PolarMapOptions{}.sector_deg);
  EXPECT_EQ(o.edges.low_threshold, 40.0);
  EXPECT_EQ(o.edges.high_threshold, 50.0);
}

TEST(AvoidYamlTest, TheSharedFileFeedsBothReaders) {
  const auto both = AvoidFileOptionsFromYaml(
      "ipt:\n  min_translation_m: 0.01\navoid:\n  gap: {margin_m: 0.1}\n", "f.yaml");
  EXPECT_EQ(both.ipt.min_translation_m, 0.01);
  EXPECT_EQ(both.avoid.gap.margin_m, 0.1);
}

TEST(AvoidYamlTest, TheFlatIptFormatFeedsBothReadersToo) {
  const auto both = AvoidFileOptionsFromYaml(
      "features: {detector: orb}\nmin_translation_m: 0.02\navoid:\n  polar: {sector_deg: 10}\n", "f.yaml");
  EXPECT_EQ(both.ipt.features.detector, obstacles::Detector::kOrb);
  EXPECT_EQ(both.ipt.min_translation_m, 0.02);
  EXPECT_EQ(both.avoid.polar.sector_deg, 10.0);
  // Mistakes in the IPT part are still named.
  try {
    AvoidFileOptionsFromYaml("ipt:\n  features: {ratio: abc}\navoid: {}\n", "f.yaml");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("f.yaml (section ipt): `features.ratio`"), std::string::npos) << e.what();
  }
}

TEST(AvoidYamlTest, ErrorsNameTheFileAndKey) {
  EXPECT_NE(ErrorOf("avoid:\n  polar: {radius: 2}\n").find("opts.yaml: `avoid.polar.radius` is not a known option"),
            std::string::npos);
  EXPECT_NE(ErrorOf("avoid:\n  edges: {low_threshold: abc}\n").find("`avoid.edges.low_threshold` must be a number"),
            std::string::npos);
  EXPECT_NE(ErrorOf("avoid:\n  edges: {low_threshold: 60}\n").find("high_threshold"), std::string::npos);
  EXPECT_NE(ErrorOf("avod:\n  edges: {}\n").find("`avod` is not a known section"), std::string::npos);
  EXPECT_NE(ErrorOf("avoid: [1, 2\n").find("not valid YAML"), std::string::npos);
  EXPECT_NE(ErrorOf("avoid:\n  polar: {sector_deg: 7}\n").find("sector_deg"), std::string::npos);
  EXPECT_NE(ErrorOf("avoid:\n  memory: {decisions: -1}\n").find("memory.decisions must be in [0, 1000]"),
            std::string::npos);
  EXPECT_NE(ErrorOf("avoid:\n  memory: {frames: 3}\n").find("`avoid.memory.frames` is not a known option"),
            std::string::npos);
}

}  // namespace
}  // namespace squint::config
