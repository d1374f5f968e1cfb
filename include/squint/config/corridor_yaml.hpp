// The corridor calibration file (`squint perceive --calib FILE`): a YAML mirror of
// corridor::CorridorOptions. Every key is optional; absent keys keep the struct's defaults.
//
//   glance: {sampling: point}              # point | area
//   heading:
//     cues:                                # per cue: enabled, weight, scale, bias_deg, std_deg
//       entropy:   {weight: 1.0, scale: 1.0, bias_deg: 0.0}
//       symmetry:  {...}
//       phase:     {...}
//       vanishing: {...}
//       bright:    {...}
//     slice_width_px: 3                    # and every other HeadingOptions member, same name
//     max_abs_heading_deg: 40              #   (validity range) ...
//     filter: {enabled: false, process_std_deg_per_sqrt_s: 0.1, process_std_deg: 0.3,
//              odom_noise_fraction: 0.05, no_odom_std_deg: 3,
//              gate_chi2: 9, reinit_after_rejections: 20}   # heading filter over time
//   distance:
//     cues:                                # per cue: enabled, weight
//       ttc: {weight: 2.0}
//       jeffrey: {weight: 1.0}
//       entropy: {weight: 1.0}
//     ttc_scale: 1.0
//     ttc_bias_m: 0.0
//     speed_mps: 0.0
//     alpha2: 200.0
//     beta2: 20.0
//     alpha3: 0.05
//     image_bits: 6
//     min_m: 0.0                           # validity range
//     max_m: 60.0
//     floor_contact: {enabled: true, half_width_deg: 2, min_step: 6, min_column_fraction: 0.5,
//                     min_m: 0.3, max_m: 20, overrides_fusion: true, agreement_ratio: 0.5,
//                     motion_window_m: 0, motion_tol_rows: 0.5, motion_min_fraction: 0.8,
//                     motion_min_readings: 5, refine_same_sign: false,
//                     lined_wall_rel_step: 0}   # 0 = off; in [0, 1]
//   gate: {enabled: true, threshold: 0.01}
#pragma once

#include <filesystem>
#include <string>

#include "squint/corridor/options.hpp"

namespace squint::config {

// Parses YAML text on top of `base` (defaults when omitted). Throws squint::Error naming
// `source` and the offending key for a parse error, an unknown key, a wrong type or options that
// fail Validate().
corridor::CorridorOptions CorridorOptionsFromYaml(const std::string& text, const std::string& source,
                                                  const corridor::CorridorOptions& base = {});
// Reads a file; throws squint::Error naming the file when missing or invalid.
corridor::CorridorOptions LoadCorridorOptions(const std::filesystem::path& path,
                                              const corridor::CorridorOptions& base = {});
// Every member, so that reading the text back gives equal options (round trip).
std::string CorridorOptionsToYaml(const corridor::CorridorOptions& options);
// Writes atomically (io::WriteFileAtomically).
void SaveCorridorOptions(const std::filesystem::path& path, const corridor::CorridorOptions& options);

}  // namespace squint::config
