// Corridor perception pipeline: glance, rapid-perception gate (§5.3), the eight measures and
// their fusion (weighted consensus for heading, weighted mean for distance).
#include "squint/corridor/perceiver.hpp"

#include <algorithm>
#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::corridor {

bool RapidPerceptionGate::Update(double entropy) {
  last_change_.reset();
  const bool first = !reference_.has_value();
  if (first) reference_ = entropy;
  bool process = true;
  if (!first && previous_) {
    if (*reference_ > 0.0) {
      last_change_ = std::abs(entropy - *previous_) / *reference_;
      process = !options_.enabled || *last_change_ >= options_.threshold;
    }
  }
  previous_ = entropy;
  return process;
}

void RapidPerceptionGate::Reset() {
  reference_.reset();
}

Perceiver::Perceiver(const Options& options, std::optional<CameraModel> camera)
    : options_(options), gate_(options.gate) {
  const std::string problem = options_.Validate();
  if (!problem.empty()) throw Error("corridor options: " + problem);
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
  distance_measures_[0] =
      std::make_unique<TimeToContactDistance>(options_.distance, glance_camera_.cx, glance_camera_.cy);
  distance_measures_[1] = std::make_unique<JeffreyDistance>(options_.distance);
  distance_measures_[2] = std::make_unique<EntropyDistance>(options_.distance);
}

Perceiver::~Perceiver() = default;

void Perceiver::Reset() {
  gate_.Reset();
  gate_ = RapidPerceptionGate(options_.gate);
  has_previous_ = false;
}

void Perceiver::ResetGateReference() { gate_.Reset(); }

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

PerceptionResult Perceiver::Process(const PixelView& frame, std::optional<double> travelled_m, double dt_s) {
  Glance glance;
  MakeGlance(frame, options_.sampling, glance);
  return ProcessGlance(glance, travelled_m, dt_s);
}

PerceptionResult Perceiver::ProcessGlance(const Glance& glance, std::optional<double> travelled_m, double dt_s) {
  PerceptionResult result;
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
  if (!process) {
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

  std::optional<double> travelled = travelled_m;
  if (!travelled && options_.distance.speed_mps > 0.0 && dt_s > 0.0) travelled = options_.distance.speed_mps * dt_s;
  for (int i = 0; i < kDistanceCueCount; ++i) {
    DistanceMeasureResult& d = result.distance[i];
    if (!options_.distance.enabled[i] || options_.distance.weights[i] <= 0.0) {
      d.reason = Reason::kDisabled;
      continue;
    }
    if (!had_previous) {
      d.reason = Reason::kNoPreviousFrame;
      continue;
    }
    distance_measures_[i]->Measure(prev, cur, travelled, d);
  }
  Fuse(result);
  current_ = next;
  has_previous_ = true;
  return result;
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
  // Distance: weighted mean of the available estimates (paper §5.3).
  double sw = 0.0, swd = 0.0;
  for (int i = 0; i < kDistanceCueCount; ++i) {
    DistanceMeasureResult& d = result.distance[i];
    if (!d.dist_m) continue;
    sw += options_.distance.weights[i];
    swd += options_.distance.weights[i] * *d.dist_m;
    d.fused = true;
  }
  if (sw > 0.0) result.dist_end_m = swd / sw;
}

}  // namespace squint::corridor
