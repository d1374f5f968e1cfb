// YAML <-> obstacles::AvoidOptions (the `avoid:` section), with the `ipt:` section handed to the
// IPT options reader.
#include "squint/config/avoid_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "squint/config/obstacles_yaml.hpp"
#include "squint/core/error.hpp"

namespace squint::config {

using obstacles::AvoidOptions;

namespace {

YAML::Node Parse(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(source + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
}

void CheckTopLevel(const YAML::Node& root, const std::string& source) {
  if (!root || root.IsNull()) return;
  if (!root.IsMap()) throw Error(source + ": the top level must be a mapping with `ipt:` and/or `avoid:`");
  std::set<std::string> allowed(std::begin(kOtherSections), std::end(kOtherSections));
  allowed.insert(std::begin(kIptTopLevelKeys), std::end(kIptTopLevelKeys));  // the flat IPT format
  allowed.insert("avoid");
  for (const auto& kv : root) {
    const std::string name = kv.first.as<std::string>();
    if (!allowed.count(name))
      throw Error(source + ": `" + name + "` is not a known section (expected `ipt:` and/or `avoid:`)");
  }
}

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& key, const std::string& what) const {
    throw Error(source_ + ": `" + key + "` " + what);
  }

  void RequireMap(const YAML::Node& node, const std::string& key, const std::set<std::string>& allowed) const {
    if (!node.IsMap()) Fail(key, "must be a mapping");
    for (const auto& kv : node) {
      const std::string name = kv.first.as<std::string>();
      if (!allowed.count(name)) Fail(key + "." + name, "is not a known option");
    }
  }

  template <typename T>
  void Get(const YAML::Node& node, const std::string& parent, const std::string& name, T* out) const {
    const YAML::Node v = node[name];
    if (!v) return;
    const std::string key = parent + "." + name;
    try {
      if (!v.IsScalar()) throw YAML::Exception(YAML::Mark(), "not a scalar");
      *out = v.as<T>();
    } catch (const YAML::Exception&) {
      Fail(key, std::is_same_v<T, bool> ? "must be true or false"
                : std::is_integral_v<T>   ? "must be an integer"
                                          : "must be a number");
    }
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(*out)) Fail(key, "must be a finite number");
  }

 private:
  std::string source_;
};

AvoidOptions ParseAvoid(const YAML::Node& root, const std::string& source, const AvoidOptions& base) {
  AvoidOptions o = base;
  if (!root || root.IsNull() || !root["avoid"] || root["avoid"].IsNull()) return o;
  const Reader r(source);
  const YAML::Node a = root["avoid"];
  r.RequireMap(a, "avoid", {"edges", "outline", "polar", "gap", "memory"});
  if (const YAML::Node n = a["edges"]) {
    r.RequireMap(n, "avoid.edges", {"sigma_px", "low_threshold", "high_threshold", "base_edges"});
    r.Get(n, "avoid.edges", "base_edges", &o.edges.base_edges);
    r.Get(n, "avoid.edges", "sigma_px", &o.edges.sigma_px);
    r.Get(n, "avoid.edges", "low_threshold", &o.edges.low_threshold);
    r.Get(n, "avoid.edges", "high_threshold", &o.edges.high_threshold);
  }
  if (const YAML::Node n = a["outline"]) {
    r.RequireMap(n, "avoid.outline", {"window_width_px", "window_height_px", "ground_stop_radius_px", "max_gap_rows",
                                      "base_trace", "base_below_features", "base_max_rise_px", "base_min_step"});
    r.Get(n, "avoid.outline", "base_below_features", &o.outline.base_below_features);
    r.Get(n, "avoid.outline", "base_trace", &o.outline.base_trace);
    r.Get(n, "avoid.outline", "base_max_rise_px", &o.outline.base_max_rise_px);
    r.Get(n, "avoid.outline", "base_min_step", &o.outline.base_min_step);
    r.Get(n, "avoid.outline", "window_width_px", &o.outline.window_width_px);
    r.Get(n, "avoid.outline", "window_height_px", &o.outline.window_height_px);
    r.Get(n, "avoid.outline", "ground_stop_radius_px", &o.outline.ground_stop_radius_px);
    r.Get(n, "avoid.outline", "max_gap_rows", &o.outline.max_gap_rows);
  }
  if (const YAML::Node n = a["polar"]) {
    r.RequireMap(n, "avoid.polar",
                 {"roi_radius_m", "sector_deg", "min_contacts", "free_needs_ground", "min_ground_features",
                  "min_ground_range_m"});
    r.Get(n, "avoid.polar", "roi_radius_m", &o.polar.roi_radius_m);
    r.Get(n, "avoid.polar", "sector_deg", &o.polar.sector_deg);
    r.Get(n, "avoid.polar", "min_contacts", &o.polar.min_contacts);
    r.Get(n, "avoid.polar", "free_needs_ground", &o.polar.free_needs_ground);
    r.Get(n, "avoid.polar", "min_ground_features", &o.polar.min_ground_features);
    r.Get(n, "avoid.polar", "min_ground_range_m", &o.polar.min_ground_range_m);
  }
  if (const YAML::Node n = a["gap"]) {
    r.RequireMap(n, "avoid.gap", {"robot_radius_m", "margin_m"});
    r.Get(n, "avoid.gap", "robot_radius_m", &o.gap.robot_radius_m);
    r.Get(n, "avoid.gap", "margin_m", &o.gap.margin_m);
  }
  if (const YAML::Node n = a["memory"]) {
    r.RequireMap(n, "avoid.memory", {"decisions", "radius_m"});
    r.Get(n, "avoid.memory", "decisions", &o.memory.decisions);
    r.Get(n, "avoid.memory", "radius_m", &o.memory.radius_m);
  }
  const std::string problem = o.Validate();
  if (!problem.empty()) throw Error(source + ": avoid." + problem);
  return o;
}

}  // namespace

