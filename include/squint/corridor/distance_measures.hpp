// The three distance-to-end cues of paper §4.2, from two consecutive glances: time to contact
// by the direct method (eq. 3), Jeffrey divergence (eq. 4) and entropy change (§4.2.3).
#pragma once

#include <memory>
#include <optional>

#include "squint/corridor/measure.hpp"
#include "squint/corridor/options.hpp"
#include "squint/corridor/prepared_glance.hpp"

namespace squint::corridor {

// Horn, Fang & Masaki's direct time to contact (eq. 3), in frame intervals, for a camera
// translating along its optical axis towards a plane: τ = -Σ G² / Σ G·I_t with
// G = x·I_x + y·I_y about the expansion centre (cx, cy) of the glance. I_x, I_y are the mean of
// both frames' central differences; I_t = I2 - I1. With gain_compensation, τ = −1/c from the
// joint least-squares fit I_t ≈ c·G + e·M + f (M the mean brightness of the two frames), which
// absorbs a change of camera gain (e) and offset (f) between the frames. None when Σ G² == 0 or
// the fit leaves c zero or undetermined.
std::optional<double> TimeToContactFrames(const Glance& previous, const Glance& current, double cx,
                                          double cy, bool gain_compensation = false);

class DistanceMeasure {
 public:
  virtual ~DistanceMeasure() = default;
  virtual DistanceCue Cue() const = 0;
  // `travelled_m`: distance travelled between the two glances (only g1 uses it). Fills
  // out.raw, out.dist_m (or none) and out.reason. Never allocates.
  virtual void Measure(const PreparedGlance& previous, const PreparedGlance& current,
                       std::optional<double> travelled_m, DistanceMeasureResult& out) const = 0;
  // The cue's distance model applied to a model input (out.model_input's units), range-checked
  // against min_m/max_m and the cue's validity window; none outside them.
  virtual std::optional<double> Distance(double model_input) const = 0;
};

// g1 = τ · travelled per frame (§4.2.1), then the options' scale and bias. The direct method's
// τ·s refers to the middle of the baseline s, so the model input is τ·s − s/2 (the distance
// from the current frame).
class TimeToContactDistance final : public DistanceMeasure {
 public:
  // (cx, cy): the expansion centre in glance pixels.
  TimeToContactDistance(const DistanceOptions& options, double cx, double cy)
      : options_(options), cx_(cx), cy_(cy) {}
  DistanceCue Cue() const override { return DistanceCue::kTimeToContact; }
  // Consecutive frames (a one-frame baseline).
  void Measure(const PreparedGlance& previous, const PreparedGlance& current,
               std::optional<double> travelled_m, DistanceMeasureResult& out) const override;
  // Any baseline: `earlier` is `baseline_frames` frames before `current`, `travelled_m` the
  // distance driven between them.
  void MeasureBaseline(const Glance& earlier, const Glance& current, int baseline_frames,
                       std::optional<double> travelled_m, DistanceMeasureResult& out) const;
  std::optional<double> Distance(double model_input) const override;

 private:
  DistanceOptions options_;
  double cx_;
  double cy_;
};

// g2 = β2 − α2 · J (§4.2.2).
class JeffreyDistance final : public DistanceMeasure {
 public:
  explicit JeffreyDistance(const DistanceOptions& options) : options_(options) {}
  DistanceCue Cue() const override { return DistanceCue::kJeffrey; }
  void Measure(const PreparedGlance& previous, const PreparedGlance& current,
               std::optional<double> travelled_m, DistanceMeasureResult& out) const override;
  std::optional<double> Distance(double model_input) const override;

 private:
  DistanceOptions options_;
};

// g3 = α3 / (H(t-1) − H(t)) (§4.2.3).
class EntropyDistance final : public DistanceMeasure {
 public:
  explicit EntropyDistance(const DistanceOptions& options) : options_(options) {}
  DistanceCue Cue() const override { return DistanceCue::kEntropy; }
  void Measure(const PreparedGlance& previous, const PreparedGlance& current,
               std::optional<double> travelled_m, DistanceMeasureResult& out) const override;
  std::optional<double> Distance(double model_input) const override;

 private:
  DistanceOptions options_;
};

}  // namespace squint::corridor
