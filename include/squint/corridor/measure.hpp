// Result types shared by the corridor measures: which cue, its estimate or "no estimate" with a
// reason, and its per-column score curve. Fixed-size, so producing one never allocates.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "squint/corridor/glance.hpp"

namespace squint::corridor {

// The five heading cues of paper §4.1, in the order of the perceive CSV columns.
enum class HeadingCue : std::uint8_t { kEntropy, kSymmetry, kPhase, kVanishing, kBright };
inline constexpr int kHeadingCueCount = 5;
// The three distance-to-end cues of paper §4.2.
enum class DistanceCue : std::uint8_t { kTimeToContact, kJeffrey, kEntropy };
inline constexpr int kDistanceCueCount = 3;

// Short lower-case names, used in CSV columns and YAML keys: entropy, symmetry, phase,
// vanishing, bright / ttc, jeffrey, entropy.
const char* CueName(HeadingCue cue);
const char* CueName(DistanceCue cue);

// Why a measure gave no estimate (kNone when it gave one).
enum class Reason : std::uint8_t {
  kNone,
  kNotProcessed,        // the rapid-perception gate skipped the frame, or nothing ran yet
  kDisabled,            // the cue's weight is 0 or it is switched off in the options
  kUniformFrame,        // no intensity variation in the glance
  kFlatCurve,           // the score curve has no clear extremum (prominence below threshold)
  kPeakAtBorder,        // the extremum sits in the excluded border columns
  kNoBrightCluster,     // k-means found no distinct bright cluster in the upper half
  kZeroGradient,        // no image gradient to measure
  kNoMatch,             // self-similarity found no placement better than chance
  kDegenerateGeometry,  // corner lines parallel or the vanishing point far outside the image
  kNoPreviousFrame,     // consecutive-frame measure on the first frame
  kIdenticalFrames,     // consecutive glances equal: no temporal change to measure
  kTtcDenominatorZero,  // Σ G·I_t of eq. 3 is zero
  kNotApproaching,      // the image contracts (time-to-contact negative)
  kNoTravel,            // travelled distance unknown or zero, no speed option
  kOutOfRange,          // the estimate lies outside the options' validity range
};
const char* ReasonText(Reason reason);

struct HeadingMeasureResult {
  HeadingCue cue = HeadingCue::kEntropy;
  // The raw answer: a glance column (sub-pixel, 0 = left pixel centre), before calibration.
  std::optional<double> column_px;
  // Heading from the column through the glance camera, then the cue's scale and bias.
  std::optional<double> heading_deg;
  Reason reason = Reason::kNotProcessed;
  // How clear the extremum is, in [0, 1] (0 when there is no estimate).
  double confidence = 0.0;
  // True when fusion used this estimate; false for a missing estimate and for one that
  // disagreed with the consensus of the other cues (it is kept here, e.g. for calibration).
  bool fused = false;
  // Per-column score (cue-specific units; larger = more likely the corridor axis for every
  // cue; the phase cue stores -|Σ phase|). Columns the cue cannot score hold 0.
  std::array<float, kGlanceWidth> curve{};

  bool HasEstimate() const { return heading_deg.has_value(); }
};

struct DistanceMeasureResult {
  DistanceCue cue = DistanceCue::kTimeToContact;
  // The raw quantity before the distance model: time to contact in frames (eq. 3), the Jeffrey
  // divergence J (eq. 4), or the entropy change H(t-1) - H(t) in nats.
  std::optional<double> raw;
  // What the distance model takes: time to contact times the baseline's travel, minus half of
  // it (metres from the current frame), J, or ΔH; this frame's value, and its temporal median
  // (DistanceOptions::median_frames) that dist_m comes from.
  std::optional<double> model_input;
  std::optional<double> filtered_input;
  // This frame's own estimate (no temporal median), and the Perceiver's estimate (the model on
  // the median; the cue's output).
  std::optional<double> instant_m;
  std::optional<double> dist_m;
  // Time to contact: the glances compared lie this many frames apart (0 for the other cues).
  int baseline_frames = 0;
  Reason reason = Reason::kNotProcessed;
  bool fused = false;

  bool HasEstimate() const { return dist_m.has_value(); }
};

}  // namespace squint::corridor
