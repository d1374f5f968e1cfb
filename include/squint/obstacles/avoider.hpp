// The obstacle-avoidance stage for the closed loop: from the classified features of one frame
// pair and the later grey image, the edge map, obstacle outlines, contact points, the polar
// occupancy map and the steering decision (obstacle paper §5).
#pragma once

#include <span>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "squint/core/camera.hpp"
#include "squint/core/pose.hpp"
#include "squint/obstacles/contacts.hpp"
#include "squint/obstacles/edge_map.hpp"
#include "squint/obstacles/feature.hpp"
#include "squint/obstacles/gap_steering.hpp"
#include "squint/obstacles/outline.hpp"
#include "squint/obstacles/polar_map.hpp"

namespace squint::obstacles {

// Beyond the paper: a short memory of contact points in the odometry frame. The camera sees
// 65° ahead and no floor nearer than about 0.6 m, so an obstacle beside the robot, or one it has
// come close to, leaves the view after a turn or a few steps; its contacts seen earlier still
// occupy their sectors (and narrow the gaps) for `decisions` frames. Used only when Process()
// gets the odometry pose of the frame.
struct ContactMemoryOptions {
  int decisions = 4;       // contacts of this many earlier decisions are kept (0: no memory)
  double radius_m = 1.5;   // remembered contacts farther than this from the robot are left out

  std::string Validate() const;
};

struct AvoidOptions {
  EdgeMapOptions edges;
  OutlineOptions outline;
  PolarMapOptions polar;
  GapOptions gap;
  ContactMemoryOptions memory;

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
  // Contacts of earlier frames (contact memory, robot frame now; `pixel` is NaN): only with the
  // odometry pose. The polar map and the gaps are built from `contacts` and these.
  std::vector<ContactPoint> remembered;
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
  // The same with the contact memory: `odom` is the odometry pose of `gray`'s frame. Earlier
  // frames' contacts (kept in the odometry frame) join this frame's in the polar map; this
  // frame's contacts within the ROI are then remembered.
  const AvoidResult& Process(const cv::Mat& gray, std::span<const ClassifiedFeature> features, const Pose2& odom);

  // The remembered contacts (within memory.radius_m) in the frame of the robot at `odom`.
  void RememberedPoints(const Pose2& odom, std::vector<Eigen::Vector2d>* points) const;
  // Whether the robot's footprint (radius + margin) can drive `length_m` straight ahead from
  // `odom` without touching a remembered contact: for moves made without a classified frame.
  bool StraightPathClear(const Pose2& odom, double length_m) const;
  // Forgets every remembered contact.
  void ClearMemory() { memory_.clear(); }

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

  struct Remembered {
    Eigen::Vector2d odom_m;  // floor point in the odometry frame
    long decision = 0;       // the memory decision that saw it
  };
  std::vector<Remembered> memory_;
  long memory_decision_ = 0;
  std::vector<ContactPoint> all_contacts_;  // this frame's and the remembered ones
  std::vector<Eigen::Vector2d> remembered_points_;  // RememberedPoints() of this frame

  void Perceive(const cv::Mat& gray, std::span<const ClassifiedFeature> features);
  void Decide(std::span<const ContactPoint> contacts);
};

}  // namespace squint::obstacles
