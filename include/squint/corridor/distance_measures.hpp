// The three distance-to-end cues of paper §4.2, from two consecutive glances: time to contact
// by the direct method (eq. 3), Jeffrey divergence (eq. 4) and entropy change (§4.2.3).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <optional>

#include "squint/corridor/measure.hpp"
#include "squint/corridor/options.hpp"
#include "squint/corridor/prepared_glance.hpp"

namespace squint::corridor {

// A grey image for time to contact's scale search: the 32×24 glance or, with
// DistanceOptions::ttc_glance_scale, a finer area-averaged image of the frame (at most
// kMaxTtcWidth × kMaxTtcHeight). Rows are contiguous (stride = width). A view: owns no pixels.
inline constexpr int kMaxTtcWidth = 128;
inline constexpr int kMaxTtcHeight = 96;
inline constexpr int kMaxTtcPixels = kMaxTtcWidth * kMaxTtcHeight;
struct TtcImage {
  const std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::uint8_t At(int u, int v) const { return data[v * width + u]; }
};
inline TtcImage TtcView(const Glance& g) { return {g.pixels.data(), kGlanceWidth, kGlanceHeight}; }

// Horn, Fang & Masaki's direct time to contact (eq. 3), in frame intervals, for a camera
// translating along its optical axis towards a plane: τ = -Σ G² / Σ G·I_t with
// G = x·I_x + y·I_y about the expansion centre (cx, cy) of the glance. I_x, I_y are the mean of
// both frames' central differences; I_t = I2 - I1. With gain_compensation, τ = −1/c from the
// joint least-squares fit I_t ≈ c·G + e·M + f (M the mean brightness of the two frames), which
// absorbs a change of camera gain (e) and offset (f) between the frames. None when Σ G² == 0 or
// the fit leaves c zero or undetermined.
std::optional<double> TimeToContactFrames(const Glance& previous, const Glance& current, double cx,
                                          double cy, bool gain_compensation = false);

// The magnification σ ≥ 1 of `current` relative to `earlier` about the expansion centre (cx, cy):
// the σ in [1, max_scale] whose magnified earlier glance, earlier(c + (p − c)/σ) (bilinear),
// best matches `current` by normalised cross-correlation over the current glance's pixels p
// within ±half_width_px columns and ±half_height_px rows of the centre (clipped to the glance).
// NCC makes the match invariant to a gain and offset change between the frames.
// With `initial_scale` (a prediction, e.g. from the last distance estimate and the travel):
// Gauss–Newton on σ from it (the current glance regressed on the magnified earlier one, its
// σ-derivative and 1; 2–5 iterations), accepted when its NCC reaches `accept_ncc`. Without a
// prediction, or when the refined NCC is below accept_ncc: a grid every 0.01 over [1, max_scale]
// (every other row and column of windows over 256 pixels), then Gauss–Newton from its best.
// `ncc` gets the best correlation. None when the window holds fewer than 12 pixels or either
// side is uniform. A best σ at 1 (no measurable expansion) returns exactly 1.
struct ScaleMatch {
  double scale = 1.0;
  double ncc = 0.0;
  double contrast = 0.0;  // standard deviation of the current glance in the window (grey levels)
  bool searched = false;  // the grid ran (no prediction, or its refinement was poor)
};
std::optional<ScaleMatch> ExpansionScale(const TtcImage& earlier, const TtcImage& current, double cx, double cy,
                                         double half_width_px, double half_height_px, double max_scale,
                                         std::optional<double> initial_scale = std::nullopt,
                                         double accept_ncc = 1.0);
inline std::optional<ScaleMatch> ExpansionScale(const Glance& earlier, const Glance& current, double cx, double cy,
                                                double half_width_px, double half_height_px, double max_scale,
                                                std::optional<double> initial_scale = std::nullopt,
                                                double accept_ncc = 1.0) {
  return ExpansionScale(TtcView(earlier), TtcView(current), cx, cy, half_width_px, half_height_px, max_scale,
                        initial_scale, accept_ncc);
}

// Far-structure cells (DistanceOptions::ttc_cell_px): the window of ExpansionScale cut into
// cells of about cell_px × cell_px pixels; in each cell whose grey-level σ reaches min_contrast
// the magnification is refined by Gauss–Newton from start_scale, and kept when its NCC reaches
// min_ncc and its standard error (of the linearised Gauss–Newton regression) is at most max_se.
// Cells are visited nearest (cx, cy) first (ties in row-major order) and the result holds them
// in that order; with max_cells > 0 the search stops after that many answered (the nearest
// ones). None for a bad centre or window. At most kMaxTtcCells cells (no allocation).
inline constexpr int kMaxTtcCells = 96;
struct CellScales {
  std::array<double, kMaxTtcCells> scale{};
  std::array<double, kMaxTtcCells> radius_px{};  // of the cell's centre from the expansion centre
  int count = 0;
};
std::optional<CellScales> CellExpansionScales(const TtcImage& earlier, const TtcImage& current, double cx,
                                              double cy, double half_width_px, double half_height_px,
                                              double max_scale, double start_scale, double cell_px,
                                              double min_contrast, double min_ncc, double max_se = HUGE_VAL,
                                              int max_cells = 0);
inline std::optional<CellScales> CellExpansionScales(const Glance& earlier, const Glance& current, double cx,
                                                     double cy, double half_width_px, double half_height_px,
                                                     double max_scale, double start_scale, double cell_px,
                                                     double min_contrast, double min_ncc, double max_se = HUGE_VAL,
                                                     int max_cells = 0) {
  return CellExpansionScales(TtcView(earlier), TtcView(current), cx, cy, half_width_px, half_height_px, max_scale,
                             start_scale, cell_px, min_contrast, min_ncc, max_se, max_cells);
}
// The lower q-quantile of `values` (the element of rank floor(q · (n − 1)); reorders them); 0
// when empty.
double LowerQuantile(std::span<double> values, double q);

// 3×3 binomial smoothing ([1 2 1] ⊗ [1 2 1] / 16, rounded; border pixels repeated). `in` and
// `out` may not be the same glance.
void SmoothGlance(const Glance& in, Glance& out);
// The same for any TtcImage; `out` holds in.width × in.height pixels and is not in.data.
void SmoothTtcImage(const TtcImage& in, std::uint8_t* out);
// `out` (width × height ≤ kMaxTtcPixels, within the frame's size) from `frame` by exact area
// averaging: each pixel is the rounded mean of the source area [u·W/width, (u+1)·W/width) ×
// [v·H/height, (v+1)·H/height), partial source pixels weighted by their covered fraction. Grey
// as MakeGlance's. Preconditions (SQUINT_ENSURE): a non-empty frame with 1, 3 or 4 channels.
void MakeAreaImage(const PixelView& frame, int width, int height, std::uint8_t* out);

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
  // (cx, cy): the expansion centre in glance pixels. focal_px and camera_height_m (glance
  // camera; 0 = unknown) size the scale search's window (DistanceOptions::ttc_scale_search).
  TimeToContactDistance(const DistanceOptions& options, double cx, double cy, double focal_px = 0.0,
                        double camera_height_m = 0.0)
      : options_(options), cx_(cx), cy_(cy), focal_px_(focal_px), camera_height_m_(camera_height_m) {}
  DistanceCue Cue() const override { return DistanceCue::kTimeToContact; }
  // Consecutive frames (a one-frame baseline).
  void Measure(const PreparedGlance& previous, const PreparedGlance& current,
               std::optional<double> travelled_m, DistanceMeasureResult& out) const override;
  // Any baseline: `earlier` is `baseline_frames` frames before `current`, `travelled_m` the
  // distance driven between them.
  void MeasureBaseline(const Glance& earlier, const Glance& current, int baseline_frames,
                       std::optional<double> travelled_m, DistanceMeasureResult& out) const;
  // The scale search (DistanceOptions::ttc_scale_search) over the same baseline: out.raw = σ − 1
  // (≤ 0: no measurable expansion), model input s / (σ − 1). No estimate (kZeroGradient) when
  // the window's contrast is below ttc_min_contrast or the best NCC below ttc_min_ncc (a plain
  // wall close up: no texture to match, which must not read as "no expansion, very far"). `reference_m`: the last distance
  // estimate, which sizes the window (none: the whole glance).
  // The images may be finer than the glance (DistanceOptions::ttc_glance_scale): the expansion
  // centre, focal length and every window and cell size (given in glance pixels, i.e. angles) are
  // scaled by image width / 32 and height / 24.
  void MeasureScale(const TtcImage& earlier, const TtcImage& current, int baseline_frames,
                    std::optional<double> travelled_m, std::optional<double> reference_m,
                    DistanceMeasureResult& out) const;
  void MeasureScale(const Glance& earlier, const Glance& current, int baseline_frames,
                    std::optional<double> travelled_m, std::optional<double> reference_m,
                    DistanceMeasureResult& out) const {
    MeasureScale(TtcView(earlier), TtcView(current), baseline_frames, travelled_m, reference_m, out);
  }
  std::optional<double> Distance(double model_input) const override;

 private:
  DistanceOptions options_;
  double cx_;
  double cy_;
  double focal_px_;
  double camera_height_m_;
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
