// YAML <-> obstacles::IptOptions, with unknown keys and wrong types reported by name.
#include "squint/config/obstacles_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "squint/core/error.hpp"
#include "squint/io/atomic_output.hpp"

namespace squint::config {

using obstacles::IptOptions;

namespace {

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& key, const std::string& what) const {
    throw Error(source_ + ": `" + key + "` " + what);
  }

  void RequireMap(const YAML::Node& node, const std::string& key, const std::set<std::string>& allowed) const {
    if (!node.IsMap()) Fail(key.empty() ? "(top level)" : key, "must be a mapping");
    for (const auto& kv : node) {
      const std::string name = kv.first.as<std::string>();
      if (!allowed.count(name)) Fail(Join(key, name), "is not a known option");
    }
  }

  static std::string Join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }

  template <typename T>
  void Get(const YAML::Node& node, const std::string& parent, const std::string& name, T* out) const {
    const YAML::Node v = node[name];
    if (!v) return;
    try {
      if (!v.IsScalar()) throw YAML::Exception(YAML::Mark(), "not a scalar");
      *out = v.as<T>();
    } catch (const YAML::Exception&) {
      Fail(Join(parent, name), std::string("must be ") + TypeName<T>());
    }
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(*out)) Fail(Join(parent, name), "must be a finite number");
  }

 private:
  template <typename T>
  static const char* TypeName() {
    if constexpr (std::is_same_v<T, bool>) return "true or false";
    else if constexpr (std::is_integral_v<T>) return "an integer";
    else if constexpr (std::is_floating_point_v<T>) return "a number";
    else return "a string";
  }
  std::string source_;
};

}  // namespace

namespace {

// The IPT part of a (possibly shared) options file: the `ipt:` section when there is one, else the
// top level without the other readers' sections. Sets `where` to name the section in errors.
YAML::Node IptPart(const YAML::Node& doc, const std::string& source, std::string* where) {
  *where = source;
  if (!doc.IsMap()) return doc;
  const std::set<std::string> others(std::begin(kNonIptSections), std::end(kNonIptSections));
  YAML::Node own(YAML::NodeType::Map);
  for (const auto& kv : doc) {
    const std::string name = kv.first.as<std::string>();
    if (others.count(name) || name == "ipt") continue;
    own[name] = kv.second;
  }
  const YAML::Node ipt = doc["ipt"];
  if (!ipt) return own;
  if (own.size() != 0)
    throw Error(source + ": `" + own.begin()->first.as<std::string>() +
                "` must not stand at the top level beside an `ipt:` section (put the IPT options under `ipt:`)");
  *where = source + " (section ipt)";
  return ipt;
}

}  // namespace

