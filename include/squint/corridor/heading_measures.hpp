// The five heading cues of paper §4.1, one class each behind a small interface. Each scores
// every glance column, picks the extremum and says whether it is trustworthy; converting the
// column to degrees (camera model, calibration) and fusing is the Perceiver's job.
#pragma once

#include <memory>
#include <optional>

#include "squint/corridor/measure.hpp"
#include "squint/corridor/options.hpp"
#include "squint/corridor/prepared_glance.hpp"

namespace squint::corridor {

class HeadingMeasure {
 public:
  virtual ~HeadingMeasure() = default;
  virtual HeadingCue Cue() const = 0;
  // Fills out.curve, out.column_px (or none), out.reason and out.confidence; leaves
  // out.heading_deg and out.fused alone. Never allocates.
  virtual void Measure(const PreparedGlance& glance, HeadingMeasureResult& out) const = 0;
};

// f1: entropy of the grey levels in a vertical slice around each column; the maximum (§4.1.1).
class EntropyHeading final : public HeadingMeasure {
 public:
  explicit EntropyHeading(const HeadingOptions& options) : options_(options) {}
  HeadingCue Cue() const override { return HeadingCue::kEntropy; }
  void Measure(const PreparedGlance& glance, HeadingMeasureResult& out) const override;

 private:
  HeadingOptions options_;
};

// f2: mutual information between the mirrored left and right halves of the window around each
// column (eq. 2); the maximum is the symmetry axis (§4.1.2). With options.symmetry_significance
// the MI is weighted by the window's pair count (see HeadingOptions).
class SymmetryHeading final : public HeadingMeasure {
 public:
  explicit SymmetryHeading(const HeadingOptions& options) : options_(options) {}
  HeadingCue Cue() const override { return HeadingCue::kSymmetry; }
  void Measure(const PreparedGlance& glance, HeadingMeasureResult& out) const override;

 private:
  HeadingOptions options_;
};

// f3: aggregate Sobel gradient phase (§4.1.3). By default each edge pixel's phase gives its edge
// line, and the lines vote for where they cross the horizon row (the vanishing point of the
// corridor's parallel edges); with options.phase_line_vote = false, the paper's form: the
// column where the phases of a window balance (minimum |Σ|).
class PhaseHeading final : public HeadingMeasure {
 public:
  // `horizon_row`: the glance row of the horizon when the camera is known (else the middle row).
  explicit PhaseHeading(const HeadingOptions& options, std::optional<double> horizon_row = std::nullopt)
      : options_(options), horizon_row_(horizon_row) {}
  HeadingCue Cue() const override { return HeadingCue::kPhase; }
  void Measure(const PreparedGlance& glance, HeadingMeasureResult& out) const override;

 private:
  void MeasureLineVote(const PreparedGlance& glance, HeadingMeasureResult& out) const;
  void MeasureBalance(const PreparedGlance& glance, HeadingMeasureResult& out) const;

  HeadingOptions options_;
  std::optional<double> horizon_row_;
};

// f4: vanishing point by self-similarity (§4.1.4): the half-size glance is slid over the glance;
// at the placement of maximum mutual information, the lines joining corresponding corners meet
// at the vanishing point, whose x is kept.
class VanishingHeading final : public HeadingMeasure {
 public:
  // `horizon_row`: the glance row of the horizon when the camera is known; the search then
  // covers vanishing points within options.vanishing_row_margin_px of it (else every row).
  explicit VanishingHeading(const HeadingOptions& options, std::optional<double> horizon_row = std::nullopt)
      : options_(options), horizon_row_(horizon_row) {}
  HeadingCue Cue() const override { return HeadingCue::kVanishing; }
  void Measure(const PreparedGlance& glance, HeadingMeasureResult& out) const override;

 private:
  HeadingOptions options_;
  std::optional<double> horizon_row_;
};

// f5: the median column of the brighter of two k-means (k = 2) grey-level clusters in the upper
// part of the glance (§4.1.5).
class BrightHeading final : public HeadingMeasure {
 public:
  explicit BrightHeading(const HeadingOptions& options) : options_(options) {}
  HeadingCue Cue() const override { return HeadingCue::kBright; }
  void Measure(const PreparedGlance& glance, HeadingMeasureResult& out) const override;

 private:
  HeadingOptions options_;
};

std::unique_ptr<HeadingMeasure> MakeHeadingMeasure(HeadingCue cue, const HeadingOptions& options,
                                                   std::optional<double> horizon_row = std::nullopt);

}  // namespace squint::corridor
