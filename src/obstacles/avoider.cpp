// The obstacle-avoidance stage: edges -> outlines -> contacts -> polar map -> steering.
#include "squint/obstacles/avoider.hpp"

#include "squint/core/error.hpp"

namespace squint::obstacles {

std::string AvoidOptions::Validate() const {
  for (const std::string& p : {edges.Validate(), outline.Validate(), polar.Validate(), gap.Validate()}) {
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
}

const AvoidResult& Avoider::Process(const cv::Mat& gray, std::span<const ClassifiedFeature> features) {
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
  result_.map = &polar_.Build(result_.contacts, result_.ground_floor_m);
  FindGaps(*result_.map, options_.gap, &result_.gaps);
  result_.decision = ChooseSteering(result_.gaps);
  return result_;
}

}  // namespace squint::obstacles
