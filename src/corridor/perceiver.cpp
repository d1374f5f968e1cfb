// Corridor perception pipeline: glance, rapid-perception gate (§5.3), the eight measures and
// their fusion (weighted consensus for heading, weighted mean for distance), and the optional
// heading filter over time.
#include "squint/corridor/perceiver.hpp"

#include <algorithm>
#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/core/median.hpp"

namespace squint::corridor {
namespace {

// Odometry travel per frame below this (metres) means the robot stands or turns in place: the
// distance cues' history restarts.
constexpr double kMinDrivingTravelM = 1e-3;

// The heading filter's options in the Kalman filter's terms (its distance half stays unused).
CorridorKalmanOptions HeadingFilterKalmanOptions(const HeadingFilterOptions& f) {
  CorridorKalmanOptions k;
  k.heading_process_std_deg = f.process_std_deg;
  k.heading_process_std_deg_per_sqrt_s = f.process_std_deg_per_sqrt_s;
  k.heading_odom_noise_fraction = f.odom_noise_fraction;
  k.no_odom_heading_std_deg = f.no_odom_std_deg;
  k.gate_chi2 = f.gate_chi2;
  k.reinit_after_rejections = f.reinit_after_rejections;
  return k;
}

}  // namespace

bool RapidPerceptionGate::Update(double entropy) {
  last_change_.reset();
  const bool first = !reference_.has_value();
  if (first) reference_ = entropy;
  bool process = true;
  if (!first && previous_) {
    if (*reference_ > 0.0) {
      last_change_ = std::abs(entropy - *previous_) / *reference_;
      process = !options_.enabled || *last_change_ >= options_.threshold ||
                (options_.max_skipped_frames > 0 && skipped_ >= options_.max_skipped_frames);
    }
  }
  skipped_ = process ? 0 : skipped_ + 1;
  if (process || !options_.compare_with_last_processed) previous_ = entropy;
  return process;
}

void RapidPerceptionGate::Reset() {
  reference_.reset();
  skipped_ = 0;
}

Perceiver::Perceiver(const Options& options, std::optional<CameraModel> camera)
    : options_(options), gate_(options.gate) {
  const std::string problem = options_.Validate();
  if (!problem.empty()) throw Error("corridor options: " + problem);
  heading_filter_ = CorridorKalman(HeadingFilterKalmanOptions(options_.heading.filter));
  std::optional<double> horizon_row;
  if (camera && camera->HasIntrinsics() && camera->width > 0 && camera->height > 0) {
    glance_camera_ = camera->Scaled(kGlanceWidth, kGlanceHeight);
    has_intrinsics_ = true;
    horizon_row = glance_camera_.HorizonRow();
  } else {
    glance_camera_.width = kGlanceWidth;
    glance_camera_.height = kGlanceHeight;
    glance_camera_.cx = (kGlanceWidth - 1) / 2.0;
    glance_camera_.cy = (kGlanceHeight - 1) / 2.0;
  }
  for (int i = 0; i < kHeadingCueCount; ++i)
    heading_measures_[i] = MakeHeadingMeasure(static_cast<HeadingCue>(i), options_.heading, horizon_row);
  // Time to contact expands about the point the robot drives towards: on the horizon when the
  // camera's pitch is known.
  const double ttc_cy =
      (options_.distance.ttc_centre_at_horizon && horizon_row) ? *horizon_row : glance_camera_.cy;
  distance_measures_[0] = std::make_unique<TimeToContactDistance>(
      options_.distance, glance_camera_.cx, ttc_cy, has_intrinsics_ ? glance_camera_.fx : 0.0,
      has_intrinsics_ ? glance_camera_.height_m : 0.0);
  // Time to contact's own image (ttc_glance_scale) and the glance history, allocated once.
  if (options_.distance.ttc_glance_scale != 1.0) {
    ttc_width_ = static_cast<int>(std::lround(kGlanceWidth * options_.distance.ttc_glance_scale));
    ttc_height_ = static_cast<int>(std::lround(kGlanceHeight * options_.distance.ttc_glance_scale));
    const std::size_t n = static_cast<std::size_t>(ttc_width_ * ttc_height_);
    ttc_image_.assign(n, 0);
    smoothed_ttc_image_.assign(n, 0);
    fine_history_px_.assign(n * kHistorySize, 0);
  }
  if (options_.distance.floor_contact.enabled && camera && FloorContact::CameraProblem(*camera).empty())
    floor_contact_ = std::make_unique<FloorContact>(*camera, options_.distance.floor_contact);
  if (floor_contact_ && options_.distance.floor_contact.motion_window_m > 0.0)
    floor_motion_ = std::make_unique<FloorMotionCheck>(*camera, options_.distance.floor_contact);
  distance_measures_[1] = std::make_unique<JeffreyDistance>(options_.distance);
  distance_measures_[2] = std::make_unique<EntropyDistance>(options_.distance);
}

Perceiver::~Perceiver() = default;

void Perceiver::Reset() {
  gate_.Reset();
  gate_ = RapidPerceptionGate(options_.gate);
  has_previous_ = false;
  ResetDistanceHistory();
  heading_filter_.Reset();
}

void Perceiver::ResetDistanceHistory() {
  history_count_ = 0;
  history_head_ = 0;
  travel_m_ = 0.0;
  for (CueWindow& w : cue_windows_) w.count = w.head = 0;
  floor_window_.count = floor_window_.head = 0;
  if (floor_motion_) floor_motion_->Reset();
  short_window_.count = short_window_.head = 0;
  last_ttc_input_m_.reset();
}

void Perceiver::ResetGateReference() { gate_.Reset(); }

void Perceiver::ResetHeadingFilter() { heading_filter_.Reset(); }

void Perceiver::ResetHeadingFilter(double prior_deg, double std_deg) {
  heading_filter_.Reset();
  heading_filter_.SetHeading(prior_deg, std_deg);
}

double Perceiver::ColumnToHeadingDeg(double column_px) const {
  if (has_intrinsics_) return RadToDeg(glance_camera_.HeadingFromColumn(column_px));
  return options_.heading.fallback_deg_per_column * (column_px - glance_camera_.cx);
}

double Perceiver::HeadingDegToColumn(double heading_deg) const {
  if (has_intrinsics_) return glance_camera_.cx + glance_camera_.fx * std::tan(DegToRad(heading_deg));
  return glance_camera_.cx + heading_deg / options_.heading.fallback_deg_per_column;
}

namespace {

// Whether a cue's score curve carries evidence: not for a frame it could not score at all.
bool CurveUsable(Reason reason) {
  switch (reason) {
    case Reason::kNone:
    case Reason::kFlatCurve:
    case Reason::kPeakAtBorder:
    case Reason::kOutOfRange:
    case Reason::kDegenerateGeometry:
      return true;
    default:
      return false;
  }
}

}  // namespace

void Perceiver::FuseHeadingCurves(PerceptionResult& result) const {
  // Sum over cues of weight × (curve − median) / (max − min), on the glance columns x, whose
  // (uncalibrated) headings ColumnToHeadingDeg(x) are the fused heading's grid; a calibrated cue's
  // curve is read at the column whose calibrated heading is that grid heading.
  std::array<double, kGlanceWidth> sum{};
  bool any = false;
  for (int i = 0; i < kHeadingCueCount; ++i) {
    const HeadingMeasureResult& h = result.heading[i];
    const HeadingCueOptions& cue = options_.heading.cues[i];
    if (!cue.enabled || cue.weight <= 0.0 || !CurveUsable(h.reason)) continue;
    std::array<float, kGlanceWidth> sorted = h.curve;
    std::nth_element(sorted.begin(), sorted.begin() + kGlanceWidth / 2, sorted.end());
    const double median = sorted[kGlanceWidth / 2];
    const auto [lo_it, hi_it] = std::minmax_element(h.curve.begin(), h.curve.end());
    const double lo = *lo_it, hi = *hi_it;
    if (!(hi > lo) || !std::isfinite(hi) || !std::isfinite(lo)) continue;
    const double k = cue.weight / (hi - lo);
    const bool identity = cue.scale == 1.0 && cue.bias_deg == 0.0;
    for (int x = 0; x < kGlanceWidth; ++x) {
      double value = h.curve[x];
      if (!identity) {
        const double col = HeadingDegToColumn((ColumnToHeadingDeg(x) - cue.bias_deg) / cue.scale);
        const double c = std::isfinite(col) ? std::clamp(col, 0.0, kGlanceWidth - 1.0) : 0.0;
        const int c0 = std::min(static_cast<int>(c), kGlanceWidth - 2);
        const double f = c - c0;
        value = (1.0 - f) * h.curve[c0] + f * h.curve[c0 + 1];
      }
      sum[x] += k * (value - median);
    }
    any = true;
  }
  if (!any) return;
  // The maximum over the columns inside the border (parabolic sub-column refinement).
  int best = 1;
  for (int x = 2; x < kGlanceWidth - 1; ++x)
    if (sum[x] > sum[best]) best = x;
  double column = best;
  const double a = sum[best - 1], b = sum[best], c = sum[best + 1];
  const double denom = a - 2.0 * b + c;
  if (denom < 0.0) column += std::clamp(0.5 * (a - c) / denom, -0.5, 0.5);
  const double deg = ColumnToHeadingDeg(column);
  if (!std::isfinite(deg) || std::abs(deg) > options_.heading.max_abs_heading_deg) return;
  result.heading_deg = deg;
  for (HeadingMeasureResult& h : result.heading)
    h.fused = h.heading_deg && std::abs(*h.heading_deg - deg) <= options_.heading.agreement_deg;
}

void Perceiver::PredictHeading(std::optional<double> travelled_m, std::optional<double> turned_deg, double dt_s) {
  if (!options_.heading.filter.enabled) return;
  std::optional<Pose2> motion;
  if (turned_deg && std::isfinite(*turned_deg)) motion = Pose2{travelled_m.value_or(0.0), 0.0, DegToRad(*turned_deg)};
  heading_filter_.Predict(motion, dt_s);
}

void Perceiver::FilterHeading(PerceptionResult& result) {
  result.heading_instant_deg = result.heading_deg;
  if (!options_.heading.filter.enabled) return;
  // Each cue's calibrated estimate is one measurement with the cue's σ, in cue order.
  for (int i = 0; i < kHeadingCueCount; ++i) {
    const HeadingMeasureResult& h = result.heading[i];
    if (h.heading_deg) heading_filter_.UpdateHeading(*h.heading_deg, options_.heading.cues[i].std_deg);
  }
  result.heading_deg.reset();
  const std::optional<double> state = heading_filter_.HeadingDeg();
  if (state && std::abs(*state) <= options_.heading.max_abs_heading_deg) result.heading_deg = state;
}

PerceptionResult Perceiver::Process(const PixelView& frame, std::optional<double> travelled_m, double dt_s,
                                    std::optional<double> turned_deg) {
  Glance glance;
  MakeGlance(frame, options_.sampling, glance);
  const DistanceOptions& d = options_.distance;
  constexpr int kTtc = static_cast<int>(DistanceCue::kTimeToContact);
  const bool ttc_on = d.enabled[kTtc] && d.weights[kTtc] > 0.0;
  const std::uint8_t* fine = nullptr;
  if (ttc_on && !ttc_image_.empty() && frame.width >= ttc_width_ && frame.height >= ttc_height_) {
    MakeAreaImage(frame, ttc_width_, ttc_height_, ttc_image_.data());
    fine = ttc_image_.data();
  }
  if (d.ttc_area_glance && options_.sampling != GlanceSampling::kArea && ttc_on) {
    MakeGlance(frame, GlanceSampling::kArea, area_glance_);
    return ProcessImpl(glance, area_glance_, fine, &frame, travelled_m, dt_s, turned_deg);
  }
  return ProcessImpl(glance, glance, fine, &frame, travelled_m, dt_s, turned_deg);
}

PerceptionResult Perceiver::ProcessGlance(const Glance& glance, std::optional<double> travelled_m, double dt_s,
                                          std::optional<double> turned_deg) {
  return ProcessImpl(glance, glance, nullptr, nullptr, travelled_m, dt_s, turned_deg);
}

void Perceiver::PushHistory(const Glance& g, const std::uint8_t* fine) {
  history_head_ = (history_head_ + 1) % kHistorySize;
  history_[history_head_] = g;
  history_fine_[history_head_] = fine != nullptr;
  if (fine) {
    const TtcImage slot = FineHistoryAt(history_head_);
    std::copy(fine, fine + static_cast<std::size_t>(slot.width) * static_cast<std::size_t>(slot.height),
              fine_history_px_.begin() + (slot.data - fine_history_px_.data()));
  }
  history_travel_m_[history_head_] = travel_m_;
  history_count_ = std::min(history_count_ + 1, kHistorySize);
}

PerceptionResult Perceiver::ProcessImpl(const Glance& glance, const Glance& ttc_glance_in, const std::uint8_t* fine_in,
                                        const PixelView* frame,
                                        std::optional<double> travelled_m, double dt_s,
                                        std::optional<double> turned_deg) {
  PerceptionResult result;
  // Time to contact compares binomially smoothed glances (DistanceOptions::ttc_smooth).
  if (options_.distance.ttc_smooth) SmoothGlance(ttc_glance_in, smoothed_ttc_glance_);
  const Glance& ttc_glance = options_.distance.ttc_smooth ? smoothed_ttc_glance_ : ttc_glance_in;
  const std::uint8_t* fine = fine_in;
  if (fine_in && options_.distance.ttc_smooth) {
    SmoothTtcImage(TtcImage{fine_in, ttc_width_, ttc_height_}, smoothed_ttc_image_.data());
    fine = smoothed_ttc_image_.data();
  }
  for (int i = 0; i < kHeadingCueCount; ++i) result.heading[i].cue = static_cast<HeadingCue>(i);
  for (int i = 0; i < kDistanceCueCount; ++i) result.distance[i].cue = static_cast<DistanceCue>(i);

  const int next = has_previous_ ? 1 - current_ : current_;
  PreparedGlance& cur = prepared_[next];
  ComputeHistogramAndEntropy(glance, options_.distance.image_bits, cur);
  result.entropy = cur.entropy;
  const bool process = gate_.Update(cur.entropy);
  result.gate_change = gate_.LastChange();
  const bool had_previous = has_previous_;
  const PreparedGlance& prev = prepared_[current_];
  // Distance history (every frame, processed or not): the travel since the previous frame, and
  // a restart when the robot stands or turns in place (odometry reports no forward travel).
  std::optional<double> travelled = travelled_m;
  if (!travelled && options_.distance.speed_mps > 0.0 && dt_s > 0.0) travelled = options_.distance.speed_mps * dt_s;
  if (travelled && *travelled < kMinDrivingTravelM) ResetDistanceHistory();
  if (travelled) travel_m_ += std::max(0.0, *travelled);
  // The heading filter follows the odometry on every frame, processed or skipped.
  if (had_previous) PredictHeading(travelled_m, turned_deg, dt_s);
  if (!process) {
    PushHistory(ttc_glance, fine);
    // Skipped frames still become the previous frame of the next one, so consecutive-frame
    // measures always compare neighbouring frames.
    current_ = next;
    has_previous_ = true;
    return result;
  }
  result.processed = true;
  PrepareMeasures(options_.heading.column_bits, options_.heading.vanishing_bits, cur);

  for (int i = 0; i < kHeadingCueCount; ++i) {
    HeadingMeasureResult& h = result.heading[i];
    const HeadingCueOptions& cue = options_.heading.cues[i];
    if (!cue.enabled || cue.weight <= 0.0) {
      h.reason = Reason::kDisabled;
      continue;
    }
    heading_measures_[i]->Measure(cur, h);
    if (!h.column_px) continue;
    const double deg = cue.scale * ColumnToHeadingDeg(*h.column_px) + cue.bias_deg;
    if (!std::isfinite(deg) || std::abs(deg) > options_.heading.max_abs_heading_deg) {
      h.reason = Reason::kOutOfRange;
      continue;
    }
    h.heading_deg = deg;
  }

  if (had_previous) {
    MeasureDistances(prev, cur, ttc_glance, fine, travelled, result);
  } else {
    for (DistanceMeasureResult& d : result.distance) d.reason = Reason::kNoPreviousFrame;
  }
  PushHistory(ttc_glance, fine);
  if (floor_contact_) {
    // Measured on processed frames only (the gate's skipped frames return above).
    if (frame) result.dist_floor_raw_m = floor_contact_->Measure(*frame);
    result.dist_floor_m = PushAndMedian(floor_window_, result.dist_floor_raw_m, true);
    if (floor_motion_) result.dist_floor_moves_as_floor = floor_motion_->Update(travel_m_, result.dist_floor_raw_m);
  }
  Fuse(result);
  FilterHeading(result);
  current_ = next;
  has_previous_ = true;
  return result;
}

std::optional<double> Perceiver::PushAndMedian(CueWindow& w, std::optional<double> input, bool travel_compensated) const {
  // The ring holds the newest median_frames inputs (newest at w.head); the median takes the
  // count written since the last reset, newest first.
  const int kCap = options_.distance.median_frames;
  if (input) {
    w.head = (w.head + 1) % kCap;
    w.input[w.head] = *input;
    w.travel_m[w.head] = travel_m_;
    w.count = std::min(w.count + 1, kCap);
  }
  if (w.count == 0) return std::nullopt;
  std::array<double, kMaxDistanceMedianFrames> v{};
  int n = 0;
  for (int k = 0; k < w.count; ++k) {
    const int idx = ((w.head - k) % kCap + kCap) % kCap;
    v[n++] = travel_compensated ? w.input[idx] - (travel_m_ - w.travel_m[idx]) : w.input[idx];
  }
  return MedianInPlace(std::span<double>(v.data(), static_cast<std::size_t>(n)));
}

void Perceiver::MeasureDistances(const PreparedGlance& prev, const PreparedGlance& cur, const Glance& ttc_glance,
                                 const std::uint8_t* fine, std::optional<double> travelled,
                                 PerceptionResult& result) {
  const DistanceOptions& o = options_.distance;
  const int n_hist = kHistorySize;
  for (int i = 0; i < kDistanceCueCount; ++i) {
    DistanceMeasureResult& d = result.distance[i];
    if (!o.enabled[i] || o.weights[i] <= 0.0) {
      d.reason = Reason::kDisabled;
      continue;
    }
    const bool ttc = static_cast<DistanceCue>(i) == DistanceCue::kTimeToContact;
    if (ttc && history_count_ > 0 && o.ttc_scale_search) {
      // The longest baseline (history_[head - k + 1] is k frames back) whose travel stays within
      // ttc_baseline_fraction of the last filtered distance, or within ttc_initial_baseline_m
      // before there is one.
      const auto& measure = static_cast<const TimeToContactDistance&>(*distance_measures_[i]);
      const double max_travel =
          last_ttc_input_m_ ? o.ttc_baseline_fraction * *last_ttc_input_m_ : o.ttc_initial_baseline_m;
      const int max_k = std::min(o.ttc_max_baseline_frames, history_count_);
      int k = 1;
      for (int kk = max_k; kk > 1; --kk) {
        const int idx = ((history_head_ - kk + 1) % n_hist + n_hist) % n_hist;
        if (travel_m_ - history_travel_m_[idx] <= max_travel) {
          k = kk;
          break;
        }
      }
      const int idx = ((history_head_ - k + 1) % n_hist + n_hist) % n_hist;
      std::optional<double> s;
      if (travelled) s = travel_m_ - history_travel_m_[idx];
      // Warming up: until the history spans ttc_warmup_m of driving (or is full), no reading. The first
      // one-frame baselines' expansion is within the search's noise and reads as a short
      // distance, which then kept the baseline short (a trap: drive-3-00l read 1–2 m for its
      // first 2 m of driving, 14 m from the end).
      const double whole =
          travel_m_ - history_travel_m_[((history_head_ - history_count_ + 1) % n_hist + n_hist) % n_hist];
      if (travelled && whole < o.ttc_warmup_m - 1e-9 && history_count_ < n_hist) {
        d.baseline_frames = k;
        d.reason = history_[idx].pixels == ttc_glance.pixels ? Reason::kIdenticalFrames : Reason::kNoTravel;
      } else if (fine && history_fine_[idx]) {
        // Time to contact's finer image (ttc_glance_scale).
        measure.MeasureScale(FineHistoryAt(idx), TtcImage{fine, ttc_width_, ttc_height_}, k, s, last_ttc_input_m_,
                             d);
      } else {
        measure.MeasureScale(history_[idx], ttc_glance, k, s, last_ttc_input_m_, d);
      }
    } else if (ttc && history_count_ > 0) {
      const auto& measure = static_cast<const TimeToContactDistance&>(*distance_measures_[i]);
      // The one-frame time to contact, median-filtered on its own: a reference for the
      // baseline that cannot run away (a too-long baseline decorrelates the glances near the
      // end and returns a large τ, which would lengthen the baseline further).
      std::optional<double> s1;
      if (travelled) s1 = travel_m_ - history_travel_m_[history_head_];
      measure.MeasureBaseline(history_[history_head_], ttc_glance, 1, s1, d);
      std::optional<double> short_input = d.model_input;
      if (!short_input && d.raw && *d.raw <= 0.0 && travelled) short_input = HUGE_VAL;
      const std::optional<double> short_median = PushAndMedian(short_window_, short_input, false);
      std::optional<double> reference = last_ttc_input_m_;
      if (short_median && (!reference || *short_median < *reference)) reference = short_median;
      // The longest baseline (history_[head - k + 1] is k frames back: the current glance is not
      // in the history yet) whose travel stays within the fraction of the reference distance;
      // with no reference yet, one frame.
      const int max_k = std::min(o.ttc_max_baseline_frames, history_count_);
      int k = 1;
      for (int kk = max_k; kk > 1 && reference; --kk) {
        const int idx = ((history_head_ - kk + 1) % n_hist + n_hist) % n_hist;
        if (travel_m_ - history_travel_m_[idx] <= o.ttc_baseline_fraction * *reference) {
          k = kk;
          break;
        }
      }
      if (k > 1) {
        const int idx = ((history_head_ - k + 1) % n_hist + n_hist) % n_hist;
        std::optional<double> s;
        if (travelled) s = travel_m_ - history_travel_m_[idx];
        measure.MeasureBaseline(history_[idx], ttc_glance, k, s, d);
      }
    } else {
      distance_measures_[i]->Measure(prev, cur, travelled, d);
    }
    // Temporal median of the model input. Time to contact: a contracting or unchanging image
    // (τ ≤ 0: no measurable expansion) counts as "very far", and earlier values are moved to
    // this frame by the travel since.
    std::optional<double> input = d.model_input;
    if (ttc && !input && d.raw && *d.raw <= 0.0 && travelled) input = HUGE_VAL;
    const std::optional<double> median = PushAndMedian(cue_windows_[i], input, ttc);
    if (!median) continue;
    const double med = *median;
    if (!std::isfinite(med)) {  // mostly "very far": no estimate, the longest baseline next
      if (ttc) last_ttc_input_m_ = o.max_m;
      continue;
    }
    d.filtered_input = med;
    if (ttc) last_ttc_input_m_ = med;
    d.dist_m = distance_measures_[i]->Distance(med);
    d.reason = d.dist_m ? Reason::kNone : Reason::kOutOfRange;
  }
}

void Perceiver::Fuse(PerceptionResult& result) const {
  // Heading: by default the sum of the cues' curves (HeadingOptions::fuse_curves); else the cue estimate with the most weight within agreement_deg of it, then the weighted
  // mean of those within agreement_deg (a consensus), so that one cue peaking on a lit wall
  // cannot drag the answer. A consensus needs min_consensus_cues cues; when no group that large
  // exists the cues disagree and no single one is trusted: the answer is the weighted mean of
  // all of them (a compromise that is never further from the truth than the worst cue).
  struct Candidate {
    double deg;
    double weight;
    int cue;
  };
  std::array<Candidate, kHeadingCueCount> c{};
  int n = 0;
  double total = 0.0;
  for (int i = 0; i < kHeadingCueCount; ++i) {
    const HeadingMeasureResult& h = result.heading[i];
    if (!h.heading_deg) continue;
    const double w = options_.heading.cues[i].weight;
    c[n++] = {*h.heading_deg, w, i};
    total += w;
  }
  if (options_.heading.fuse_curves) {
    FuseHeadingCurves(result);
  } else if (n > 0 && total > 0.0) {
    const double tol = options_.heading.agreement_deg;
    const int min_cues = std::min(options_.heading.min_consensus_cues, n);
    // The candidate with the most weight within tol of it and at least min_cues members
    // (ties: the first); -1 when there is none.
    int centre = -1;
    double best_support = -1.0;
    for (int k = 0; k < n; ++k) {
      double support = 0.0;
      int members = 0;
      for (int m = 0; m < n; ++m)
        if (std::abs(c[m].deg - c[k].deg) <= tol) support += c[m].weight, ++members;
      if (members >= min_cues && support > best_support) best_support = support, centre = k;
    }
    double sw = 0.0, swd = 0.0;
    for (int k = 0; k < n; ++k) {
      if (centre >= 0 && std::abs(c[k].deg - c[centre].deg) > tol) continue;
      sw += c[k].weight;
      swd += c[k].weight * c[k].deg;
      result.heading[c[k].cue].fused = true;
    }
    if (sw > 0.0) result.heading_deg = swd / sw;
  }
  // Distance: weighted mean of the available (median-filtered) estimates (paper §5.3), each
  // weight falling with the cue's error growth: inverse variance when σ grows with distance.
  // Cues with fuse off are reported, not fused; with fused_max_std_m a fused estimate whose
  // σ = 1 / sqrt(Σ w) exceeds it is not given.
  double sw = 0.0, swd = 0.0;
  for (int i = 0; i < kDistanceCueCount; ++i) {
    DistanceMeasureResult& d = result.distance[i];
    if (!d.dist_m || !options_.distance.fuse[i]) continue;
    const double w = options_.distance.FusionWeight(i, *d.dist_m);
    sw += w;
    swd += w * *d.dist_m;
    d.fused = true;
  }
  const double max_std = options_.distance.fused_max_std_m;
  if (sw > 0.0 && max_std > 0.0 && 1.0 / std::sqrt(sw) > max_std) {
    for (DistanceMeasureResult& d : result.distance) d.fused = false;
  } else if (sw > 0.0) {
    result.dist_end_m = swd / sw;
  }
  // The end wall's floor contact, where it has a reading, is the answer (FloorContactOptions)
  // when the cues' fused distance agrees with it or its readings move as a floor point does.
  const FloorContactOptions& fc = options_.distance.floor_contact;
  if (fc.overrides_fusion && result.dist_floor_m &&
      (fc.agreement_ratio <= 0.0 || result.dist_floor_moves_as_floor ||
       (result.dist_end_m && std::abs(*result.dist_end_m - *result.dist_floor_m) <= fc.agreement_ratio * *result.dist_end_m))) {
    result.dist_end_m = *result.dist_floor_m;
    for (DistanceMeasureResult& d : result.distance) d.fused = false;
  }
}

}  // namespace squint::corridor
