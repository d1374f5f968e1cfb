// The obstacles options file: round trip, defaults for absent keys, and one clear error per mistake.
#include "squint/config/obstacles_yaml.hpp"

#include <gtest/gtest.h>

#include "squint/core/error.hpp"

namespace squint::config {
namespace {

std::string ErrorOf(const std::string& text) {
  try {
    IptOptionsFromYaml(text, "opts.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ObstaclesYaml, RoundTripKeepsEveryMember) {
  obstacles::IptOptions o;
  o.features.detector = obstacles::Detector::kKlt;
  o.features.max_features = 123;
  o.fundamental.inlier_threshold_px = 0.75;
  o.classifier.zones[0] = {0.0123, std::nullopt};
  o.classifier.zones[1] = {0.031, 0.0912345678};
  o.classifier.zones[2] = {0.2, 0.5};
  o.classifier.refinement = false;
  o.classifier.zoning.dst_m = 2.0;
  o.min_translation_m = 0.002;
  const auto back = IptOptionsFromYaml(IptOptionsToYaml(o), "roundtrip");
  EXPECT_EQ(IptOptionsToYaml(back), IptOptionsToYaml(o));
  EXPECT_EQ(back.features.detector, obstacles::Detector::kKlt);
  EXPECT_EQ(back.features.max_features, 123);
  EXPECT_DOUBLE_EQ(*back.classifier.zones[1].refine_high_m, 0.0912345678);
  EXPECT_FALSE(back.classifier.zones[0].refine_high_m.has_value());
  EXPECT_FALSE(back.classifier.refinement);
}

TEST(ObstaclesYaml, AbsentKeysKeepDefaults) {
  const auto o = IptOptionsFromYaml("features: {detector: orb}\n", "x");
  EXPECT_EQ(o.features.detector, obstacles::Detector::kOrb);
  EXPECT_EQ(IptOptionsToYaml(IptOptionsFromYaml("", "x")), IptOptionsToYaml(obstacles::IptOptions{}));
}

TEST(ObstaclesYaml, MistakesNameTheFileAndKey) {
  EXPECT_NE(ErrorOf("features: {detector: surf}").find("features.detector"), std::string::npos);
  EXPECT_NE(ErrorOf("features: {max_featurs: 3}").find("features.max_featurs"), std::string::npos);
  EXPECT_NE(ErrorOf("features: {ratio: abc}").find("features.ratio"), std::string::npos);
  EXPECT_NE(ErrorOf("features: {ratio: 2.0}").find("ratio"), std::string::npos);
  EXPECT_NE(ErrorOf("classifier: {zones: [{beta_m: 0.1}]}").find("classifier.zones"), std::string::npos);
  EXPECT_NE(ErrorOf("classifier: {zones: [{beta_m: 0.1}, {beta_m: 0.1, refine_high_m: 0.05}, {beta_m: 1}]}").find("refine_high_m"),
            std::string::npos);
  EXPECT_NE(ErrorOf("fundamental: [1, 2]").find("fundamental"), std::string::npos);
  EXPECT_NE(ErrorOf("a: [unclosed").find("not valid YAML"), std::string::npos);
  EXPECT_NE(ErrorOf("min_translation_m: .nan").find("min_translation_m"), std::string::npos);
  for (const char* t : {"features: {detector: surf}", "bogus: 1", "a: [unclosed"})
    EXPECT_EQ(ErrorOf(t).rfind("opts.yaml", 0), 0u) << t;
  EXPECT_THROW(LoadIptOptions("/nonexistent/opts.yaml"), Error);
}

}  // namespace
}  // namespace squint::config
