// The obstacle-avoidance stage for the closed loop: from the classified features of one frame
// pair and the later grey image, the edge map, obstacle outlines, contact points, the polar
// occupancy map and the steering decision (obstacle paper §5).
#pragma once

#include <span>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "squint/core/camera.hpp"
#include "squint/obstacles/contacts.hpp"
#include "squint/obstacles/edge_map.hpp"
#include "squint/obstacles/feature.hpp"
#include "squint/obstacles/gap_steering.hpp"
#include "squint/obstacles/outline.hpp"
#include "squint/obstacles/polar_map.hpp"

namespace squint::obstacles {

struct AvoidOptions {
  EdgeMapOptions edges;
  OutlineOptions outline;
  PolarMapOptions polar;
  GapOptions gap;

  // Empty when valid, otherwise the first problem found.
  std::string Validate() const;
};

// Everything one Process() call found; references into the Avoider, valid until the next call.
struct AvoidResult {
  const cv::Mat* edges = nullptr;                     // CV_8U, 255 on edge pixels
  const cv::Mat* base_edges = nullptr;                // CV_8U horizontal edges; empty when off
  const std::vector<OutlineTrace>* traces = nullptr;  // one per contact-giving outline
  const std::vector<Eigen::Vector2i>* outline_pixels = nullptr;
  std::vector<ContactPoint> contacts;  // every contact below the horizon (in and beyond the ROI)
  std::vector<Eigen::Vector2d> ground_floor_m;  // floor points of the ground features (robot frame)
  const PolarMap* map = nullptr;
  std::vector<Gap> gaps;
  SteeringDecision decision;
};

// Reuses its buffers between calls (no steady-state allocation). Not thread-safe.
class Avoider {
 public:
  // Throws squint::Error when the camera or the options are invalid.
  Avoider(const CameraModel& camera, AvoidOptions options = {});

  // `gray`: the later image of the pair, 8-bit single channel, of the camera's size.
  // `features`: that pair's classified features, pixels in `gray`.
  const AvoidResult& Process(const cv::Mat& gray, std::span<const ClassifiedFeature> features);

  const CameraModel& Camera() const { return camera_; }
  const AvoidOptions& Options() const { return options_; }
  const AvoidResult& Result() const { return result_; }

 private:
  CameraModel camera_;
  AvoidOptions options_;
  EdgeMapper edges_;
  OutlineTracer tracer_;
  PolarMapper polar_;
  AvoidResult result_;
};

}  // namespace squint::obstacles
