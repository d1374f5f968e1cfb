// Obstacle outlines (obstacle paper §5.1, §6.3): from each obstacle feature, the edge pixels in
// a window around it are traced downward until the last edge pixel or a ground feature; where a
// trace ends is an obstacle-to-floor contact point (in pixels). Beyond the paper, from each contact
// the obstacle's base is followed sideways along the horizontal-edge map, every base pixel being a
// contact too (so a box's front between its two vertical borders is not left free).
#pragma once

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "squint/obstacles/feature.hpp"

namespace squint::obstacles {

struct OutlineOptions {
  // Search window centred on an obstacle feature (paper §6.3: 9×15, taller than wide so that a
  // feature a little above or below a break in a vertical border still finds it). Odd sizes.
  int window_width_px = 9;
  int window_height_px = 15;
  // A trace stops on a ground feature: a pixel within this Chebyshev distance of one.
  int ground_stop_radius_px = 1;
  // Rows a trace may jump over when the edge below is broken (0 = the paper: stop at the last
  // edge pixel).
  int max_gap_rows = 0;
  // Beyond the paper: follow the base from each contact along the horizontal-edge map (left and
  // right, one column per step, up to base_max_rise_px rows up or down), while the grey level
  // steps across it by at least base_min_step (mean of the rows 3-6 above against 3-6 below, with
  // one sign all along: a base, not a thin floor line) and until a ground feature.
  bool base_trace = true;
  // With base_trace: also start a base below every obstacle feature, at the first horizontal
  // edge straight below it that passes the step test, unless a ground feature comes first
  // (within window_width_px / 2 columns of the way down).
  bool base_below_features = true;
  int base_max_rise_px = 1;
  double base_min_step = 20.0;

  std::string Validate() const;
};

// One traced outline: the pixels from its seed down to its contact point.
struct OutlineTrace {
  int first = 0;  // index of its first pixel in OutlineTracer::Pixels()
  int count = 0;
  Eigen::Vector2i contact_px;  // the last pixel: where the obstacle meets the floor
  bool stopped_on_ground = false;
  // A base found straight below an obstacle feature (no vertical outline): contact_px is where
  // the search met it, and its contacts are the base pixels only.
  bool below_feature = false;
  int base_first = 0;  // its base pixels (each a contact): index into OutlineTracer::BaseContacts()
  int base_count = 0;
};

// Traces outlines into buffers reused from frame to frame. Not thread-safe.
class OutlineTracer {
 public:
  explicit OutlineTracer(OutlineOptions options = {});

  // `edges`: CV_8U mask (non-zero = edge) as EdgeMapper gives. Features outside the image are
  // ignored. Returns one trace per distinct outline, in a deterministic order (features in the
  // given order, seeds top-to-bottom then left-to-right); a trace that joins a pixel already on
  // another outline ends there and adds no contact.
  const std::vector<OutlineTrace>& Trace(const cv::Mat& edges, std::span<const ClassifiedFeature> features);
  // The same, then each contact's base is followed along `base_edges` (CV_8U, as
  // EdgeMapper::BaseEdges gives) with the step test on `gray` (CV_8U), when base_trace is on.
  const std::vector<OutlineTrace>& Trace(const cv::Mat& edges, const cv::Mat& base_edges, const cv::Mat& gray,
                                         std::span<const ClassifiedFeature> features);

  // Every outline pixel of the last call, including branches that merged into another outline.
  const std::vector<Eigen::Vector2i>& Pixels() const { return pixels_; }
  // Every base pixel of the last call (each one a contact), in trace order.
  const std::vector<Eigen::Vector2i>& BaseContacts() const { return base_; }
  const OutlineOptions& Options() const { return options_; }

 private:
  OutlineOptions options_;
  cv::Mat ground_;   // CV_8U: 1 near a ground feature
  cv::Mat visited_;  // CV_8U: 1 on a traced outline
  std::vector<OutlineTrace> traces_;
  std::vector<Eigen::Vector2i> pixels_;
  std::vector<Eigen::Vector2i> base_;
  cv::Mat base_visited_;  // CV_8U: 1 on a traced base

  void TraceBase(const cv::Mat& base_edges, const cv::Mat& gray, OutlineTrace* trace);
};

}  // namespace squint::obstacles
