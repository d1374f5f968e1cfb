// Corridor perception for one camera: glance → rapid-perception gate → five heading and three
// distance measures → fusion. The object owns every buffer, so Process() never allocates.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "squint/core/camera.hpp"
#include "squint/core/image_view.hpp"
#include "squint/corridor/distance_measures.hpp"
#include "squint/corridor/floor_contact.hpp"
#include "squint/corridor/glance.hpp"
#include "squint/corridor/heading_measures.hpp"
#include "squint/corridor/kalman.hpp"
#include "squint/corridor/measure.hpp"
#include "squint/corridor/options.hpp"
#include "squint/corridor/prepared_glance.hpp"

namespace squint::corridor {

struct PerceptionResult {
  // False when the rapid-perception gate skipped the frame (then every estimate is empty and
  // every measure's reason is kNotProcessed).
  bool processed = false;
  // |H(t) − H(t−1)| / H(reference) (§5.3); none on the first frame after a reset.
  std::optional<double> gate_change;
  // Fused estimates (none when no cue answered). With HeadingOptions::filter enabled,
  // heading_deg is the heading filter's state after this frame's cues (none while the state is
  // beyond max_abs_heading_deg), and heading_instant_deg the per-frame fusion; without the
  // filter both are the per-frame fusion.
  std::optional<double> heading_deg;
  std::optional<double> heading_instant_deg;
  std::optional<double> dist_end_m;
  // The end wall's floor contact (FloorContactOptions; Process() with a full camera only): this
  // frame's reading and its temporal median. With overrides_fusion the median, when there is
  // one, is dist_end_m.
  std::optional<double> dist_floor_raw_m;
  std::optional<double> dist_floor_m;
  // Whether this frame's floor-contact readings pass the motion test
  // (FloorContactOptions::motion_window_m; false when it is off).
  bool dist_floor_moves_as_floor = false;
  // Per cue, indexed by HeadingCue / DistanceCue.
  std::array<HeadingMeasureResult, kHeadingCueCount> heading{};
  std::array<DistanceMeasureResult, kDistanceCueCount> distance{};
  // Whole-glance entropy in nats (at the options' image_bits).
  double entropy = 0.0;

  const HeadingMeasureResult& Heading(HeadingCue cue) const { return heading[static_cast<int>(cue)]; }
  const DistanceMeasureResult& Distance(DistanceCue cue) const { return distance[static_cast<int>(cue)]; }
};

// The gate alone (§5.3), for callers that want it without the measures.
class RapidPerceptionGate {
 public:
  explicit RapidPerceptionGate(GateOptions options = {}) : options_(options) {}
  // Feeds the entropy of the next glance; returns true when the frame must be fully processed.
  // The first frame after Reset() becomes the reference and is always processed; so is any frame
  // when the reference entropy is 0 (a uniform first frame) or the gate is disabled, and any
  // frame after max_skipped_frames skipped ones. The change is measured from the previous frame
  // or, with compare_with_last_processed, from the last processed one.
  bool Update(double entropy);
  // The next frame becomes the new reference (call when a new corridor starts).
  void Reset();
  std::optional<double> LastChange() const { return last_change_; }

 private:
  GateOptions options_;
  std::optional<double> reference_;
  std::optional<double> previous_;
  std::optional<double> last_change_;
  int skipped_ = 0;  // frames skipped since the last processed one
};

class Perceiver {
 public:
  using Options = CorridorOptions;

  // `camera`: the full-resolution camera of the frames given to Process(); the glance camera is
  // camera.Scaled(32, 24). Without intrinsics (none or fx == 0) headings use
  // options.heading.fallback_deg_per_column. Throws squint::Error when options.Validate() fails.
  explicit Perceiver(const Options& options = {}, std::optional<CameraModel> camera = std::nullopt);
  ~Perceiver();
  Perceiver(const Perceiver&) = delete;
  Perceiver& operator=(const Perceiver&) = delete;

  // Processes the next frame (grey or colour). `travelled_m`: distance driven since the previous
  // frame (odometry); when none, options.distance.speed_mps × dt_s is used for time to contact.
  // dt_s is the time since the previous frame (≥ 0). `turned_deg`: the odometry's rotation since
  // the previous frame (left positive), the heading filter's process model (unused without
  // the filter; without it the filter only widens its uncertainty). Every value is finite or
  // absent.
  PerceptionResult Process(const PixelView& frame, std::optional<double> travelled_m, double dt_s,
                           std::optional<double> turned_deg = std::nullopt);
  PerceptionResult Process(const GrayView& frame, std::optional<double> travelled_m, double dt_s,
                           std::optional<double> turned_deg = std::nullopt) {
    return Process(PixelView::FromGray(frame), travelled_m, dt_s, turned_deg);
  }
  // Same, for a ready 32×24 glance (skips sampling).
  PerceptionResult ProcessGlance(const Glance& glance, std::optional<double> travelled_m, double dt_s,
                                 std::optional<double> turned_deg = std::nullopt);

  // Forgets the previous frame and the gate reference (a new sequence).
  void Reset();
  // The next frame becomes the gate's reference (a new corridor), keeping the previous frame.
  void ResetGateReference();
  // Restarts the heading filter (HeadingOptions::filter) from the next processed frame, keeping
  // everything else: the caller's reference axis changed (a new corridor).
  void ResetHeadingFilter();
  // The same, starting from a prior heading (degrees, standard deviation std_deg) instead of
  // from the next processed frame; a non-finite prior is no prior.
  void ResetHeadingFilter(double prior_deg, double std_deg);