IptOptions IptOptionsFromYaml(const std::string& text, const std::string& source, const IptOptions& base) {
  IptOptions o = base;
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(source + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
  if (!doc || doc.IsNull()) return o;
  std::string where;
  const YAML::Node root = IptPart(doc, source, &where);
  if (!root || root.IsNull()) return o;
  const Reader r(where);
  r.RequireMap(root, "", {"features", "fundamental", "classifier", "min_translation_m", "pure_rotation_deg",
                          "mirror_aware"});

  if (const YAML::Node f = root["features"]) {
    r.RequireMap(f, "features",
                 {"detector", "max_features", "ratio", "sift_contrast_threshold", "sift_octave_layers",
                  "sift_first_octave", "orb_fast_threshold", "orb_levels", "orb_upright", "akaze_threshold", "klt_quality", "klt_min_distance_px",
                  "klt_window_px", "klt_levels", "klt_max_fb_error_px", "refine_subpixel", "refine_window_px",
                  "refine_max_shift_px", "max_displacement_px"});
    std::string detector = obstacles::DetectorName(o.features.detector);
    r.Get(f, "features", "detector", &detector);
    if (!obstacles::ParseDetector(detector, &o.features.detector))
      r.Fail("features.detector", "must be sift, orb, akaze or klt (got '" + detector + "')");
    auto& x = o.features;
    r.Get(f, "features", "max_features", &x.max_features);
    r.Get(f, "features", "ratio", &x.ratio);
    r.Get(f, "features", "sift_contrast_threshold", &x.sift_contrast_threshold);
    r.Get(f, "features", "sift_octave_layers", &x.sift_octave_layers);
    r.Get(f, "features", "sift_first_octave", &x.sift_first_octave);
    r.Get(f, "features", "orb_fast_threshold", &x.orb_fast_threshold);
    r.Get(f, "features", "orb_levels", &x.orb_levels);
    r.Get(f, "features", "orb_upright", &x.orb_upright);
    r.Get(f, "features", "akaze_threshold", &x.akaze_threshold);
    r.Get(f, "features", "klt_quality", &x.klt_quality);
    r.Get(f, "features", "klt_min_distance_px", &x.klt_min_distance_px);
    r.Get(f, "features", "klt_window_px", &x.klt_window_px);
    r.Get(f, "features", "klt_levels", &x.klt_levels);
    r.Get(f, "features", "klt_max_fb_error_px", &x.klt_max_fb_error_px);
    r.Get(f, "features", "refine_subpixel", &x.refine_subpixel);
    r.Get(f, "features", "refine_window_px", &x.refine_window_px);
    r.Get(f, "features", "refine_max_shift_px", &x.refine_max_shift_px);
    r.Get(f, "features", "max_displacement_px", &x.max_displacement_px);
  }
  if (const YAML::Node f = root["fundamental"]) {
    r.RequireMap(f, "fundamental", {"inlier_threshold_px", "confidence", "max_iterations", "max_refinements", "min_matches"});
    auto& x = o.fundamental;
    r.Get(f, "fundamental", "inlier_threshold_px", &x.inlier_threshold_px);
    r.Get(f, "fundamental", "confidence", &x.confidence);
    r.Get(f, "fundamental", "max_iterations", &x.max_iterations);
    r.Get(f, "fundamental", "max_refinements", &x.max_refinements);
    r.Get(f, "fundamental", "min_matches", &x.min_matches);
  }
  if (const YAML::Node c = root["classifier"]) {
    r.RequireMap(c, "classifier", {"zone_beta", "refinement", "zones", "zoning"});
    r.Get(c, "classifier", "zone_beta", &o.classifier.zone_beta);
    r.Get(c, "classifier", "refinement", &o.classifier.refinement);
    if (const YAML::Node z = c["zones"]) {
      if (!z.IsSequence() || z.size() != 3)
        r.Fail("classifier.zones", "must be a list of 3 entries (zones 0, 1, 2)");
      for (std::size_t i = 0; i < 3; ++i) {
        const std::string key = "classifier.zones[" + std::to_string(i) + "]";
        r.RequireMap(z[i], key, {"beta_m", "refine_high_m"});
        auto& t = o.classifier.zones[i];
        r.Get(z[i], key, "beta_m", &t.beta_m);
        if (const YAML::Node h = z[i]["refine_high_m"]; h && !h.IsNull()) {
          double high = 0.0;
          r.Get(z[i], key, "refine_high_m", &high);
          t.refine_high_m = high;
        } else if (h) {
          t.refine_high_m.reset();
        }
      }
    }
    if (const YAML::Node z = c["zoning"]) {
      r.RequireMap(z, "classifier.zoning", {"dst_m", "step_m", "zone2_min_d_m", "zone0_max_d_m"});
      auto& x = o.classifier.zoning;
      r.Get(z, "classifier.zoning", "dst_m", &x.dst_m);
      r.Get(z, "classifier.zoning", "step_m", &x.step_m);
      r.Get(z, "classifier.zoning", "zone2_min_d_m", &x.zone2_min_d_m);
      r.Get(z, "classifier.zoning", "zone0_max_d_m", &x.zone0_max_d_m);
    }
  }
  r.Get(root, "", "min_translation_m", &o.min_translation_m);
  r.Get(root, "", "pure_rotation_deg", &o.pure_rotation_deg);
  r.Get(root, "", "mirror_aware", &o.mirror_aware);
  if (auto why = o.Validate(); !why.empty()) throw Error(where + ": invalid options: " + why);
  return o;
}

IptOptions LoadIptOptions(const std::filesystem::path& path, const IptOptions& base) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open the options file");
  std::stringstream text;
  text << in.rdbuf();
  return IptOptionsFromYaml(text.str(), path.string(), base);
}

