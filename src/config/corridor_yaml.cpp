// YAML (de)serialisation of corridor::CorridorOptions: the `--calib FILE` format.
#include "squint/config/corridor_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>

#include "squint/core/error.hpp"
#include "squint/io/atomic_output.hpp"

namespace squint::config {
namespace {

using corridor::CorridorOptions;
using corridor::DistanceCue;
using corridor::FloorContactOptions;
using corridor::HeadingCue;

// Reads mapping keys, refusing unknown ones so that a typo is not silently ignored.
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string path, const std::string& source)
      : node_(node), path_(std::move(path)), source_(source) {
    if (!node_.IsMap()) throw Error(source_ + ": '" + path_ + "' must be a mapping");
  }
  ~MapReader() = default;

  template <typename T>
  void Get(const std::string& key, T& value) {
    seen_.insert(key);
    const YAML::Node n = node_[key];
    if (!n) return;
    try {
      value = n.as<T>();
    } catch (const YAML::Exception&) {
      throw Error(source_ + ": '" + Key(key) + "' has a value of the wrong type (line " +
                  std::to_string(n.Mark().line + 1) + ")");
    }
  }
  // A sub-mapping (or none when absent).
  std::optional<YAML::Node> Child(const std::string& key) {
    seen_.insert(key);
    const YAML::Node n = node_[key];
    if (!n) return std::nullopt;
    return n;
  }
  std::string Key(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  void CheckUnknown() const {
    for (const auto& kv : node_) {
      const std::string key = kv.first.as<std::string>();
      if (!seen_.count(key)) throw Error(source_ + ": unknown key '" + Key(key) + "'");
    }
  }

 private:
  YAML::Node node_;
  std::string path_;
  const std::string& source_;
  std::set<std::string> seen_;
};

void ReadHeading(const YAML::Node& node, const std::string& source, corridor::HeadingOptions& h) {
  MapReader r(node, "heading", source);
  if (auto cues = r.Child("cues")) {
    MapReader rc(*cues, "heading.cues", source);
    for (int i = 0; i < corridor::kHeadingCueCount; ++i) {
      const std::string name = corridor::CueName(static_cast<HeadingCue>(i));
      if (auto c = rc.Child(name)) {
        MapReader m(*c, "heading.cues." + name, source);
        m.Get("enabled", h.cues[i].enabled);
        m.Get("weight", h.cues[i].weight);
        m.Get("scale", h.cues[i].scale);
        m.Get("bias_deg", h.cues[i].bias_deg);
        m.Get("std_deg", h.cues[i].std_deg);
        m.CheckUnknown();
      }
    }
    rc.CheckUnknown();
  }
  r.Get("slice_width_px", h.slice_width_px);
  r.Get("border_px", h.border_px);
  r.Get("min_prominence", h.min_prominence);
  r.Get("column_bits", h.column_bits);
  r.Get("symmetry_half_width_px", h.symmetry_half_width_px);
  r.Get("symmetry_min_half_width_px", h.symmetry_min_half_width_px);
  r.Get("vanishing_bits", h.vanishing_bits);
  r.Get("vanishing_row_margin_px", h.vanishing_row_margin_px);
  r.Get("vanishing_max_outside_px", h.vanishing_max_outside_px);
  r.Get("bright_rows_fraction", h.bright_rows_fraction);
  r.Get("bright_min_separation", h.bright_min_separation);
  r.Get("kmeans_iterations", h.kmeans_iterations);
  r.Get("bright_max_fraction", h.bright_max_fraction);
  r.Get("phase_min_gradient", h.phase_min_gradient);
  r.Get("phase_max_deg", h.phase_max_deg);
  r.Get("symmetry_significance", h.symmetry_significance);
  r.Get("fuse_curves", h.fuse_curves);
  r.Get("phase_line_vote", h.phase_line_vote);
  r.Get("phase_min_vertical_deg", h.phase_min_vertical_deg);
  r.Get("phase_min_horizon_rows", h.phase_min_horizon_rows);
  r.Get("max_abs_heading_deg", h.max_abs_heading_deg);
  r.Get("agreement_deg", h.agreement_deg);
  r.Get("min_consensus_cues", h.min_consensus_cues);
  r.Get("fallback_deg_per_column", h.fallback_deg_per_column);
  if (auto f = r.Child("filter")) {
    MapReader m(*f, "heading.filter", source);
    m.Get("enabled", h.filter.enabled);
    m.Get("process_std_deg_per_sqrt_s", h.filter.process_std_deg_per_sqrt_s);
    m.Get("process_std_deg", h.filter.process_std_deg);
    m.Get("odom_noise_fraction", h.filter.odom_noise_fraction);
    m.Get("no_odom_std_deg", h.filter.no_odom_std_deg);
    m.Get("gate_chi2", h.filter.gate_chi2);
    m.Get("reinit_after_rejections", h.filter.reinit_after_rejections);
    m.CheckUnknown();
  }
  r.CheckUnknown();
}

void ReadDistance(const YAML::Node& node, const std::string& source, corridor::DistanceOptions& d) {
  MapReader r(node, "distance", source);
  if (auto cues = r.Child("cues")) {
    MapReader rc(*cues, "distance.cues", source);
    for (int i = 0; i < corridor::kDistanceCueCount; ++i) {
      const std::string name = corridor::CueName(static_cast<DistanceCue>(i));
      if (auto c = rc.Child(name)) {
        MapReader m(*c, "distance.cues." + name, source);
        bool enabled = d.enabled[i];
        m.Get("enabled", enabled);
        d.enabled[i] = enabled;
        m.Get("weight", d.weights[i]);
        m.Get("valid_min_m", d.valid_min_m[i]);
        m.Get("valid_max_m", d.valid_max_m[i]);
        m.Get("error_growth_per_m", d.error_growth_per_m[i]);
        bool fuse = d.fuse[i];
        m.Get("fuse", fuse);
        d.fuse[i] = fuse;
        m.CheckUnknown();
      }
    }
    rc.CheckUnknown();
  }
  r.Get("ttc_scale", d.ttc_scale);
  r.Get("ttc_bias_m", d.ttc_bias_m);
  r.Get("speed_mps", d.speed_mps);
  r.Get("alpha2", d.alpha2);
  r.Get("beta2", d.beta2);
  r.Get("alpha3", d.alpha3);
  r.Get("image_bits", d.image_bits);
  r.Get("min_m", d.min_m);
  r.Get("max_m", d.max_m);
  r.Get("median_frames", d.median_frames);
  r.Get("ttc_window_min_height_px", d.ttc_window_min_height_px);
  r.Get("ttc_whole_glance_first", d.ttc_whole_glance_first);
  r.Get("ttc_smooth", d.ttc_smooth);
  r.Get("ttc_max_baseline_frames", d.ttc_max_baseline_frames);
  r.Get("ttc_baseline_fraction", d.ttc_baseline_fraction);
  r.Get("ttc_centre_at_horizon", d.ttc_centre_at_horizon);
  r.Get("ttc_gain_compensation", d.ttc_gain_compensation);
  r.Get("ttc_scale_search", d.ttc_scale_search);
  r.Get("ttc_max_scale", d.ttc_max_scale);
  r.Get("ttc_window_half_width_m", d.ttc_window_half_width_m);
  r.Get("ttc_window_height_factor", d.ttc_window_height_factor);
  r.Get("ttc_window_min_px", d.ttc_window_min_px);
  r.Get("ttc_initial_baseline_m", d.ttc_initial_baseline_m);
  r.Get("ttc_warmup_m", d.ttc_warmup_m);
  r.Get("ttc_area_glance", d.ttc_area_glance);
  r.Get("ttc_glance_scale", d.ttc_glance_scale);
  r.Get("ttc_min_contrast", d.ttc_min_contrast);
  r.Get("ttc_min_ncc", d.ttc_min_ncc);
  r.Get("ttc_cell_px", d.ttc_cell_px);
  r.Get("ttc_cell_quantile", d.ttc_cell_quantile);
  r.Get("ttc_cell_min_count", d.ttc_cell_min_count);
  r.Get("ttc_cell_max_se_fraction", d.ttc_cell_max_se_fraction);
  r.Get("ttc_cell_min_expansion", d.ttc_cell_min_expansion);
  r.Get("ttc_cell_nearest", d.ttc_cell_nearest);
  r.Get("ttc_cell_nearest_at_min_window", d.ttc_cell_nearest_at_min_window);
  r.Get("fused_max_std_m", d.fused_max_std_m);
  if (auto f = r.Child("floor_contact")) {
    MapReader m(*f, "distance.floor_contact", source);
    m.Get("enabled", d.floor_contact.enabled);
    m.Get("half_width_deg", d.floor_contact.half_width_deg);
    m.Get("min_step", d.floor_contact.min_step);
    m.Get("min_column_fraction", d.floor_contact.min_column_fraction);
    m.Get("min_m", d.floor_contact.min_m);
    m.Get("max_m", d.floor_contact.max_m);
    m.Get("overrides_fusion", d.floor_contact.overrides_fusion);
    m.Get("agreement_ratio", d.floor_contact.agreement_ratio);
    m.Get("motion_window_m", d.floor_contact.motion_window_m);
    m.Get("motion_tol_rows", d.floor_contact.motion_tol_rows);
    m.Get("motion_min_fraction", d.floor_contact.motion_min_fraction);
    m.Get("motion_min_readings", d.floor_contact.motion_min_readings);
    m.Get("refine_same_sign", d.floor_contact.refine_same_sign);
    m.Get("lined_wall_rel_step", d.floor_contact.lined_wall_rel_step);
    m.CheckUnknown();
  }
  r.CheckUnknown();
}

}  // namespace

