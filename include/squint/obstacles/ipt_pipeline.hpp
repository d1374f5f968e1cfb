// The obstacle-detection pipeline of one consecutive frame pair (paper §3–4): features and matches,
// undistortion, robust fundamental matrix, back-projection with odometry, discrepancy, horizon,
// zone β and refinement. Output: the classified features (the hand-over to outlines/contacts).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "squint/core/camera.hpp"
#include "squint/core/pose.hpp"
#include "squint/obstacles/classifier.hpp"
#include "squint/obstacles/feature.hpp"
#include "squint/obstacles/feature_tracker.hpp"
#include "squint/obstacles/fundamental.hpp"
#include "squint/obstacles/zones.hpp"

namespace squint::obstacles {

struct IptOptions {
  FeatureOptions features;
  FundamentalOptions fundamental;
  ClassifierOptions classifier;
  // Odometry translation between the frames below which the pair has no usable motion (D is then
  // zero for every point and undefined as a cue).
  double min_translation_m = 0.005;
  // With less translation than min_translation_m but more yaw change than this, the pair is a pure
  // rotation (reported separately: it is a common manoeuvre).
  double pure_rotation_deg = 0.5;
  // The discrepancy the classifier thresholds: true = MirrorAwareDiscrepancy() (a floor point's
  // reflection in a specular floor counts as floor), false = the paper's D (eq. 4).
  bool mirror_aware = true;

  std::string Validate() const;
};

enum class PairStatus { kOk, kMissingOdometry, kNoMotion, kPureRotation, kTooFewFeatures, kBadImage };
const char* PairStatusName(PairStatus status);

// A tracked feature with everything the classifier saw, including those the refinement left out
// (for evaluation and drawing).
struct MeasuredFeature {
  Eigen::Vector2d pixel;           // later frame, raw pixel
  Eigen::Vector2d previous_pixel;  // earlier frame, raw pixel
  int zone = 0;                    // 0–3 (3 = above the horizon)
  std::optional<double> discrepancy_m;  // the classified discrepancy (IptOptions::mirror_aware); none in zone 3
  std::optional<double> plain_discrepancy_m;   // D of eq. 4; none in zone 3
  std::optional<double> signed_discrepancy_m;  // SignedDiscrepancy(); none in zone 3
  std::optional<FeatureClass> cls;      // none when left unclassified by the refinement
  double motion_epipolar_px = 0.0;      // MotionEpipolarErrorPx() under the odometry motion
};

struct PairResult {
  PairStatus status = PairStatus::kOk;
  std::string reason;  // empty when ok; otherwise one line saying why nothing was classified
  std::vector<ClassifiedFeature> features;  // classified features only (the hand-over)
  std::vector<MeasuredFeature> measured;    // every feature that survived matching and F
  int matches = 0;                          // correspondences before the fundamental matrix
  bool Ok() const { return status == PairStatus::kOk; }
};

class IptPipeline {
 public:
  // Throws squint::Error when the camera or options are invalid (the message says what is wrong).
  IptPipeline(const CameraModel& camera, const IptOptions& options);
  ~IptPipeline();
  IptPipeline(IptPipeline&&) noexcept;
  IptPipeline& operator=(IptPipeline&&) noexcept;

  // Classifies the features of one consecutive pair. Images are 8-bit grey of the camera's size;
  // poses are world_T_robot from odometry. Never throws for degenerate input: the status says why.
  PairResult Process(const cv::Mat& previous_image, const cv::Mat& current_image,
                     const std::optional<Pose2>& previous_odom, const std::optional<Pose2>& current_odom);
  // As above, reusing `result`'s storage.
  void Process(const cv::Mat& previous_image, const cv::Mat& current_image, const std::optional<Pose2>& previous_odom,
               const std::optional<Pose2>& current_odom, PairResult* result);

  const CameraModel& Camera() const;
  const IptOptions& Options() const;
  const ZoneLayout& Zones() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace squint::obstacles