std::string IptOptionsToYaml(const IptOptions& o) {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << YAML::BeginMap;
  const auto& f = o.features;
  e << YAML::Key << "features" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "detector" << YAML::Value << obstacles::DetectorName(f.detector);
  e << YAML::Key << "max_features" << YAML::Value << f.max_features;
  e << YAML::Key << "ratio" << YAML::Value << f.ratio;
  e << YAML::Key << "sift_contrast_threshold" << YAML::Value << f.sift_contrast_threshold;
  e << YAML::Key << "sift_octave_layers" << YAML::Value << f.sift_octave_layers;
  e << YAML::Key << "sift_first_octave" << YAML::Value << f.sift_first_octave;
  e << YAML::Key << "orb_fast_threshold" << YAML::Value << f.orb_fast_threshold;
  e << YAML::Key << "orb_levels" << YAML::Value << f.orb_levels;
  e << YAML::Key << "orb_upright" << YAML::Value << f.orb_upright;
  e << YAML::Key << "akaze_threshold" << YAML::Value << f.akaze_threshold;
  e << YAML::Key << "klt_quality" << YAML::Value << f.klt_quality;
  e << YAML::Key << "klt_min_distance_px" << YAML::Value << f.klt_min_distance_px;
  e << YAML::Key << "klt_window_px" << YAML::Value << f.klt_window_px;
  e << YAML::Key << "klt_levels" << YAML::Value << f.klt_levels;
  e << YAML::Key << "klt_max_fb_error_px" << YAML::Value << f.klt_max_fb_error_px;
  e << YAML::Key << "refine_subpixel" << YAML::Value << f.refine_subpixel;
  e << YAML::Key << "refine_window_px" << YAML::Value << f.refine_window_px;
  e << YAML::Key << "refine_max_shift_px" << YAML::Value << f.refine_max_shift_px;
  e << YAML::Key << "max_displacement_px" << YAML::Value << f.max_displacement_px;
  e << YAML::EndMap;
  const auto& F = o.fundamental;
  e << YAML::Key << "fundamental" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "inlier_threshold_px" << YAML::Value << F.inlier_threshold_px;
  e << YAML::Key << "confidence" << YAML::Value << F.confidence;
  e << YAML::Key << "max_iterations" << YAML::Value << F.max_iterations;
  e << YAML::Key << "max_refinements" << YAML::Value << F.max_refinements;
  e << YAML::Key << "min_matches" << YAML::Value << F.min_matches;
  e << YAML::EndMap;
  const auto& c = o.classifier;
  e << YAML::Key << "classifier" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "zone_beta" << YAML::Value << c.zone_beta;
  e << YAML::Key << "refinement" << YAML::Value << c.refinement;
  e << YAML::Key << "zones" << YAML::Value << YAML::BeginSeq;
  for (const auto& t : c.zones) {
    e << YAML::Flow << YAML::BeginMap << YAML::Key << "beta_m" << YAML::Value << t.beta_m;
    if (t.refine_high_m) e << YAML::Key << "refine_high_m" << YAML::Value << *t.refine_high_m;
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
  e << YAML::Key << "zoning" << YAML::Value << YAML::Flow << YAML::BeginMap;
  e << YAML::Key << "dst_m" << YAML::Value << c.zoning.dst_m;
  e << YAML::Key << "step_m" << YAML::Value << c.zoning.step_m;
  e << YAML::Key << "zone2_min_d_m" << YAML::Value << c.zoning.zone2_min_d_m;
  e << YAML::Key << "zone0_max_d_m" << YAML::Value << c.zoning.zone0_max_d_m;
  e << YAML::EndMap;
  e << YAML::EndMap;
  e << YAML::Key << "min_translation_m" << YAML::Value << o.min_translation_m;
  e << YAML::Key << "pure_rotation_deg" << YAML::Value << o.pure_rotation_deg;
  e << YAML::Key << "mirror_aware" << YAML::Value << o.mirror_aware;
  e << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

void SaveIptOptions(const std::filesystem::path& path, const IptOptions& options) {
  io::WriteFileAtomically(path, IptOptionsToYaml(options));
}

}  // namespace squint::config
