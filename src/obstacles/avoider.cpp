// The obstacle-avoidance stage: edges -> outlines -> contacts -> polar map -> steering.
#include "squint/obstacles/avoider.hpp"

#include <cmath>
#include <limits>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::obstacles {

std::string ContactMemoryOptions::Validate() const {
  if (!(decisions >= 0 && decisions <= 1000)) return "memory.decisions must be in [0, 1000]";
  if (!(radius_m > 0.0 && radius_m <= 100.0)) return "memory.radius_m must be in (0, 100]";
  return {};
}

std::string AvoidOptions::Validate() const {
  for (const std::string& p : {edges.Validate(), outline.Validate(), polar.Validate(), gap.Validate(), memory.Validate()}) {
    if (!p.empty()) return p;
  }
  return {};
}

namespace {
const AvoidOptions& Checked(const CameraModel& camera, const AvoidOptions& options) {
  const std::string cam = camera.Validate();
  if (!cam.empty()) throw Error("avoid: invalid camera: " + cam);
  if (!camera.HasIntrinsics()) throw Error("avoid: the camera has no intrinsics (fx, fy)");
  const std::string problem = options.Validate();
  if (!problem.empty()) throw Error("avoid options: " + problem);
  return options;
}
}  // namespace

Avoider::Avoider(const CameraModel& camera, AvoidOptions options)
    : camera_(camera),
      options_(Checked(camera, options)),
      edges_(options_.edges),
      tracer_(options_.outline),
      polar_(camera_, options_.polar) {
  result_.contacts.reserve(2048);
  result_.gaps.reserve(64);
  result_.ground_floor_m.reserve(512);
  result_.remembered.reserve(2048);
  all_contacts_.reserve(4096);
  memory_.reserve(4096);
  remembered_points_.reserve(4096);
}

void Avoider::Perceive(const cv::Mat& gray, std::span<const ClassifiedFeature> features) {
  SQUINT_ENSURE(gray.type() == CV_8UC1 && gray.cols == camera_.width && gray.rows == camera_.height,
                "Avoider::Process needs an 8-bit grey image of the camera's size");
  result_.edges = &edges_.Compute(gray);
  result_.base_edges = &edges_.BaseEdges();
  result_.traces = &tracer_.Trace(*result_.edges, edges_.BaseEdges(), gray, features);
  result_.outline_pixels = &tracer_.Pixels();
  result_.contacts.clear();
  for (const OutlineTrace& t : *result_.traces) {
    if (t.below_feature) continue;  // its contacts are its base pixels
    if (auto c = ContactFromPixel(camera_, t.contact_px.cast<double>())) result_.contacts.push_back(*c);
  }
  for (const Eigen::Vector2i& p : tracer_.BaseContacts()) {
    if (auto c = ContactFromPixel(camera_, p.cast<double>())) result_.contacts.push_back(*c);
  }
  result_.ground_floor_m.clear();
  for (const ClassifiedFeature& f : features) {
    if (f.cls != FeatureClass::kGround) continue;
    if (auto p = camera_.FloorPoint(f.pixel)) result_.ground_floor_m.push_back(*p);
  }
  result_.remembered.clear();
}

void Avoider::Decide(std::span<const ContactPoint> contacts) {
  result_.map = &polar_.Build(contacts, result_.ground_floor_m);
  FindGaps(*result_.map, options_.gap, &result_.gaps);
  result_.decision = ChooseSteering(result_.gaps);
}

const AvoidResult& Avoider::Process(const cv::Mat& gray, std::span<const ClassifiedFeature> features) {
  Perceive(gray, features);
  Decide(result_.contacts);
  return result_;
}

void Avoider::RememberedPoints(const Pose2& odom, std::vector<Eigen::Vector2d>* points) const {
  SQUINT_ENSURE(points != nullptr, "RememberedPoints needs an output vector");
  points->clear();
  const Pose2 robot_T_odom = odom.Inverse();
  const double r2 = options_.memory.radius_m * options_.memory.radius_m;
  for (const Remembered& m : memory_) {
    const Eigen::Vector2d p = robot_T_odom.Apply(m.odom_m);
    if (p.squaredNorm() <= r2) points->push_back(p);
  }
}

bool Avoider::StraightPathClear(const Pose2& odom, double length_m) const {
  std::vector<Eigen::Vector2d> points;
  RememberedPoints(odom, &points);
  return StraightPathFree(points, length_m, options_.gap.robot_radius_m + options_.gap.margin_m);
}

const AvoidResult& Avoider::Process(const cv::Mat& gray, std::span<const ClassifiedFeature> features,
                                    const Pose2& odom) {
  Perceive(gray, features);
  const int keep = options_.memory.decisions;
  if (keep == 0) {
    memory_.clear();
    Decide(result_.contacts);
    return result_;
  }
  // Forget what is older than `keep` decisions, then add the rest, in this robot frame.
  std::erase_if(memory_, [&](const Remembered& m) { return m.decision < memory_decision_ - keep; });
  RememberedPoints(odom, &remembered_points_);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Eigen::Vector2d& p : remembered_points_) {
    ContactPoint c;
    c.pixel = Eigen::Vector2d(nan, nan);
    c.floor_m = p;
    c.range_m = p.norm();
    c.bearing_deg = RadToDeg(std::atan2(p.y(), p.x()));
    result_.remembered.push_back(c);
  }
  all_contacts_.assign(result_.contacts.begin(), result_.contacts.end());
  all_contacts_.insert(all_contacts_.end(), result_.remembered.begin(), result_.remembered.end());
  Decide(all_contacts_);
  for (const ContactPoint& c : result_.contacts) {
    if (c.range_m > options_.polar.roi_radius_m) continue;
    memory_.push_back({odom.Apply(c.floor_m), memory_decision_});
  }
  ++memory_decision_;
  return result_;
}

}  // namespace squint::obstacles
