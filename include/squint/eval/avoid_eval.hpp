// Evaluation of the avoidance stage (issue 6) against the floor contacts that label masks imply:
// per image column, the lowest standing pixel is where something meets the floor; its floor
// point gives a true range and bearing, hence a true polar map. Also the per-pair driver that
// `squint avoid` and `squint eval avoid` share.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "squint/config/avoid_yaml.hpp"
#include "squint/io/sequence.hpp"
#include "squint/obstacles/avoider.hpp"
#include "squint/obstacles/ipt_pipeline.hpp"

namespace squint::eval {

// One contact per image column whose lowest standing (non-zero) label pixel lies below the
// horizon: the floor point of that pixel's lower border (u, v + 0.5). A column standing down to
// the last row gives the last row's border (the true contact is nearer, out of view).
std::vector<obstacles::ContactPoint> LabelContacts(const CameraModel& camera, const cv::Mat& label);

// Runs IPT + avoidance over every consecutive pair of a sequence. `on_frame(frame, image,
// pair, avoid)` is called for each pair the IPT classified (frame = the later frame's row, as in
// `squint obstacles`); `on_skip(frame, pair)` for the others. Throws squint::Error for bad input.
void RunAvoidOnSequence(
    const io::Sequence& sequence, const config::AvoidFileOptions& options,
    const std::function<void(std::size_t, const cv::Mat&, const obstacles::PairResult&, const obstacles::AvoidResult&)>&
        on_frame,
    const std::function<void(std::size_t, const obstacles::PairResult&)>& on_skip = {});

struct AvoidFrameScore {
  std::size_t frame = 0;
  int sectors_in_view = 0;
  int sectors_agree = 0;
  int true_occupied = 0, detected_occupied = 0, both_occupied = 0;
  bool stop = false;
  std::optional<double> steer_deg;
  bool true_stop = false;              // the same gap steering on the true map stops
  std::optional<bool> steer_truly_free;  // no true contact within the ROI ±free_cone_deg of the steer
};

struct AvoidSequenceScore {
  std::string name;
  std::size_t pairs = 0, pairs_ok = 0;
  std::map<std::string, std::size_t> skipped;  // IPT status name -> pairs
  std::vector<AvoidFrameScore> frames;
};

struct AvoidEvalOptions {
  double free_cone_deg = 10.0;  // the steering direction must be free within ± this
};

// Scores one sequence (it needs label masks and odometry; throws squint::Error otherwise).
AvoidSequenceScore EvaluateAvoidSequence(const std::filesystem::path& sequence, const config::AvoidFileOptions& options,
                                         const AvoidEvalOptions& eval_options = {},
                                         const std::function<void(std::size_t, std::size_t)>& progress = {});

struct AvoidTotals {
  std::size_t frames = 0, sectors_in_view = 0, sectors_agree = 0;
  std::size_t true_occupied = 0, detected_occupied = 0, both_occupied = 0;
  std::size_t stops = 0, true_stops = 0, moving = 0, moving_free = 0;
  double SectorAgreement() const { return sectors_in_view ? double(sectors_agree) / sectors_in_view : 0.0; }
  double SteerFreeRate() const { return moving ? double(moving_free) / moving : 0.0; }
};
AvoidTotals Totals(const std::vector<AvoidFrameScore>& frames);

}  // namespace squint::eval
