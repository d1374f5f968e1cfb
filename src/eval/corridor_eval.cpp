// Corridor perception against ground truth: the runs, the calibration fit and file, and the
// evaluation report (corridor_eval.hpp).
#include "squint/eval/corridor_eval.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "squint/config/corridor_yaml.hpp"
#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/core/pose.hpp"
#include "squint/corridor/distance_measures.hpp"
#include "squint/corridor/perceiver.hpp"
#include "squint/eval/metrics.hpp"
#include "squint/eval/plot.hpp"
#include "squint/io/atomic_output.hpp"

namespace squint::eval {
namespace {

namespace fs = std::filesystem;
using corridor::DistanceCue;
using corridor::HeadingCue;
using corridor::kDistanceCueCount;
using corridor::kHeadingCueCount;

constexpr const char* kRecordTag = "squint-corridor-calibration/1";

const char* HName(int i) { return corridor::CueName(static_cast<HeadingCue>(i)); }
const char* DName(int i) { return corridor::CueName(static_cast<DistanceCue>(i)); }

// ---- Calibration record YAML --------------------------------------------------------------

template <typename T>
void Read(const YAML::Node& map, const std::string& key, T& value, const std::string& source,
          const std::string& path) {
  const YAML::Node n = map[key];
  if (!n) return;
  try {
    value = n.as<T>();
  } catch (const YAML::Exception&) {
    throw Error(source + ": '" + path + key + "' has a value of the wrong type (line " +
                std::to_string(n.Mark().line + 1) + ")");
  }
}

void EmitRecord(YAML::Emitter& e, const CalibrationRecord& r) {
  e << YAML::BeginMap;
  e << YAML::Key << "calibration" << YAML::Value << kRecordTag;
  e << YAML::Key << "fitted_on" << YAML::Value << YAML::Flow << r.fitted_on;
  e << YAML::Key << "intrinsics" << YAML::Value << r.intrinsics;
  e << YAML::Key << "heading" << YAML::Value << YAML::BeginMap;
  for (int i = 0; i < kHeadingCueCount; ++i) {
    const HeadingCueCalibration& h = r.heading[i];
    e << YAML::Key << HName(i) << YAML::Value << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "fitted" << YAML::Value << h.fitted;
    e << YAML::Key << "scale" << YAML::Value << h.scale;
    e << YAML::Key << "bias_deg" << YAML::Value << h.bias_deg;
    e << YAML::Key << "error_std_deg" << YAML::Value << h.error_std_deg;
    e << YAML::Key << "rmse_deg" << YAML::Value << h.rmse_deg;
    e << YAML::Key << "inlier_fraction" << YAML::Value << h.inlier_fraction;
    e << YAML::Key << "reliable_min_deg" << YAML::Value << h.reliable_min_deg;
    e << YAML::Key << "reliable_max_deg" << YAML::Value << h.reliable_max_deg;
    e << YAML::Key << "samples" << YAML::Value << h.samples;
    e << YAML::EndMap;
  }
  e << YAML::EndMap;
  e << YAML::Key << "fused_distance_rmse_m" << YAML::Value << r.fused_distance_rmse_m;
  e << YAML::Key << "distance" << YAML::Value << YAML::BeginMap;
  for (int i = 0; i < kDistanceCueCount; ++i) {
    const DistanceCueCalibration& d = r.distance[i];
    e << YAML::Key << DName(i) << YAML::Value << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "fitted" << YAML::Value << d.fitted;
    e << YAML::Key << "scale" << YAML::Value << d.scale;
    e << YAML::Key << "alpha" << YAML::Value << d.alpha;
    e << YAML::Key << "beta" << YAML::Value << d.beta;
    e << YAML::Key << "rmse_m" << YAML::Value << d.rmse_m;
    e << YAML::Key << "error_std_m" << YAML::Value << d.error_std_m;
    e << YAML::Key << "sigma0_m" << YAML::Value << d.sigma0_m;
    e << YAML::Key << "sigma_slope" << YAML::Value << d.sigma_slope;
    e << YAML::Key << "inlier_fraction" << YAML::Value << d.inlier_fraction;
    e << YAML::Key << "samples" << YAML::Value << d.samples;
    e << YAML::EndMap;
  }
  e << YAML::EndMap;
  e << YAML::EndMap;
}

CalibrationRecord ParseRecord(const YAML::Node& root, const std::string& source) {
  CalibrationRecord r;
  if (!root.IsMap()) throw Error(source + ": the calibration record (second document) must be a mapping");
  std::string tag;
  Read(root, "calibration", tag, source, "");
  if (tag != kRecordTag)
    throw Error(source + ": the second document's 'calibration' must be '" + std::string(kRecordTag) + "'");
  Read(root, "fitted_on", r.fitted_on, source, "");
  Read(root, "intrinsics", r.intrinsics, source, "");
  Read(root, "fused_distance_rmse_m", r.fused_distance_rmse_m, source, "");
  if (const YAML::Node h = root["heading"]) {
    if (!h.IsMap()) throw Error(source + ": 'heading' must be a mapping");
    for (int i = 0; i < kHeadingCueCount; ++i) {
      const YAML::Node c = h[HName(i)];
      if (!c) continue;
      const std::string p = std::string("heading.") + HName(i) + ".";
      HeadingCueCalibration& x = r.heading[i];
      Read(c, "fitted", x.fitted, source, p);
      Read(c, "scale", x.scale, source, p);
      Read(c, "bias_deg", x.bias_deg, source, p);
      Read(c, "error_std_deg", x.error_std_deg, source, p);
      Read(c, "rmse_deg", x.rmse_deg, source, p);
      Read(c, "inlier_fraction", x.inlier_fraction, source, p);
      Read(c, "reliable_min_deg", x.reliable_min_deg, source, p);
      Read(c, "reliable_max_deg", x.reliable_max_deg, source, p);
      Read(c, "samples", x.samples, source, p);
      if (!(x.error_std_deg > 0.0) || !std::isfinite(x.error_std_deg))
        throw Error(source + ": '" + p + "error_std_deg' must be positive");
    }
  }
  if (const YAML::Node d = root["distance"]) {
    if (!d.IsMap()) throw Error(source + ": 'distance' must be a mapping");
    for (int i = 0; i < kDistanceCueCount; ++i) {
      const YAML::Node c = d[DName(i)];
      if (!c) continue;
      const std::string p = std::string("distance.") + DName(i) + ".";
      DistanceCueCalibration& x = r.distance[i];
      Read(c, "fitted", x.fitted, source, p);
      Read(c, "scale", x.scale, source, p);
      Read(c, "alpha", x.alpha, source, p);
      Read(c, "beta", x.beta, source, p);
      Read(c, "rmse_m", x.rmse_m, source, p);
      Read(c, "error_std_m", x.error_std_m, source, p);
      Read(c, "sigma0_m", x.sigma0_m, source, p);
      Read(c, "sigma_slope", x.sigma_slope, source, p);
      Read(c, "inlier_fraction", x.inlier_fraction, source, p);
      Read(c, "samples", x.samples, source, p);
      if (!(x.sigma0_m > 0.0) || !(x.sigma_slope >= 0.0))
        throw Error(source + ": '" + p + "sigma0_m' must be positive and 'sigma_slope' non-negative");
    }
  }
  return r;
}

}  // namespace

std::string CalibrationFileToYaml(const CorridorCalibrationFile& file) {
  std::ostringstream os;
  os << "# squint corridor calibration (written by `squint calibrate`; docs/calibration.md).\n"
        "# Document 1: the perception options (include/squint/config/corridor_yaml.hpp), read by\n"
        "#   perceive, eval and explore through --calib. Heading cue weights are 1/sigma^2 (deg^-2),\n"
        "#   distance cue weights 1/sigma^2 (m^-2) at the distance named in the record.\n"
        "# Document 2: the calibration record: what was fitted, on which sequences, how well, the\n"
        "#   reliable heading range of each cue and the Kalman filter's measurement noise.\n";
  os << config::CorridorOptionsToYaml(file.options);
  os << "\n---\n";
  YAML::Emitter e;
  e.SetDoublePrecision(8);
  EmitRecord(e, file.record);
  os << e.c_str() << "\n";
  return os.str();
}

CorridorCalibrationFile CalibrationFileFromYaml(const std::string& text, const std::string& source) {
  CorridorCalibrationFile f;
  std::vector<YAML::Node> docs;
  try {
    docs = YAML::LoadAll(text);
  } catch (const YAML::Exception& ex) {
    throw Error(source + ": YAML parse error at line " + std::to_string(ex.mark.line + 1) + ": " + ex.msg);
  }
  if (docs.size() > 2) throw Error(source + ": expected at most two YAML documents, found " + std::to_string(docs.size()));
  // The options document: parsed by its owner (the first document of the text).
  std::string first = text;
  if (docs.size() == 2) {
    const std::size_t sep = text.find("\n---");
    if (sep != std::string::npos) first = text.substr(0, sep + 1);
  }
  f.options = config::CorridorOptionsFromYaml(first, source);
  if (docs.size() == 2) f.record = ParseRecord(docs[1], source);
  return f;
}

CorridorCalibrationFile LoadCalibrationFile(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open the calibration file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return CalibrationFileFromYaml(ss.str(), path.string());
}

void SaveCalibrationFile(const fs::path& path, const CorridorCalibrationFile& file) {
  io::WriteFileAtomically(path, CalibrationFileToYaml(file));
}

// ---- Runs -------------------------------------------------------------------------------

CorridorRun RunCorridorSequence(const io::Sequence& sequence, const CorridorRunOptions& options,
                                const std::function<void(std::size_t)>& progress) {
  CorridorRun run;
  run.name = sequence.Dir().filename().string();
  if (run.name.empty()) run.name = sequence.Dir().parent_path().filename().string();
  corridor::CorridorOptions ungated = options.perception;
  ungated.gate.enabled = false;
  corridor::CorridorOptions gated = options.perception;
  gated.gate.enabled = true;
  corridor::Perceiver all(ungated, sequence.Camera());
  std::optional<corridor::Perceiver> with_gate;
  if (options.gated_pass) with_gate.emplace(gated, sequence.Camera());
  corridor::CorridorKalman kalman(options.kalman);

  const corridor::DistanceOptions& dopt = options.perception.distance;

  const auto& records = sequence.Frames();
  run.frames.reserve(records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    const io::FrameRecord& rec = records[i];
    const cv::Mat img = sequence.LoadImage(i);
    const corridor::PixelView view{img.data, img.cols, img.rows, static_cast<std::ptrdiff_t>(img.step[0]),
                                   img.channels()};
    CorridorFrame f;
    f.index = i;
    f.stamp = rec.stamp;
    f.gt = rec.gt;
    std::optional<Pose2> motion;
    double dt_s = 0.0;
    if (i > 0) {
      dt_s = std::max(0.0, rec.stamp - records[i - 1].stamp);
      if (rec.odom && records[i - 1].odom) {
        motion = Between(*records[i - 1].odom, *rec.odom);
        f.travelled_m = std::hypot(motion->x, motion->y);
        f.moving_forward = motion->x >= options.min_forward_m &&
                           std::abs(RadToDeg(WrapPi(motion->yaw))) < options.max_turn_deg;
      }
    }
    std::optional<double> turned_deg;
    if (motion) turned_deg = RadToDeg(WrapPi(motion->yaw));
    const corridor::PerceptionResult r = all.Process(view, f.travelled_m, dt_s, turned_deg);
    for (int c = 0; c < kHeadingCueCount; ++c) {
      const corridor::HeadingMeasureResult& h = r.heading[c];
      if (h.column_px) f.heading_camera_deg[c] = all.ColumnToHeadingDeg(*h.column_px);
      f.heading_deg[c] = h.heading_deg;
    }
    // Per cue: this frame's own model input and estimate, and the Perceiver's temporal median
    // (its output). The unfiltered weighted average is recomputed here for comparison.
    double sw = 0.0, swd = 0.0;
    for (int c = 0; c < kDistanceCueCount; ++c) {
      const corridor::DistanceMeasureResult& d = r.distance[c];
      f.dist_raw[c] = d.model_input;
      f.dist_m[c] = d.instant_m;
      f.dist_filtered_raw[c] = d.filtered_input;
      f.dist_filtered_m[c] = d.dist_m;
      if (d.instant_m && dopt.fuse[c]) {
        const double w = dopt.FusionWeight(c, *d.instant_m);
        sw += w;
        swd += w * *d.instant_m;
      }
    }
    if (sw > 0.0) f.instant_dist_m = swd / sw;
    f.fused_heading_deg = r.heading_deg;
    f.fused_instant_heading_deg = r.heading_instant_deg;
    f.fused_dist_m = r.dist_end_m;

    // Kalman filter over the cues, odometry as the process model.
    if (i > 0) kalman.Predict(motion);
    for (int c = 0; c < kHeadingCueCount; ++c) {
      if (!f.heading_deg[c]) continue;
      const HeadingCueCalibration& hc = options.record.heading[c];
      if (options.kalman_reliable_ranges_only &&
          (*f.heading_deg[c] < hc.reliable_min_deg || *f.heading_deg[c] > hc.reliable_max_deg))
        continue;
      kalman.UpdateHeading(*f.heading_deg[c], hc.error_std_deg);
    }
    for (int c = 0; c < kDistanceCueCount; ++c) {
      if (!f.dist_filtered_m[c] || !dopt.fuse[c]) continue;
      const DistanceCueCalibration& dc = options.record.distance[c];
      kalman.UpdateDistance(*f.dist_filtered_m[c],
                            dc.sigma0_m + dc.sigma_slope * std::max(0.0, *f.dist_filtered_m[c]));
    }
    f.kalman_heading_deg = kalman.HeadingDeg();
    f.kalman_dist_m = kalman.DistanceM();

    if (with_gate) {
      const corridor::PerceptionResult g = with_gate->Process(view, f.travelled_m, dt_s, turned_deg);
      f.gated_processed = g.processed;
      f.gate_change = g.gate_change;
      if (g.processed) f.gated_heading_deg = g.heading_deg;
    }
    run.frames.push_back(f);
    if (progress) progress(i + 1);
  }
  return run;
}

// ---- Calibration fit --------------------------------------------------------------------

std::string CalibrateOptions::Validate() const {
  if (!fit_heading && !fit_distance) return "nothing to fit (both heading and distance are off)";
  if (!std::isfinite(ttc_cell_px) || (ttc_cell_px != 0.0 && ttc_cell_px < 3.0))
    return "ttc_cell_px must be 0 (keep the base's) or >= 3";
  if (!(ttc_cell_quantile >= 0.0 && ttc_cell_quantile <= 1.0)) return "ttc_cell_quantile must be in [0, 1]";
  if (ttc_cell_nearest < 0 || ttc_cell_nearest > 96) return "ttc_cell_nearest must be in [0, 96]";
  if (!(ttc_glance_scale >= 1.0 && ttc_glance_scale <= 4.0)) return "ttc_glance_scale must be in [1, 4]";
  if (!(floor_motion_window_m >= 0.0 && std::isfinite(floor_motion_window_m)))
    return "floor_motion_window_m must be >= 0 (0 = keep the base's)";
  if (!(floor_lined_wall_rel_step >= 0.0 && floor_lined_wall_rel_step <= 1.0))
    return "floor_lined_wall_rel_step must be in [0, 1] (0 = keep the base's)";
  for (double c : ttc_glance_scales)
    if (!(c >= 1.0 && c <= 4.0)) return "every ttc_glance_scales candidate must be in [1, 4]";
  if (!(fusion_max_truth_m > 0.0)) return "fusion_max_truth_m must be positive";
  if (!(min_fused_coverage >= 0.0 && min_fused_coverage <= 1.0)) return "min_fused_coverage must be in [0, 1]";
  if (std::string s = heading.Validate(); !s.empty()) return "heading: " + s;
  if (std::string s = distance.Validate(); !s.empty()) return "distance: " + s;
  return {};
}

corridor::CorridorOptions CalibrationBaseOptions(const corridor::CorridorOptions& base,
                                                 const CalibrateOptions& options) {
  corridor::CorridorOptions out = base;
  if (options.fit_distance && options.ttc_cell_px > 0.0 && base.distance.ttc_cell_px == 0.0) {
    out.distance.ttc_cell_px = options.ttc_cell_px;
    out.distance.ttc_cell_quantile = options.ttc_cell_quantile;
    out.distance.ttc_cell_nearest = options.ttc_cell_nearest;
  }
  if (options.fit_distance && options.ttc_glance_scale != 1.0 && base.distance.ttc_glance_scale == 1.0)
    out.distance.ttc_glance_scale = options.ttc_glance_scale;
  if (options.fit_distance && options.floor_motion_window_m > 0.0 && base.distance.floor_contact.motion_window_m == 0.0)
    out.distance.floor_contact.motion_window_m = options.floor_motion_window_m;
  if (options.fit_distance && options.floor_refine_same_sign) out.distance.floor_contact.refine_same_sign = true;
  if (options.fit_distance && options.floor_lined_wall_rel_step > 0.0 && base.distance.floor_contact.lined_wall_rel_step == 0.0)
    out.distance.floor_contact.lined_wall_rel_step = options.floor_lined_wall_rel_step;
  return out;
}

void CheckCalibrationInputs(const io::Sequence& sequence, bool need_heading, bool need_distance) {
  const std::string where = (sequence.Dir() / "frames.csv").string();
  if (sequence.Size() == 0) throw Error(where + ": no frames");
  bool any_heading = false, any_dist = false;
  for (const io::FrameRecord& r : sequence.Frames()) {
    any_heading = any_heading || r.gt.heading_deg.has_value();
    any_dist = any_dist || r.gt.dist_end_m.has_value();
  }
  if (need_heading && !any_heading)
    throw Error(where + ": no gt_heading_deg values; heading calibration needs ground-truth heading "
                        "(or pass --only distance)");
  if (need_distance && !any_dist)
    throw Error(where + ": no gt_dist_end_m values; distance calibration needs ground-truth distance to the "
                        "end (or pass --only heading)");
  if (need_distance && !sequence.HasOdometry())
    throw Error(where + ": distance calibration needs odometry (odom_x, odom_y, odom_yaw on every row) to scale "
                        "time to contact and to tell driving from turning");
}

void CheckCalibrationSpread(const std::vector<const io::Sequence*>& sequences, bool need_heading,
                            bool need_distance, double min_heading_span_deg, double min_dist_span_m) {
  double h_lo = HUGE_VAL, h_hi = -HUGE_VAL, d_lo = HUGE_VAL, d_hi = -HUGE_VAL;
  for (const io::Sequence* s : sequences)
    for (const io::FrameRecord& r : s->Frames()) {
      if (r.gt.heading_deg) {
        h_lo = std::min(h_lo, *r.gt.heading_deg);
        h_hi = std::max(h_hi, *r.gt.heading_deg);
      }
      if (r.gt.dist_end_m) {
        d_lo = std::min(d_lo, *r.gt.dist_end_m);
        d_hi = std::max(d_hi, *r.gt.dist_end_m);
      }
    }
  if (need_heading && !(h_hi - h_lo >= min_heading_span_deg))
    throw Error(fmt::format("singular calibration: the true headings of all {} sequence(s) span only {:.3g} deg "
                            "(need >= {:g}); record a heading sweep (or pass --only distance)",
                            sequences.size(), std::max(0.0, h_hi - h_lo), min_heading_span_deg));
  if (need_distance && !(d_hi - d_lo >= min_dist_span_m))
    throw Error(fmt::format("singular calibration: the true distances to the end of all {} sequence(s) span only "
                            "{:.3g} m (need >= {:g}); record a drive toward the end (or pass --only heading)",
                            sequences.size(), std::max(0.0, d_hi - d_lo), min_dist_span_m));
}

namespace {

// The fused distance of one calibration frame under the fitted options for the cues in `mask`
// (bit c = cue c): each cue's fitted model applied to the Perceiver's filtered input, weighted as
// Perceiver::Fuse does; its σ = 1 / sqrt(Σ w). None when no cue in the mask answered.
struct FusedSample {
  double dist_m = 0.0;
  double std_m = 0.0;
};
std::optional<FusedSample> FuseFrame(const CorridorFrame& f, const corridor::DistanceOptions& d,
                                     const std::array<std::unique_ptr<corridor::DistanceMeasure>, kDistanceCueCount>& m,
                                     unsigned mask) {
  double sw = 0.0, swd = 0.0;
  for (int c = 0; c < kDistanceCueCount; ++c) {
    if (!(mask & (1u << c)) || !f.dist_filtered_raw[c]) continue;
    const std::optional<double> est = m[c]->Distance(*f.dist_filtered_raw[c]);
    if (!est) continue;
    const double w = d.FusionWeight(c, *est);
    sw += w;
    swd += w * *est;
  }
  if (!(sw > 0.0)) return std::nullopt;
  return FusedSample{swd / sw, 1.0 / std::sqrt(sw)};
}

}  // namespace

namespace {

// The frames the distance fusion is judged on: driving forward, truth within the distance fits'
// window, up to fusion_max_truth_m.
std::vector<const CorridorFrame*> FusionFrames(const std::vector<CorridorRun>& runs, const CalibrateOptions& options) {
  std::vector<const CorridorFrame*> frames;
  for (const CorridorRun& run : runs)
    for (const CorridorFrame& f : run.frames)
      if (f.moving_forward && f.gt.dist_end_m && *f.gt.dist_end_m >= options.distance.min_truth_m &&
          *f.gt.dist_end_m <= std::min(options.distance.max_truth_m, options.fusion_max_truth_m))
        frames.push_back(&f);
  return frames;
}

// RMSE against the truth over the FusionFrames of an estimate per frame (`estimate(frame)`: an
// optional distance); `answered` counts the frames with one.
template <class Estimate>
CueRmse FusionFramesRmse(const std::vector<CorridorRun>& runs, const CalibrateOptions& options, Estimate estimate) {
  CueRmse out;
  double sq = 0.0;
  for (const CorridorFrame* f : FusionFrames(runs, options)) {
    ++out.frames;
    if (const std::optional<double> e = estimate(*f)) {
      sq += (*e - *f->gt.dist_end_m) * (*e - *f->gt.dist_end_m);
      ++out.answered;
    }
  }
  if (out.answered > 0) out.rmse_m = std::sqrt(sq / static_cast<double>(out.answered));
  return out;
}

}  // namespace

CueRmse TtcCalibrationRmse(const std::vector<CorridorRun>& runs, const CalibrateOptions& options,
                           const CorridorCalibrationFile& file) {
  const corridor::DistanceOptions& d = file.options.distance;
  std::array<std::unique_ptr<corridor::DistanceMeasure>, kDistanceCueCount> m;
  m[0] = std::make_unique<corridor::TimeToContactDistance>(d, 0.0, 0.0);
  return FusionFramesRmse(runs, options, [&](const CorridorFrame& f) -> std::optional<double> {
    if (const auto e = FuseFrame(f, d, m, 1u)) return e->dist_m;
    return std::nullopt;
  });
}

CueRmse FusedDistanceRmse(const std::vector<CorridorRun>& runs, const CalibrateOptions& options) {
  return FusionFramesRmse(runs, options, [](const CorridorFrame& f) { return f.fused_dist_m; });
}

bool KeepFloorMotion(const CueRmse& with, const CueRmse& without) {
  return with.answered >= without.answered && with.rmse_m < without.rmse_m;
}

void ChooseDistanceFusion(const std::vector<CorridorRun>& runs, const CalibrateOptions& options,
                          CorridorCalibrationFile& out) {
  corridor::DistanceOptions& d = out.options.distance;
  std::array<std::unique_ptr<corridor::DistanceMeasure>, kDistanceCueCount> m;
  m[0] = std::make_unique<corridor::TimeToContactDistance>(d, 0.0, 0.0);
  m[1] = std::make_unique<corridor::JeffreyDistance>(d);
  m[2] = std::make_unique<corridor::EntropyDistance>(d);
  // The frames the distance fits use (driving forward, truth within the fit's window), up to
  // fusion_max_truth_m.
  const std::vector<const CorridorFrame*> frames = FusionFrames(runs, options);
  if (frames.empty()) return;
  // The cues that enter the fusion now (enabled, weighted, fuse on), as a mask.
  const auto fused_cues = [&d] {
    unsigned mask = 0;
    for (int c = 0; c < kDistanceCueCount; ++c)
      if (d.enabled[c] && d.weights[c] > 0.0 && d.fuse[c]) mask |= 1u << c;
    return mask;
  };
  const unsigned available = fused_cues();
  if (options.select_distance_cues && available != 0) {
    // The non-empty subset of the available cues whose fusion has the lowest RMSE over the frames
    // where it answers; a subset answering on fewer frames than the best coverage of any subset
    // (less 5 %) is not considered. Ties: the larger subset (the lower mask on equal size).
    // One pass per subset: its frames answered and squared error.
    constexpr unsigned kSubsets = 1u << kDistanceCueCount;
    std::array<std::size_t, kSubsets> answered{};
    std::array<double, kSubsets> sq_error{};
    std::size_t best_cover = 0;
    for (unsigned mask = 1; mask < kSubsets; ++mask) {
      if ((mask & ~available) != 0) continue;
      for (const CorridorFrame* f : frames)
        if (const auto e = FuseFrame(*f, d, m, mask)) {
          sq_error[mask] += (e->dist_m - *f->gt.dist_end_m) * (e->dist_m - *f->gt.dist_end_m);
          ++answered[mask];
        }
      best_cover = std::max(best_cover, answered[mask]);
    }
    unsigned best = available;
    double best_rmse = HUGE_VAL;
    for (unsigned mask = 1; mask < kSubsets; ++mask) {
      if ((mask & ~available) != 0) continue;
      const std::size_t n = answered[mask];
      if (n == 0 || static_cast<double>(n) < 0.95 * static_cast<double>(best_cover)) continue;
      const double rmse = std::sqrt(sq_error[mask] / static_cast<double>(n));
      const bool better = rmse < best_rmse - 1e-12 ||
                          (std::abs(rmse - best_rmse) <= 1e-12 && std::popcount(mask) > std::popcount(best));
      if (better) best_rmse = rmse, best = mask;
    }
    for (int c = 0; c < kDistanceCueCount; ++c)
      if (available & (1u << c)) d.fuse[c] = (best & (1u << c)) != 0;
    out.record.fused_distance_rmse_m = best_rmse;
  }
  if (options.fused_std_gate) {
    // The standard deviation of the true distances over the same frames; applied only when it
    // lowers the fused RMSE there and leaves an estimate on at least min_fused_coverage of them
    // (the calibrated σ may be far from the fused estimate's real error: the simulator's drives
    // fit time to contact a σ0 of 6 m, and every fused σ then exceeded the truth's spread).
    double sum = 0.0, sum2 = 0.0;
    for (const CorridorFrame* f : frames) sum += *f->gt.dist_end_m, sum2 += *f->gt.dist_end_m * *f->gt.dist_end_m;
    const double n = static_cast<double>(frames.size());
    const double limit = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
    const unsigned mask = fused_cues();  // after the choice above
    double s2_all = 0.0, s2_kept = 0.0;
    std::size_t n_all = 0, n_kept = 0;
    for (const CorridorFrame* f : frames)
      if (const auto e = FuseFrame(*f, d, m, mask)) {
        const double err2 = (e->dist_m - *f->gt.dist_end_m) * (e->dist_m - *f->gt.dist_end_m);
        s2_all += err2, ++n_all;
        if (e->std_m <= limit) s2_kept += err2, ++n_kept;
      }
    const bool lower = n_kept > 0 && n_all > 0 &&
                       s2_kept / static_cast<double>(n_kept) < s2_all / static_cast<double>(n_all);
    d.fused_max_std_m =
        lower && static_cast<double>(n_kept) >= options.min_fused_coverage * n ? limit : 0.0;
  }
}

CorridorCalibrationFile FitCorridorCalibration(const std::vector<CorridorRun>& runs,
                                               const std::vector<std::string>& sequence_names,
                                               const corridor::CorridorOptions& base,
                                               const CalibrateOptions& options) {
  if (const std::string bad = options.Validate(); !bad.empty()) throw Error("calibrate: " + bad);
  CorridorCalibrationFile out;
  out.options = base;
  out.record.fitted_on = sequence_names;

  if (options.fit_heading) {
    for (int c = 0; c < kHeadingCueCount; ++c) {
      std::vector<corridor::HeadingSample> s;
      for (const CorridorRun& run : runs)
        for (const CorridorFrame& f : run.frames)
          // Heading is fitted on frames that are not driving forward (the sweeps of §5.1): the
          // thousands of straight-driving frames at one heading would otherwise swamp the fit.
          if (!f.moving_forward && f.gt.heading_deg && f.heading_camera_deg[c])
            s.push_back({*f.gt.heading_deg, *f.heading_camera_deg[c]});
      const std::string what = std::string("heading cue '") + HName(c) + "'";
      if (s.empty()) throw Error(what + ": no frame gave both an estimate and a ground-truth heading");
      const corridor::HeadingFit fit = corridor::FitHeading(s, what, options.heading);
      HeadingCueCalibration& h = out.record.heading[c];
      h.fitted = true;
      h.scale = fit.scale;
      h.bias_deg = fit.bias_deg;
      h.error_std_deg = std::max(0.5, fit.error_std_deg);
      h.rmse_deg = fit.rmse_deg;
      h.inlier_fraction = fit.inlier_fraction;
      h.reliable_min_deg = fit.reliable_min_deg;
      h.reliable_max_deg = fit.reliable_max_deg;
      h.samples = fit.samples;
      corridor::HeadingCueOptions& o = out.options.heading.cues[c];
      o.scale = fit.scale;
      o.bias_deg = fit.bias_deg;
      o.std_deg = h.error_std_deg;
      // A cue the base options switch off (weight 0) stays off: it is fitted for the record only.
      if (o.enabled && o.weight > 0.0 && options.heading_weights_from_variance)
        o.weight = 1.0 / (h.error_std_deg * h.error_std_deg);
    }
  }
  if (options.fit_heading && options.heading_filter) out.options.heading.filter.enabled = true;
  if (options.fit_distance) {
    for (int c = 0; c < kDistanceCueCount; ++c) {
      std::vector<corridor::DistanceSample> s;
      for (const CorridorRun& run : runs)
        for (const CorridorFrame& f : run.frames)
          if (f.moving_forward && f.gt.dist_end_m && f.dist_filtered_raw[c])
            s.push_back({*f.gt.dist_end_m, *f.dist_filtered_raw[c]});
      const std::string what = std::string("distance cue '") + DName(c) + "'";
      if (s.empty())
        throw Error(what + ": no frame gave both an estimate and a ground-truth distance while driving forward");
      corridor::DistanceFit fit;
      DistanceCueCalibration& d = out.record.distance[c];
      switch (static_cast<DistanceCue>(c)) {
        case DistanceCue::kTimeToContact:
          fit = corridor::FitTtcScale(s, what, options.distance);
          out.options.distance.ttc_scale = fit.scale;
          out.options.distance.ttc_bias_m = fit.beta;
          break;
        case DistanceCue::kJeffrey:
          fit = corridor::FitJeffrey(s, what, options.distance);
          out.options.distance.alpha2 = fit.alpha;
          out.options.distance.beta2 = fit.beta;
          break;
        case DistanceCue::kEntropy:
          fit = corridor::FitEntropyDistance(s, what, options.distance);
          out.options.distance.alpha3 = fit.alpha;
          break;
      }
      d.fitted = true;
      d.scale = static_cast<DistanceCue>(c) == DistanceCue::kTimeToContact ? fit.checked_scale : fit.scale;
      d.alpha = fit.alpha;
      d.beta = fit.beta;
      d.rmse_m = fit.rmse_m;
      d.error_std_m = fit.error_std_m;
      d.sigma0_m = fit.spread.sigma0_m;
      d.sigma_slope = fit.spread.sigma_slope;
      d.inlier_fraction = fit.inlier_fraction;
      d.samples = fit.samples;
      // Fusion weight 1/σ0² with σ growing as σ0 · (1 + growth · d); a cue the base options
      // switch off stays off.
      const double sigma0 = std::max(fit.spread.sigma0_m, 0.05);
      if (out.options.distance.enabled[c] && out.options.distance.weights[c] > 0.0) {
        out.options.distance.weights[c] = 1.0 / (sigma0 * sigma0);
        out.options.distance.error_growth_per_m[c] = fit.spread.sigma_slope / sigma0;
      }
    }
  }
  if (options.fit_distance && (options.select_distance_cues || options.fused_std_gate))
    ChooseDistanceFusion(runs, options, out);
  if (const std::string bad = out.options.Validate(); !bad.empty())
    throw Error("calibrate: the fitted options are invalid: " + bad);
  return out;
}

// ---- Report -----------------------------------------------------------------------------

std::string CorridorEvalOptions::Validate() const {
  if (!(heading_bin_deg > 0.0) || !(dist_bin_m > 0.0)) return "bin widths must be positive";
  if (!(sign_min_abs_deg >= 0.0)) return "sign_min_abs_deg must be >= 0";
  if (gate_block == 0) return "gate_block must be positive";
  if (!(entropy_hist_max > 0.0) || entropy_hist_bins <= 0) return "bad entropy histogram range";
  if (plot_width_px < 200 || plot_height_px < 150) return "plots must be at least 200×150";
  return {};
}

namespace {

using Json = nlohmann::json;

Json SummaryJson(const ErrorSummary& s, const char* unit) {
  return Json{{"frames", s.frames},
              {"estimated", s.estimated},
              {"coverage", s.coverage},
              {std::string("rmse_") + unit, s.rmse},
              {std::string("mean_error_") + unit, s.mean_error},
              {std::string("std_error_") + unit, s.std_error},
              {std::string("max_abs_error_") + unit, s.max_abs_error}};
}

Json BinsJson(const std::vector<BinStats>& bins, bool with_sign) {
  Json a = Json::array();
  for (const BinStats& b : bins) {
    Json j{{"lo", b.lo},
           {"hi", b.hi},
           {"frames", b.frames},
           {"estimated", b.estimated},
           {"mean_truth", b.mean_truth},
           {"mean_estimate", b.mean_estimate},
           {"std_estimate", b.std_estimate},
           {"rmse", b.rmse}};
    if (with_sign) {
      j["signed_frames"] = b.signed_frames;
      j["right_sign_fraction"] = b.right_sign_fraction;
    }
    a.push_back(j);
  }
  return a;
}

PlotOptions Opt(const CorridorEvalOptions& o, std::string title, std::string xl, std::string yl) {
  PlotOptions p;
  p.title = std::move(title);
  p.x_label = std::move(xl);
  p.y_label = std::move(yl);
  p.width_px = o.plot_width_px;
  p.height_px = o.plot_height_px;
  return p;
}

// A series with a legend label and a style, the rest defaulted.
PlotSeries NamedSeries(std::string label, PlotStyle style) {
  PlotSeries s;
  s.label = std::move(label);
  s.style = style;
  return s;
}

// Fig. 8 / Fig. 10 style: mean estimate per bin with ±2σ, and the truth diagonal.
std::vector<PlotSeries> MeanBandSeries(const std::vector<BinStats>& bins) {
  PlotSeries mean = NamedSeries("mean estimate", PlotStyle::kLineAndMarkers);
  PlotSeries hi = NamedSeries("mean +/- 2 sigma", PlotStyle::kLine);
  PlotSeries lo = NamedSeries("", PlotStyle::kLine);
  hi.dashed = lo.dashed = true;
  hi.rgb = lo.rgb = std::array<std::uint8_t, 3>{120, 120, 200};
  hi.line_width_px = lo.line_width_px = 1;
  PlotSeries truth = NamedSeries("truth", PlotStyle::kLine);
  truth.rgb = std::array<std::uint8_t, 3>{0, 0, 0};
  truth.line_width_px = 1;
  for (const BinStats& b : bins) {
    truth.x.push_back(b.centre);
    truth.y.push_back(b.centre);
    if (b.estimated == 0) continue;
    mean.x.push_back(b.mean_truth);
    mean.y.push_back(b.mean_estimate);
    hi.x.push_back(b.mean_truth);
    hi.y.push_back(b.mean_estimate + 2 * b.std_estimate);
    lo.x.push_back(b.mean_truth);
    lo.y.push_back(b.mean_estimate - 2 * b.std_estimate);
  }
  return {truth, mean, hi, lo};
}

std::string FileSafe(const std::string& s) {
  std::string o = s;
  for (char& c : o)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return o;
}

}  // namespace

std::string WriteCorridorReport(const std::vector<CorridorRun>& runs, const fs::path& out_dir,
                                const CorridorEvalOptions& options, const std::vector<std::string>& warnings,
                                const std::string& calib_source) {
  if (const std::string bad = options.Validate(); !bad.empty()) throw Error("eval corridor: " + bad);
  io::StagedDirectory staged(out_dir);
  Json report;
  report["schema"] = "squint-corridor-eval/1";
  report["calibration"] = calib_source.empty() ? Json(nullptr) : Json(calib_source);
  report["warnings"] = warnings;
  Json seqs = Json::array();
  for (const CorridorRun& r : runs) seqs.push_back(Json{{"name", r.name}, {"frames", r.frames.size()}});
  report["sequences"] = seqs;

  // Estimators: the five heading cues, the weighted average, the Kalman filter.
  struct Estimator {
    std::string name;
    std::function<std::optional<double>(const CorridorFrame&)> get;
  };
  std::vector<Estimator> heading_est, dist_est;
  for (int c = 0; c < kHeadingCueCount; ++c)
    heading_est.push_back({HName(c), [c](const CorridorFrame& f) { return f.heading_deg[c]; }});
  heading_est.push_back({"fused", [](const CorridorFrame& f) { return f.fused_heading_deg; }});
  heading_est.push_back({"fused_instant", [](const CorridorFrame& f) { return f.fused_instant_heading_deg; }});
  heading_est.push_back({"kalman", [](const CorridorFrame& f) { return f.kalman_heading_deg; }});
  for (int c = 0; c < kDistanceCueCount; ++c)
    dist_est.push_back({DName(c), [c](const CorridorFrame& f) { return f.dist_m[c]; }});
  dist_est.push_back({"fused_instant", [](const CorridorFrame& f) { return f.instant_dist_m; }});
  for (int c = 0; c < kDistanceCueCount; ++c)
    dist_est.push_back({std::string(DName(c)) + "_median", [c](const CorridorFrame& f) { return f.dist_filtered_m[c]; }});
  dist_est.push_back({"fused", [](const CorridorFrame& f) { return f.fused_dist_m; }});
  dist_est.push_back({"kalman", [](const CorridorFrame& f) { return f.kalman_dist_m; }});

  // Heading (frames with a true heading).
  Json heading = Json::object();
  for (const Estimator& e : heading_est) {
    std::vector<Sample> s;
    for (const CorridorRun& r : runs)
      for (const CorridorFrame& f : r.frames)
        if (f.gt.heading_deg) s.push_back({*f.gt.heading_deg, e.get(f)});
    if (s.empty()) continue;
    const ErrorSummary sum = Summarize(s);
    const SignSummary sign = SignAgreement(s, options.sign_min_abs_deg);
    const auto bins = BinByTruth(s, options.heading_bin_deg, -0.5 * options.heading_bin_deg);
    Json j = SummaryJson(sum, "deg");
    j["right_sign"] = Json{{"min_abs_truth_deg", options.sign_min_abs_deg},
                           {"frames", sign.frames},
                           {"right", sign.right},
                           {"fraction", sign.fraction}};
    j["bins"] = BinsJson(bins, true);
    heading[e.name] = j;
    if (options.plots) {
      WritePlotPng(staged.Path() / ("heading_" + FileSafe(e.name) + ".png"), MeanBandSeries(bins),
                   Opt(options, "heading: " + e.name + fmt::format(" (RMSE {:.2f} deg)", sum.rmse),
                       "true heading (deg)", "estimated heading (deg)"));
      PlotSeries pct = NamedSeries("right sign %", PlotStyle::kLineAndMarkers);
      for (const BinStats& b : bins)
        if (b.signed_frames > 0) {
          pct.x.push_back(b.centre);
          pct.y.push_back(100.0 * b.right_sign_fraction);
        }
      PlotOptions po = Opt(options, "right sign: " + e.name, "true heading (deg)", "right sign (% of frames)");
      po.y_min = 0.0;
      po.y_max = 105.0;
      WritePlotPng(staged.Path() / ("sign_" + FileSafe(e.name) + ".png"), {pct}, po);
    }
  }
  report["heading"] = heading;

  // Distance to the end.
  Json distance = Json::object();
  for (const Estimator& e : dist_est) {
    std::vector<Sample> s;
    for (const CorridorRun& r : runs)
      for (const CorridorFrame& f : r.frames)
        if (f.gt.dist_end_m && f.moving_forward) s.push_back({*f.gt.dist_end_m, e.get(f)});
    if (s.empty()) continue;
    const ErrorSummary sum = Summarize(s);
    const auto bins = BinByTruth(s, options.dist_bin_m, 0.0);
    Json j = SummaryJson(sum, "m");
    Json ranges = Json::array();
    for (const auto& [lo, hi] : options.dist_ranges) {
      Json rj = SummaryJson(SummarizeRange(s, lo, hi), "m");
      rj["min_m"] = lo;
      rj["max_m"] = hi;
      ranges.push_back(rj);
    }
    j["ranges"] = ranges;
    j["bins"] = BinsJson(bins, false);
    distance[e.name] = j;
    if (options.plots) {
      WritePlotPng(staged.Path() / ("distance_" + FileSafe(e.name) + ".png"), MeanBandSeries(bins),
                   Opt(options, "distance to end: " + e.name + fmt::format(" (RMSE {:.2f} m)", sum.rmse),
                       "true distance (m)", "estimated distance (m)"));
    }
  }
  report["distance"] = distance;
  report["distance_frames_note"] =
      "distance metrics count frames where odometry shows the robot driving forward (turning in place is left out)";

  // Rapid perception (Fig. 13) and the heading accuracy it costs.
  {
    std::vector<double> changes;
    std::size_t frames = 0, processed = 0;
    Json per_seq = Json::array();
    std::vector<Sample> all_frames, processed_gated, processed_ungated, held;
    std::vector<PlotSeries> bars;
    for (const CorridorRun& r : runs) {
      std::vector<bool> flags;
      std::optional<double> last;
      for (const CorridorFrame& f : r.frames) {
        ++frames;
        flags.push_back(f.gated_processed);
        if (f.gated_processed) ++processed;
        if (f.gate_change) changes.push_back(*f.gate_change);
        if (f.gated_processed && f.gated_heading_deg) last = f.gated_heading_deg;
        if (!f.gt.heading_deg) continue;
        all_frames.push_back({*f.gt.heading_deg, f.fused_heading_deg});
        held.push_back({*f.gt.heading_deg, last});
        if (f.gated_processed) {
          processed_gated.push_back({*f.gt.heading_deg, f.gated_heading_deg});
          processed_ungated.push_back({*f.gt.heading_deg, f.fused_heading_deg});
        }
      }
      const auto blocks = CountPerBlock(flags, options.gate_block);
      const std::size_t n_proc = static_cast<std::size_t>(std::count(flags.begin(), flags.end(), true));
      per_seq.push_back(Json{{"name", r.name},
                             {"frames", flags.size()},
                             {"processed", n_proc},
                             {"fraction_processed", flags.empty() ? 0.0 : double(n_proc) / double(flags.size())},
                             {"processed_per_block", blocks}});
      PlotSeries b = NamedSeries(r.name, PlotStyle::kLineAndMarkers);
      for (std::size_t k = 0; k < blocks.size(); ++k) {
        b.x.push_back(static_cast<double>(k * options.gate_block));
        b.y.push_back(static_cast<double>(blocks[k]));
      }
      bars.push_back(b);
    }
    const Histogram h = MakeHistogram(changes, 0.0, options.entropy_hist_max, options.entropy_hist_bins);
    Json rp;
    rp["frames"] = frames;
    rp["processed"] = processed;
    rp["fraction_processed"] = frames ? double(processed) / double(frames) : 0.0;
    rp["fraction_skipped"] = frames ? 1.0 - double(processed) / double(frames) : 0.0;
    rp["block"] = options.gate_block;
    rp["entropy_change_histogram"] =
        Json{{"lo", h.lo}, {"hi", h.hi}, {"counts", h.counts}, {"overflow", h.overflow}};
    rp["sequences"] = per_seq;
    if (!all_frames.empty()) {
      rp["heading_rmse_every_frame_deg"] = Summarize(all_frames).rmse;
      rp["heading_rmse_processed_frames_gated_deg"] = Summarize(processed_gated).rmse;
      rp["heading_rmse_processed_frames_ungated_deg"] = Summarize(processed_ungated).rmse;
      rp["heading_rmse_held_between_processed_deg"] = Summarize(held).rmse;
      rp["heading_coverage_held"] = Summarize(held).coverage;
    }
    report["rapid_perception"] = rp;
    if (options.plots && frames > 0) {
      PlotSeries hs = NamedSeries("frames", PlotStyle::kLineAndMarkers);
      const double w = (h.hi - h.lo) / static_cast<double>(h.counts.size());
      for (std::size_t k = 0; k < h.counts.size(); ++k) {
        hs.x.push_back(h.lo + (static_cast<double>(k) + 0.5) * w);
        hs.y.push_back(static_cast<double>(h.counts[k]));
      }
      WritePlotPng(staged.Path() / "rapid_entropy_change.png", {hs},
                   Opt(options, "normalised entropy change between frames", "|H(t)-H(t-1)| / H(1)", "frames"));
      PlotOptions po = Opt(options,
                           fmt::format("frames fully processed per {} ({:.0f}% overall)", options.gate_block,
                                       100.0 * double(processed) / double(frames)),
                           "frame index", "processed frames");
      po.y_min = 0.0;
      po.y_max = static_cast<double>(options.gate_block) * 1.05;
      WritePlotPng(staged.Path() / "rapid_processed.png", bars, po);
    }
  }

  const std::string text = report.dump(2);
  {
    std::ofstream os(staged.Path() / "report.json");
    os << text << "\n";
    if (!os) throw Error((out_dir / "report.json").string() + ": cannot write");
  }
  staged.Commit();
  return text;
}

}  // namespace squint::eval
