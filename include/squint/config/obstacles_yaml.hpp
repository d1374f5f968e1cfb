// The obstacle-detection options file (`squint obstacles --options FILE`): a YAML mirror of
// obstacles::IptOptions. Every key is optional; absent keys keep the struct's defaults. The
// learned zone thresholds (`squint eval obstacles` writes them) live under `classifier.zones`.
//
//   features:                 # FeatureOptions, same member names
//     detector: sift          # sift | orb | akaze | klt
//     max_features: 400
//     ratio: 0.8
//     ...
//   fundamental: {inlier_threshold_px: 1.0, confidence: 0.999, max_iterations: 2000,
//                 max_refinements: 10, min_matches: 12}
//   classifier:
//     zone_beta: true         # false: one β (zones[0].beta_m) everywhere, no refinement
//     refinement: true
//     zones:                  # zones 0 (bottom), 1, 2 (just below the horizon)
//       - {beta_m: 0.021}
//       - {beta_m: 0.025, refine_high_m: 0.085}
//       - {beta_m: 0.090}
//     zoning: {dst_m: 1.5, step_m: 0.031, zone2_min_d_m: 0.08, zone0_max_d_m: 0.001}
//   min_translation_m: 0.005
//   pure_rotation_deg: 0.5
//
// The same keys may instead sit under a top-level `ipt:` section, so that one file also holds
// the other commands' sections (`avoid:`, `corridor:`, `explore:`, `sim:`), which this reader
// ignores (config/avoid_yaml.hpp reads `avoid:`).
#pragma once

#include <filesystem>
#include <string>

#include "squint/obstacles/ipt_pipeline.hpp"

namespace squint::config {

// The top-level keys of the IPT options (the flat format).
inline constexpr const char* kIptTopLevelKeys[] = {"features", "fundamental", "classifier", "min_translation_m",
                                                   "pure_rotation_deg"};
// Sections of a shared options file that belong to other readers.
inline constexpr const char* kNonIptSections[] = {"avoid", "corridor", "explore", "sim"};

// Parses YAML text on top of `base`: the IPT keys at the top level, or under `ipt:` (not both);
// the other readers' sections are skipped. Throws squint::Error naming `source` and the offending
// key for a parse error, an unknown key, a wrong type or options that fail Validate().
obstacles::IptOptions IptOptionsFromYaml(const std::string& text, const std::string& source,
                                         const obstacles::IptOptions& base = {});
// Reads a file; throws squint::Error naming the file when missing or invalid.
obstacles::IptOptions LoadIptOptions(const std::filesystem::path& path, const obstacles::IptOptions& base = {});
// Every member, so that reading the text back gives equal options (round trip).
std::string IptOptionsToYaml(const obstacles::IptOptions& options);
// Writes atomically.
void SaveIptOptions(const std::filesystem::path& path, const obstacles::IptOptions& options);

}  // namespace squint::config