AvoidOptions AvoidOptionsFromYaml(const std::string& text, const std::string& source, const AvoidOptions& base) {
  const YAML::Node root = Parse(text, source);
  CheckTopLevel(root, source);
  return ParseAvoid(root, source, base);
}

std::string AvoidOptionsToYaml(const AvoidOptions& o) {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << YAML::BeginMap << YAML::Key << "avoid" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "edges" << YAML::Value << YAML::BeginMap << YAML::Key << "sigma_px" << YAML::Value
    << o.edges.sigma_px << YAML::Key << "low_threshold" << YAML::Value << o.edges.low_threshold << YAML::Key
    << "high_threshold" << YAML::Value << o.edges.high_threshold << YAML::Key << "base_edges" << YAML::Value
    << o.edges.base_edges << YAML::EndMap;
  e << YAML::Key << "outline" << YAML::Value << YAML::BeginMap << YAML::Key << "window_width_px" << YAML::Value
    << o.outline.window_width_px << YAML::Key << "window_height_px" << YAML::Value << o.outline.window_height_px
    << YAML::Key << "ground_stop_radius_px" << YAML::Value << o.outline.ground_stop_radius_px << YAML::Key
    << "max_gap_rows" << YAML::Value << o.outline.max_gap_rows << YAML::Key << "base_trace" << YAML::Value
    << o.outline.base_trace << YAML::Key << "base_below_features" << YAML::Value << o.outline.base_below_features
    << YAML::Key << "base_max_rise_px" << YAML::Value << o.outline.base_max_rise_px
    << YAML::Key << "base_min_step" << YAML::Value << o.outline.base_min_step << YAML::EndMap;
  e << YAML::Key << "polar" << YAML::Value << YAML::BeginMap << YAML::Key << "roi_radius_m" << YAML::Value
    << o.polar.roi_radius_m << YAML::Key << "sector_deg" << YAML::Value << o.polar.sector_deg << YAML::Key
    << "min_contacts" << YAML::Value << o.polar.min_contacts << YAML::Key << "free_needs_ground" << YAML::Value
    << o.polar.free_needs_ground << YAML::Key << "min_ground_features" << YAML::Value << o.polar.min_ground_features
    << YAML::Key << "min_ground_range_m" << YAML::Value << o.polar.min_ground_range_m
    << YAML::EndMap;
  e << YAML::Key << "gap" << YAML::Value << YAML::BeginMap << YAML::Key << "robot_radius_m" << YAML::Value
    << o.gap.robot_radius_m << YAML::Key << "margin_m" << YAML::Value << o.gap.margin_m << YAML::EndMap;
  e << YAML::Key << "memory" << YAML::Value << YAML::BeginMap << YAML::Key << "decisions" << YAML::Value
    << o.memory.decisions << YAML::Key << "radius_m" << YAML::Value << o.memory.radius_m << YAML::EndMap;
  e << YAML::EndMap << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

AvoidFileOptions AvoidFileOptionsFromYaml(const std::string& text, const std::string& source) {
  const YAML::Node root = Parse(text, source);
  CheckTopLevel(root, source);
  AvoidFileOptions out;
  out.avoid = ParseAvoid(root, source, out.avoid);
  // The IPT reader takes the same text: its `ipt:` section, or its keys at the top level.
  out.ipt = IptOptionsFromYaml(text, source);
  return out;
}

AvoidFileOptions LoadAvoidFileOptions(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open the options file");
  std::stringstream ss;
  ss << in.rdbuf();
  return AvoidFileOptionsFromYaml(ss.str(), path.string());
}

}  // namespace squint::config
