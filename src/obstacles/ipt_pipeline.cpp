// The per-pair IPT obstacle pipeline: odometry checks, tracking, undistortion, robust F, floor
// back-projection, discrepancy, zones and classification.
#include "squint/obstacles/ipt_pipeline.hpp"

#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/obstacles/ipt_geometry.hpp"

namespace squint::obstacles {

std::string IptOptions::Validate() const {
  std::ostringstream why;
  if (auto s = features.Validate(); !s.empty()) why << "features: " << s << "; ";
  if (auto s = fundamental.Validate(); !s.empty()) why << "fundamental: " << s << "; ";
  if (auto s = classifier.Validate(); !s.empty()) why << "classifier: " << s << "; ";
  if (!(min_translation_m > 0.0 && std::isfinite(min_translation_m))) why << "min_translation_m must be positive; ";
  if (!(pure_rotation_deg > 0.0 && std::isfinite(pure_rotation_deg))) why << "pure_rotation_deg must be positive; ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

const char* PairStatusName(PairStatus status) {
  switch (status) {
    case PairStatus::kOk: return "ok";
    case PairStatus::kMissingOdometry: return "missing_odometry";
    case PairStatus::kNoMotion: return "no_motion";
    case PairStatus::kPureRotation: return "pure_rotation";
    case PairStatus::kTooFewFeatures: return "too_few_features";
    case PairStatus::kBadImage: return "bad_image";
  }
  return "?";
}

struct IptPipeline::Impl {
  CameraModel camera;
  IptOptions options;
  ZoneLayout zones;
  std::unique_ptr<FeatureTracker> tracker;
  // Buffers kept between pairs.
  cv::Mat grey_prev, grey_cur;
  std::vector<Match> matches;
  std::vector<cv::Point2f> undist_prev, undist_cur;

  cv::Point2f Undistort(const cv::Point2f& p) const {
    if (!camera.HasDistortion()) return p;
    const Eigen::Vector2d n = camera.Normalize({p.x, p.y});
    return {static_cast<float>(camera.cx + camera.fx * n.x()), static_cast<float>(camera.cy + camera.fy * n.y())};
  }

  // Returns an empty string when the image is usable (converted to grey into `grey` if needed).
  std::string CheckImage(const cv::Mat& image, const char* which, cv::Mat& grey, const cv::Mat** out) const {
    if (image.empty()) return fmt::format("the {} image is empty", which);
    if (image.cols != camera.width || image.rows != camera.height)
      return fmt::format("the {} image is {}x{}, the camera is {}x{}", which, image.cols, image.rows, camera.width,
                         camera.height);
    if (image.depth() != CV_8U) return fmt::format("the {} image is not 8-bit", which);
    if (image.channels() == 1) {
      *out = &image;
    } else if (image.channels() == 3 || image.channels() == 4) {
      cv::cvtColor(image, grey, image.channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
      *out = &grey;
    } else {
      return fmt::format("the {} image has {} channels", which, image.channels());
    }
    return {};
  }
};

IptPipeline::IptPipeline(const CameraModel& camera, const IptOptions& options) : impl_(std::make_unique<Impl>()) {
  if (auto why = camera.Validate(); !why.empty()) throw Error("obstacles: invalid camera: " + why);
  if (auto why = options.Validate(); !why.empty()) throw Error("obstacles: invalid options: " + why);
  impl_->camera = camera;
  impl_->options = options;
  impl_->zones = ComputeZoneLayout(camera, options.classifier.zoning);
  impl_->tracker = MakeFeatureTracker(options.features);
}

IptPipeline::~IptPipeline() = default;
IptPipeline::IptPipeline(IptPipeline&&) noexcept = default;
IptPipeline& IptPipeline::operator=(IptPipeline&&) noexcept = default;

const CameraModel& IptPipeline::Camera() const { return impl_->camera; }
const IptOptions& IptPipeline::Options() const { return impl_->options; }
const ZoneLayout& IptPipeline::Zones() const { return impl_->zones; }

PairResult IptPipeline::Process(const cv::Mat& previous_image, const cv::Mat& current_image,
                                const std::optional<Pose2>& previous_odom, const std::optional<Pose2>& current_odom) {
  PairResult result;
  Process(previous_image, current_image, previous_odom, current_odom, &result);
  return result;
}

void IptPipeline::Process(const cv::Mat& previous_image, const cv::Mat& current_image,
                          const std::optional<Pose2>& previous_odom, const std::optional<Pose2>& current_odom,
                          PairResult* result) {
  Impl& m = *impl_;
  const IptOptions& opt = m.options;
  result->status = PairStatus::kOk;
  result->reason.clear();
  result->features.clear();
  result->measured.clear();
  result->matches = 0;
  auto fail = [&](PairStatus status, std::string reason) {
    result->status = status;
    result->reason = std::move(reason);
    result->features.clear();
    result->measured.clear();
  };

  // Odometry first: without a usable motion nothing can be classified, so skip the tracking.
  if (!previous_odom || !current_odom) {
    fail(PairStatus::kMissingOdometry,
         fmt::format("no odometry pose for the {} frame", !previous_odom ? "earlier" : "later"));
    return;
  }
  const Pose2 motion = Between(*previous_odom, *current_odom);
  const double translation_m = std::hypot(motion.x, motion.y);
  if (translation_m < opt.min_translation_m) {
    const double turn_deg = std::abs(RadToDeg(motion.yaw));
    if (turn_deg > opt.pure_rotation_deg)
      fail(PairStatus::kPureRotation,
           fmt::format("pure rotation ({:.3f} m moved, {:.2f} deg turned): the discrepancy does not separate obstacles",
                       translation_m, turn_deg));
    else
      fail(PairStatus::kNoMotion, fmt::format("no motion ({:.4f} m moved, below {:.4f} m): the discrepancy is undefined",
                                              translation_m, opt.min_translation_m));
    return;
  }

  const cv::Mat* prev = nullptr;
  const cv::Mat* cur = nullptr;
  if (auto why = m.CheckImage(previous_image, "earlier", m.grey_prev, &prev); !why.empty()) {
    fail(PairStatus::kBadImage, why);
    return;
  }
  if (auto why = m.CheckImage(current_image, "later", m.grey_cur, &cur); !why.empty()) {
    fail(PairStatus::kBadImage, why);
    return;
  }

  m.tracker->Track(*prev, *cur, &m.matches);
  result->matches = static_cast<int>(m.matches.size());
  if (result->matches < opt.fundamental.min_matches) {
    fail(PairStatus::kTooFewFeatures, fmt::format("too few matched features ({}, at least {} needed)", result->matches,
                                                  opt.fundamental.min_matches));
    return;
  }
  m.undist_prev.clear();
  m.undist_cur.clear();
  for (const Match& mt : m.matches) {
    m.undist_prev.push_back(m.Undistort(mt.previous));
    m.undist_cur.push_back(m.Undistort(mt.current));
  }
  const std::optional<FundamentalResult> F = EstimateFundamental(m.undist_prev, m.undist_cur, opt.fundamental);
  if (!F || F->inliers < opt.fundamental.min_matches) {
    fail(PairStatus::kTooFewFeatures,
         fmt::format("too few matches consistent with one fundamental matrix ({} of {}, at least {} needed)",
                     F ? F->inliers : 0, result->matches, opt.fundamental.min_matches));
    return;
  }

  // Per feature: one viewing ray per pixel gives the horizon test, the discrepancies and the
  // odometry epipolar residual (the values of AboveHorizon, AllDiscrepancies, MotionEpipolarErrorPx).
  const PairGeometry geometry(m.camera, *previous_odom, *current_odom);
  for (std::size_t i = 0; i < m.matches.size(); ++i) {
    if (!F->inlier[i]) continue;
    MeasuredFeature f;
    f.pixel = {m.matches[i].current.x, m.matches[i].current.y};
    f.previous_pixel = {m.matches[i].previous.x, m.matches[i].previous.y};
    const FeatureMeasures measures = geometry.Measure(f.previous_pixel, f.pixel);
    f.motion_epipolar_px = measures.motion_epipolar_px.value_or(0.0);
    if (measures.above_horizon) {
      f.zone = kHorizonZone;
    } else {
      // A feature below the horizon now but above it before stands above the floor as well (no D).
      if (const auto& d = measures.discrepancies) {
        f.plain_discrepancy_m = d->plain_m;
        f.signed_discrepancy_m = d->signed_m;
        f.discrepancy_m = opt.mirror_aware ? d->mirror_aware_m : d->plain_m;
      }
      f.zone = f.discrepancy_m ? std::min(2, m.zones.ZoneOfRow(f.pixel.y())) : kHorizonZone;
    }
    f.cls = ClassifyFeature(f.zone, f.discrepancy_m, opt.classifier);
    if (f.cls) result->features.push_back({f.pixel, f.previous_pixel, f.discrepancy_m, *f.cls});
    result->measured.push_back(f);
  }
}

}  // namespace squint::obstacles