  const Options& GetOptions() const { return options_; }
  const CameraModel& GlanceCamera() const { return glance_camera_; }
  // The heading (degrees, before calibration) of a glance column.
  double ColumnToHeadingDeg(double column_px) const;

 private:
  // ProcessGlance with `ttc_glance` (the glance time to contact compares: area-averaged for
  // Process() with DistanceOptions::ttc_area_glance, else `glance` itself).
  // `fine`: time to contact's finer image of the frame (DistanceOptions::ttc_glance_scale;
  // ttc_width_ × ttc_height_), or null. `frame`: the full frame for the floor contact, or null.
  PerceptionResult ProcessImpl(const Glance& glance, const Glance& ttc_glance, const std::uint8_t* fine,
                               const PixelView* frame, std::optional<double> travelled_m, double dt_s, std::optional<double> turned_deg);
  // The heading filter (HeadingOptions::filter): the prediction by the odometry's turn (every
  // frame) and the update by the cues (processed frames).
  void PredictHeading(std::optional<double> travelled_m, std::optional<double> turned_deg, double dt_s);
  void FilterHeading(PerceptionResult& result);
  void Fuse(PerceptionResult& result) const;
  // Heading fusion by the sum of the cues' normalised curves (HeadingOptions::fuse_curves).
  void FuseHeadingCurves(PerceptionResult& result) const;
  // Inverse of ColumnToHeadingDeg.
  double HeadingDegToColumn(double heading_deg) const;
  // Distance cues: time to contact over the chosen baseline, the temporal medians, and the
  // glance history they need (fixed-size: no allocation).
  void MeasureDistances(const PreparedGlance& prev, const PreparedGlance& cur, const Glance& ttc_glance,
                        const std::uint8_t* fine, std::optional<double> travelled, PerceptionResult& result);
  // Pushes `g` (and the finer image `fine`, when not null) into the time-to-contact history
  // with the travel so far.
  void PushHistory(const Glance& g, const std::uint8_t* fine);
  // The finer image of history entry `idx`.
  TtcImage FineHistoryAt(int idx) const {
    return {fine_history_px_.data() + static_cast<std::size_t>(idx) * static_cast<std::size_t>(ttc_width_ * ttc_height_),
            ttc_width_, ttc_height_};
  }
  void ResetDistanceHistory();

  Options options_;
  CameraModel glance_camera_;
  bool has_intrinsics_ = false;
  RapidPerceptionGate gate_;
  std::array<std::unique_ptr<HeadingMeasure>, kHeadingCueCount> heading_measures_;
  std::array<std::unique_ptr<DistanceMeasure>, kDistanceCueCount> distance_measures_;
  // Double buffer of prepared glances: current_ indexes the newest.
  std::array<PreparedGlance, 2> prepared_{};
  int current_ = 0;
  bool has_previous_ = false;
  // Distance state. history_: the last glances of continuous forward driving (ring, newest at
  // history_head_), with the odometry travel accumulated up to each; cues_: per cue, the last
  // median_frames model inputs (ring) with the travel at which each was measured.
  static constexpr int kHistorySize = kMaxTtcBaselineFrames + 1;
  std::array<Glance, kHistorySize> history_{};
  // With ttc_glance_scale: the finer image of each history entry (kHistorySize images of
  // ttc_width_ × ttc_height_, allocated once) and whether the entry has one.
  std::vector<std::uint8_t> fine_history_px_;
  std::array<bool, kHistorySize> history_fine_{};
  std::array<double, kHistorySize> history_travel_m_{};
  int history_count_ = 0;
  int history_head_ = 0;
  double travel_m_ = 0.0;
  struct CueWindow {
    std::array<double, kMaxDistanceMedianFrames> input{};
    std::array<double, kMaxDistanceMedianFrames> travel_m{};
    int count = 0;
    int head = 0;
  };
  std::array<CueWindow, kDistanceCueCount> cue_windows_{};
  CueWindow short_window_{};  // the one-frame time to contact (the baseline's reference)
  // Floor contact (FloorContactOptions): none without a full camera or when disabled; its
  // temporal window.
  std::unique_ptr<FloorContact> floor_contact_;
  CueWindow floor_window_{};
  std::unique_ptr<FloorMotionCheck> floor_motion_;  // with motion_window_m > 0
  // Pushes `input` (when given) and returns the median of the window; time-to-contact inputs
  // are first moved to the current frame by the travel since.
  std::optional<double> PushAndMedian(CueWindow& w, std::optional<double> input, bool travel_compensated) const;
  std::optional<double> last_ttc_input_m_;  // the last filtered time-to-contact input
  Glance area_glance_{};                    // Process()'s area-averaged glance for time to contact
  Glance smoothed_ttc_glance_{};            // the time-to-contact glance smoothed (ttc_smooth)
  int ttc_width_ = kGlanceWidth;            // time to contact's own image (ttc_glance_scale)
  int ttc_height_ = kGlanceHeight;
  std::vector<std::uint8_t> ttc_image_;     // Process()'s area-averaged image of that size
  std::vector<std::uint8_t> smoothed_ttc_image_;  // ... smoothed (ttc_smooth)
  CorridorKalman heading_filter_;           // heading half only (HeadingOptions::filter)
};

}  // namespace squint::corridor