CorridorOptions CorridorOptionsFromYaml(const std::string& text, const std::string& source,
                                        const CorridorOptions& base) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(source + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
  CorridorOptions options = base;
  if (root.IsNull()) return options;
  MapReader r(root, "", source);
  if (auto glance = r.Child("glance")) {
    MapReader g(*glance, "glance", source);
    std::string sampling = options.sampling == corridor::GlanceSampling::kPoint ? "point" : "area";
    g.Get("sampling", sampling);
    if (sampling == "point") options.sampling = corridor::GlanceSampling::kPoint;
    else if (sampling == "area") options.sampling = corridor::GlanceSampling::kArea;
    else throw Error(source + ": 'glance.sampling' must be point or area, not '" + sampling + "'");
    g.CheckUnknown();
  }
  if (auto h = r.Child("heading")) ReadHeading(*h, source, options.heading);
  if (auto d = r.Child("distance")) ReadDistance(*d, source, options.distance);
  if (auto gate = r.Child("gate")) {
    MapReader g(*gate, "gate", source);
    g.Get("enabled", options.gate.enabled);
    g.Get("threshold", options.gate.threshold);
    g.Get("compare_with_last_processed", options.gate.compare_with_last_processed);
    g.Get("max_skipped_frames", options.gate.max_skipped_frames);
    g.CheckUnknown();
  }
  r.CheckUnknown();
  const std::string problem = options.Validate();
  if (!problem.empty()) throw Error(source + ": " + problem);
  return options;
}

