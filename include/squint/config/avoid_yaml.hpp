// The avoidance options (`squint avoid --options FILE`): a YAML mirror of obstacles::AvoidOptions
// under a top-level `avoid:` section. The same file may hold the IPT detection options under
// `ipt:` or as their keys at the top level (config/obstacles_yaml.hpp); each reader ignores the
// other's part, so one file serves `squint obstacles`, `squint avoid` and `squint eval avoid`.
// Every key is optional; absent keys keep the structs' defaults.
//
//   ipt:                      # obstacles::IptOptions, as `squint obstacles --options` reads
//     features: {detector: sift}
//   avoid:
//     edges:   {sigma_px: 1.0, low_threshold: 40, high_threshold: 50}
//     outline: {window_width_px: 9, window_height_px: 15, ground_stop_radius_px: 1, max_gap_rows: 0}
//     polar:   {roi_radius_m: 1.5, sector_deg: 5, min_contacts: 1}
//     gap:     {robot_radius_m: 0.25, margin_m: 0.05}
#pragma once

#include <filesystem>
#include <string>

#include "squint/obstacles/avoider.hpp"
#include "squint/obstacles/ipt_pipeline.hpp"

namespace squint::config {

// Top-level sections other squint readers own; a file holding them is still a valid options
// file here. Any other top-level key is reported as unknown.
inline constexpr const char* kOtherSections[] = {"ipt", "corridor", "explore", "sim"};

// Parses the `avoid:` section of YAML text on top of `base` (other known sections are ignored).
// Throws squint::Error naming `source` and the offending key for a parse error, an unknown key,
// a wrong type or options that fail Validate().
obstacles::AvoidOptions AvoidOptionsFromYaml(const std::string& text, const std::string& source,
                                             const obstacles::AvoidOptions& base = {});
// Every member under `avoid:`, so that reading the text back gives equal options.
std::string AvoidOptionsToYaml(const obstacles::AvoidOptions& options);

// Both halves of an avoidance options file: the IPT part (`ipt:` or the flat keys, parsed by
// config::IptOptionsFromYaml) and the `avoid:` section.
struct AvoidFileOptions {
  obstacles::IptOptions ipt;
  obstacles::AvoidOptions avoid;
};
AvoidFileOptions AvoidFileOptionsFromYaml(const std::string& text, const std::string& source);
// Reads a file; throws squint::Error naming the file when missing or invalid.
AvoidFileOptions LoadAvoidFileOptions(const std::filesystem::path& path);

}  // namespace squint::config
