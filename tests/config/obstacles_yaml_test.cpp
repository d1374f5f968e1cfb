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
  o.features.sift_first_octave = -1;
  o.mirror_aware = false;
  const auto back = IptOptionsFromYaml(IptOptionsToYaml(o), "roundtrip");
  EXPECT_EQ(IptOptionsToYaml(back), IptOptionsToYaml(o));
  EXPECT_EQ(back.features.detector, obstacles::Detector::kKlt);
  EXPECT_EQ(back.features.max_features, 123);
  EXPECT_DOUBLE_EQ(*back.classifier.zones[1].refine_high_m, 0.0912345678);
  EXPECT_FALSE(back.classifier.zones[0].refine_high_m.has_value());
  EXPECT_FALSE(back.classifier.refinement);
  EXPECT_EQ(back.features.sift_first_octave, -1);
  EXPECT_FALSE(back.mirror_aware);
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
  EXPECT_NE(ErrorOf("features: {sift_first_octave: 1}").find("sift_first_octave must be -1 or 0"), std::string::npos);
  EXPECT_NE(ErrorOf("mirror_aware: maybe").find("mirror_aware"), std::string::npos);
  for (const char* t : {"features: {detector: surf}", "bogus: 1", "a: [unclosed"})
    EXPECT_EQ(ErrorOf(t).rfind("opts.yaml", 0), 0u) << t;
  EXPECT_THROW(LoadIptOptions("/nonexistent/opts.yaml"), Error);
}

// One options file serves `squint obstacles` and `squint avoid`: the IPT reader takes the `ipt:`
// section (or its keys at the top level) and skips the other commands' sections.
TEST(ObstaclesYaml, SharedFileWithAnAvoidSection) {
  const std::string shared =
      "ipt:\n  features: {detector: orb, max_features: 77}\n  min_translation_m: 0.01\n"
      "avoid:\n  polar: {roi_radius_m: 2.0}\n  gap: {margin_m: 0.1}\n";
  const auto a = IptOptionsFromYaml(shared, "shared.yaml");
  EXPECT_EQ(a.features.detector, obstacles::Detector::kOrb);
  EXPECT_EQ(a.features.max_features, 77);
  EXPECT_EQ(a.min_translation_m, 0.01);
  // The flat format beside an `avoid:` (and the other readers') sections.
  const auto b = IptOptionsFromYaml(
      "features: {detector: klt}\nfundamental: {min_matches: 20}\navoid:\n  gap: {margin_m: 0.1}\n"
      "corridor: {}\nexplore: {}\nsim: {}\n",
      "flat.yaml");
  EXPECT_EQ(b.features.detector, obstacles::Detector::kKlt);
  EXPECT_EQ(b.fundamental.min_matches, 20);
  // Only other sections: the defaults.
  EXPECT_EQ(IptOptionsToYaml(IptOptionsFromYaml("avoid:\n  gap: {margin_m: 0.1}\n", "x")),
            IptOptionsToYaml(obstacles::IptOptions{}));
  EXPECT_EQ(IptOptionsToYaml(IptOptionsFromYaml("ipt:\navoid: {}\n", "x")), IptOptionsToYaml(obstacles::IptOptions{}));
  // A round trip through the section.
  obstacles::IptOptions o;
  o.features.max_features = 321;
  o.classifier.zones[1] = {0.03, 0.07};
  std::string nested = "ipt:\n";
  const std::string flat = IptOptionsToYaml(o);
  for (std::size_t i = 0; i < flat.size();) {
    const std::size_t j = flat.find('\n', i);
    nested += "  " + flat.substr(i, j - i) + "\n";
    i = j + 1;
  }
  EXPECT_EQ(IptOptionsToYaml(IptOptionsFromYaml(nested + "avoid: {}\n", "n")), flat);
}

TEST(ObstaclesYaml, SharedFileMistakesAreNamed) {
  EXPECT_NE(ErrorOf("ipt:\n  features: {detector: surf}\navoid: {}\n").find("opts.yaml (section ipt): `features.detector`"),
            std::string::npos);
  EXPECT_NE(ErrorOf("ipt:\n  featurs: {}\n").find("`featurs` is not a known option"), std::string::npos);
  EXPECT_NE(ErrorOf("ipt:\n  features: {}\nfundamental: {}\n").find("`fundamental` must not stand at the top level"),
            std::string::npos);
  EXPECT_NE(ErrorOf("avod: {}\n").find("`avod` is not a known option"), std::string::npos);
  EXPECT_NE(ErrorOf("ipt: [1, 2]\n").find("must be a mapping"), std::string::npos);
}

}  // namespace
}  // namespace squint::config