CorridorOptions LoadCorridorOptions(const std::filesystem::path& path, const CorridorOptions& base) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open corridor options file");
  std::stringstream ss;
  ss << in.rdbuf();
  return CorridorOptionsFromYaml(ss.str(), path.string(), base);
}

std::string CorridorOptionsToYaml(const CorridorOptions& o) {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << YAML::Comment("squint corridor options (include/squint/config/corridor_yaml.hpp)");
  e << YAML::BeginMap;
  e << YAML::Key << "glance" << YAML::Value << YAML::BeginMap << YAML::Key << "sampling" << YAML::Value
    << (o.sampling == corridor::GlanceSampling::kPoint ? "point" : "area") << YAML::EndMap;
  const auto& h = o.heading;
  e << YAML::Key << "heading" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "cues" << YAML::Value << YAML::BeginMap;
  for (int i = 0; i < corridor::kHeadingCueCount; ++i) {
    e << YAML::Key << corridor::CueName(static_cast<HeadingCue>(i)) << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "enabled" << YAML::Value << h.cues[i].enabled << YAML::Key << "weight" << YAML::Value
      << h.cues[i].weight << YAML::Key << "scale" << YAML::Value << h.cues[i].scale << YAML::Key << "bias_deg"
      << YAML::Value << h.cues[i].bias_deg << YAML::Key << "std_deg" << YAML::Value << h.cues[i].std_deg
      << YAML::EndMap;
  }
  e << YAML::EndMap;
  e << YAML::Key << "slice_width_px" << YAML::Value << h.slice_width_px;
  e << YAML::Key << "border_px" << YAML::Value << h.border_px;
  e << YAML::Key << "min_prominence" << YAML::Value << h.min_prominence;
  e << YAML::Key << "column_bits" << YAML::Value << h.column_bits;
  e << YAML::Key << "symmetry_half_width_px" << YAML::Value << h.symmetry_half_width_px;
  e << YAML::Key << "symmetry_min_half_width_px" << YAML::Value << h.symmetry_min_half_width_px;
  e << YAML::Key << "vanishing_bits" << YAML::Value << h.vanishing_bits;
  e << YAML::Key << "vanishing_row_margin_px" << YAML::Value << h.vanishing_row_margin_px;
  e << YAML::Key << "vanishing_max_outside_px" << YAML::Value << h.vanishing_max_outside_px;
  e << YAML::Key << "bright_rows_fraction" << YAML::Value << h.bright_rows_fraction;
  e << YAML::Key << "bright_min_separation" << YAML::Value << h.bright_min_separation;
  e << YAML::Key << "kmeans_iterations" << YAML::Value << h.kmeans_iterations;
  e << YAML::Key << "bright_max_fraction" << YAML::Value << h.bright_max_fraction;
  e << YAML::Key << "phase_min_gradient" << YAML::Value << h.phase_min_gradient;
  e << YAML::Key << "phase_max_deg" << YAML::Value << h.phase_max_deg;
  e << YAML::Key << "symmetry_significance" << YAML::Value << h.symmetry_significance;
  e << YAML::Key << "fuse_curves" << YAML::Value << h.fuse_curves;
  e << YAML::Key << "phase_line_vote" << YAML::Value << h.phase_line_vote;
  e << YAML::Key << "phase_min_vertical_deg" << YAML::Value << h.phase_min_vertical_deg;
  e << YAML::Key << "phase_min_horizon_rows" << YAML::Value << h.phase_min_horizon_rows;
  e << YAML::Key << "max_abs_heading_deg" << YAML::Value << h.max_abs_heading_deg;
  e << YAML::Key << "agreement_deg" << YAML::Value << h.agreement_deg;
  e << YAML::Key << "min_consensus_cues" << YAML::Value << h.min_consensus_cues;
  e << YAML::Key << "fallback_deg_per_column" << YAML::Value << h.fallback_deg_per_column;
  e << YAML::Key << "filter" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "enabled"
    << YAML::Value << h.filter.enabled << YAML::Key << "process_std_deg_per_sqrt_s" << YAML::Value
    << h.filter.process_std_deg_per_sqrt_s << YAML::Key << "process_std_deg" << YAML::Value << h.filter.process_std_deg
    << YAML::Key << "odom_noise_fraction" << YAML::Value << h.filter.odom_noise_fraction << YAML::Key
    << "no_odom_std_deg" << YAML::Value << h.filter.no_odom_std_deg << YAML::Key << "gate_chi2" << YAML::Value
    << h.filter.gate_chi2 << YAML::Key << "reinit_after_rejections" << YAML::Value
    << h.filter.reinit_after_rejections << YAML::EndMap;
  e << YAML::EndMap;
  const auto& d = o.distance;
  e << YAML::Key << "distance" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "cues" << YAML::Value << YAML::BeginMap;
  for (int i = 0; i < corridor::kDistanceCueCount; ++i) {
    e << YAML::Key << corridor::CueName(static_cast<DistanceCue>(i)) << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "enabled" << YAML::Value << static_cast<bool>(d.enabled[i]) << YAML::Key << "weight"
      << YAML::Value << d.weights[i] << YAML::Key << "valid_min_m" << YAML::Value << d.valid_min_m[i]
      << YAML::Key << "valid_max_m" << YAML::Value << d.valid_max_m[i] << YAML::Key << "error_growth_per_m"
      << YAML::Value << d.error_growth_per_m[i] << YAML::Key << "fuse" << YAML::Value << static_cast<bool>(d.fuse[i])
      << YAML::EndMap;
  }
  e << YAML::EndMap;
  e << YAML::Key << "ttc_scale" << YAML::Value << d.ttc_scale;
  e << YAML::Key << "ttc_bias_m" << YAML::Value << d.ttc_bias_m;
  e << YAML::Key << "speed_mps" << YAML::Value << d.speed_mps;
  e << YAML::Key << "alpha2" << YAML::Value << d.alpha2;
  e << YAML::Key << "beta2" << YAML::Value << d.beta2;
  e << YAML::Key << "alpha3" << YAML::Value << d.alpha3;
  e << YAML::Key << "image_bits" << YAML::Value << d.image_bits;
  e << YAML::Key << "min_m" << YAML::Value << d.min_m;
  e << YAML::Key << "max_m" << YAML::Value << d.max_m;
  e << YAML::Key << "median_frames" << YAML::Value << d.median_frames;
  e << YAML::Key << "ttc_window_min_height_px" << YAML::Value << d.ttc_window_min_height_px;
  e << YAML::Key << "ttc_whole_glance_first" << YAML::Value << d.ttc_whole_glance_first;
  e << YAML::Key << "ttc_smooth" << YAML::Value << d.ttc_smooth;
  e << YAML::Key << "ttc_max_baseline_frames" << YAML::Value << d.ttc_max_baseline_frames;
  e << YAML::Key << "ttc_baseline_fraction" << YAML::Value << d.ttc_baseline_fraction;
  e << YAML::Key << "ttc_centre_at_horizon" << YAML::Value << d.ttc_centre_at_horizon;
  e << YAML::Key << "ttc_gain_compensation" << YAML::Value << d.ttc_gain_compensation;
  e << YAML::Key << "ttc_scale_search" << YAML::Value << d.ttc_scale_search;
  e << YAML::Key << "ttc_max_scale" << YAML::Value << d.ttc_max_scale;
  e << YAML::Key << "ttc_window_half_width_m" << YAML::Value << d.ttc_window_half_width_m;
  e << YAML::Key << "ttc_window_height_factor" << YAML::Value << d.ttc_window_height_factor;
  e << YAML::Key << "ttc_window_min_px" << YAML::Value << d.ttc_window_min_px;
  e << YAML::Key << "ttc_initial_baseline_m" << YAML::Value << d.ttc_initial_baseline_m;
  e << YAML::Key << "ttc_warmup_m" << YAML::Value << d.ttc_warmup_m;
  e << YAML::Key << "ttc_area_glance" << YAML::Value << d.ttc_area_glance;
  e << YAML::Key << "ttc_glance_scale" << YAML::Value << d.ttc_glance_scale;
  e << YAML::Key << "ttc_min_contrast" << YAML::Value << d.ttc_min_contrast;
  e << YAML::Key << "ttc_min_ncc" << YAML::Value << d.ttc_min_ncc;
  e << YAML::Key << "ttc_cell_px" << YAML::Value << d.ttc_cell_px;
  e << YAML::Key << "ttc_cell_quantile" << YAML::Value << d.ttc_cell_quantile;
  e << YAML::Key << "ttc_cell_min_count" << YAML::Value << d.ttc_cell_min_count;
  e << YAML::Key << "ttc_cell_max_se_fraction" << YAML::Value << d.ttc_cell_max_se_fraction;
  e << YAML::Key << "ttc_cell_min_expansion" << YAML::Value << d.ttc_cell_min_expansion;
  e << YAML::Key << "ttc_cell_nearest" << YAML::Value << d.ttc_cell_nearest;
  e << YAML::Key << "ttc_cell_nearest_at_min_window" << YAML::Value << d.ttc_cell_nearest_at_min_window;
  e << YAML::Key << "fused_max_std_m" << YAML::Value << d.fused_max_std_m;
  const FloorContactOptions& fc = d.floor_contact;
  e << YAML::Key << "floor_contact" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "enabled"
    << YAML::Value << fc.enabled << YAML::Key << "half_width_deg" << YAML::Value << fc.half_width_deg << YAML::Key
    << "min_step" << YAML::Value << fc.min_step << YAML::Key << "min_column_fraction" << YAML::Value
    << fc.min_column_fraction << YAML::Key << "min_m" << YAML::Value << fc.min_m << YAML::Key << "max_m"
    << YAML::Value << fc.max_m << YAML::Key << "overrides_fusion" << YAML::Value << fc.overrides_fusion
    << YAML::Key << "agreement_ratio" << YAML::Value << fc.agreement_ratio << YAML::Key << "motion_window_m"
    << YAML::Value << fc.motion_window_m << YAML::Key << "motion_tol_rows" << YAML::Value << fc.motion_tol_rows
    << YAML::Key << "motion_min_fraction" << YAML::Value << fc.motion_min_fraction << YAML::Key
    << "motion_min_readings" << YAML::Value << fc.motion_min_readings << YAML::Key << "refine_same_sign"
    << YAML::Value << fc.refine_same_sign << YAML::Key << "lined_wall_rel_step" << YAML::Value
    << fc.lined_wall_rel_step << YAML::EndMap;
  e << YAML::EndMap;
  e << YAML::Key << "gate" << YAML::Value << YAML::BeginMap << YAML::Key << "enabled" << YAML::Value
    << o.gate.enabled << YAML::Key << "threshold" << YAML::Value << o.gate.threshold << YAML::Key
    << "compare_with_last_processed" << YAML::Value << o.gate.compare_with_last_processed << YAML::Key
    << "max_skipped_frames" << YAML::Value << o.gate.max_skipped_frames << YAML::EndMap;
  e << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

void SaveCorridorOptions(const std::filesystem::path& path, const CorridorOptions& options) {
  io::WriteFileAtomically(path, CorridorOptionsToYaml(options));
}

}  // namespace squint::config
