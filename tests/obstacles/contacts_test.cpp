// Tests of outline tracing and contact points on ray-cast boxes with known geometry.
#include "squint/obstacles/contacts.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "avoid_scene.hpp"
#include "squint/core/angles.hpp"
#include "squint/obstacles/edge_map.hpp"
#include "squint/obstacles/outline.hpp"

namespace squint::obstacles {
namespace {

using testing::Box;
using testing::Feature;
using testing::ObstacleCamera;
using testing::RenderBoxes;

struct Expected {
  double range_m, bearing_deg, range_tol_m, bearing_tol_deg;
};

// The analytic contact of the vertical edge at floor point (x, y), with tolerances equal to the
// largest change of range and bearing over pixel offsets of ±2 columns and ±1.5 rows (the edge
// band is a few pixels wide and the last box row is the projection rounded to a pixel).
Expected Analytic(const CameraModel& cam, double x, double y) {
  Expected e{std::hypot(x, y), RadToDeg(std::atan2(y, x)), 0, 0};
  const Eigen::Vector2d px = *cam.Project(Eigen::Vector3d(x, y, 0));
  for (double du : {-2.0, 2.0})
    for (double dv : {-1.5, 1.5}) {
      const auto c = ContactFromPixel(cam, px + Eigen::Vector2d(du, dv));
      e.range_tol_m = std::max(e.range_tol_m, std::abs(c->range_m - e.range_m));
      e.bearing_tol_deg = std::max(e.bearing_tol_deg, std::abs(c->bearing_deg - e.bearing_deg));
    }
  return e;
}

std::vector<ContactPoint> Contacts(const CameraModel& cam, const cv::Mat& img,
                                   const std::vector<ClassifiedFeature>& features, OutlineOptions oo = {}) {
  EdgeMapper edges;
  OutlineTracer tracer(oo);
  std::vector<ContactPoint> out;
  for (const OutlineTrace& t : tracer.Trace(edges.Compute(img), features))
    if (auto c = ContactFromPixel(cam, t.contact_px.cast<double>())) out.push_back(*c);
  return out;
}

TEST(ContactsTest, FloorPixelGivesRangeAndLeftPositiveBearing) {
  const CameraModel cam = ObstacleCamera();
  const Eigen::Vector2d px = *cam.Project(Eigen::Vector3d(1.2, 0.5, 0.0));
  const auto c = ContactFromPixel(cam, px);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->range_m, std::hypot(1.2, 0.5), 1e-9);
  EXPECT_NEAR(c->bearing_deg, RadToDeg(std::atan2(0.5, 1.2)), 1e-9);
  EXPECT_GT(c->bearing_deg, 0.0) << "left of the robot is positive";
  EXPECT_LT(px.x(), cam.cx) << "and appears left of the image centre";
}

TEST(ContactsTest, PixelAboveHorizonHasNoContact) {
  const CameraModel cam = ObstacleCamera();
  EXPECT_FALSE(ContactFromPixel(cam, {128.0, cam.HorizonRow() - 5.0}).has_value());
}

TEST(ContactsTest, CentredBoxGivesContactsAtItsFrontCorners) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.0, 1.3, -0.2, 0.15, 0.3};
  const cv::Mat img = RenderBoxes(cam, {box});
  std::vector<ClassifiedFeature> f = {
      Feature(cam, {1.0, 0.15, 0.15}, FeatureClass::kObstacle),   // on the left vertical edge
      Feature(cam, {1.0, -0.2, 0.15}, FeatureClass::kObstacle)};  // on the right one
  const auto contacts = Contacts(cam, img, f);
  ASSERT_EQ(contacts.size(), 2u);
  const Expected left = Analytic(cam, 1.0, 0.15), right = Analytic(cam, 1.0, -0.2);
  EXPECT_NEAR(contacts[0].range_m, left.range_m, left.range_tol_m);
  EXPECT_NEAR(contacts[0].bearing_deg, left.bearing_deg, left.bearing_tol_deg);
  EXPECT_NEAR(contacts[1].range_m, right.range_m, right.range_tol_m);
  EXPECT_NEAR(contacts[1].bearing_deg, right.bearing_deg, right.bearing_tol_deg);
  // The tolerances stay meaningful: a few centimetres and under a degree.
  EXPECT_LT(left.range_tol_m, 0.05);
  EXPECT_LT(left.bearing_tol_deg, 1.0);
}

TEST(ContactsTest, BoxToTheLeftHasPositiveBearings) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.2, 1.5, 0.3, 0.6, 0.4};
  const cv::Mat img = RenderBoxes(cam, {box});
  std::vector<ClassifiedFeature> f = {Feature(cam, {1.2, 0.6, 0.2}, FeatureClass::kObstacle)};
  const auto contacts = Contacts(cam, img, f);
  ASSERT_EQ(contacts.size(), 1u);
  const Expected e = Analytic(cam, 1.2, 0.6);
  EXPECT_NEAR(contacts[0].range_m, e.range_m, e.range_tol_m);
  EXPECT_NEAR(contacts[0].bearing_deg, e.bearing_deg, e.bearing_tol_deg);
}

TEST(ContactsTest, TraceStopsOnAGroundFeature) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.0, 1.3, -0.2, 0.15, 0.3};
  const cv::Mat img = RenderBoxes(cam, {box});
  const Eigen::Vector2d bottom = *cam.Project(Eigen::Vector3d(1.0, 0.15, 0.0));
  ClassifiedFeature ground;
  // A (misclassified) ground feature on the edge, 10 rows above the true contact.
  EdgeMapper edges;
  const cv::Mat& e = edges.Compute(img);
  int row = static_cast<int>(std::lround(bottom.y())) - 10, col = -1;
  for (int u = static_cast<int>(bottom.x()) - 4; u <= static_cast<int>(bottom.x()) + 4 && col < 0; ++u)
    if (e.at<std::uint8_t>(row, u)) col = u;
  ASSERT_GE(col, 0);
  ground.pixel = ground.previous_pixel = Eigen::Vector2d(col + 1, row);
  ground.cls = FeatureClass::kGround;
  std::vector<ClassifiedFeature> f = {Feature(cam, {1.0, 0.15, 0.2}, FeatureClass::kObstacle), ground};
  OutlineTracer tracer;
  const auto& traces = tracer.Trace(e, f);
  ASSERT_EQ(traces.size(), 1u);
  EXPECT_TRUE(traces[0].stopped_on_ground);
  EXPECT_EQ(traces[0].contact_px.y(), row - 1) << "stops when it comes within 1 px of the ground feature";
}

TEST(ContactsTest, NoObstacleFeatureNoContact) {
  const CameraModel cam = ObstacleCamera();
  const cv::Mat img = RenderBoxes(cam, {Box{1.0, 1.3, -0.2, 0.15, 0.3}});
  std::vector<ClassifiedFeature> f = {Feature(cam, {1.0, 0.15, 0.15}, FeatureClass::kGround)};
  EXPECT_TRUE(Contacts(cam, img, f).empty());
}

TEST(ContactsTest, FeatureFarFromEdgesFindsNothing) {
  const CameraModel cam = ObstacleCamera();
  const cv::Mat img = RenderBoxes(cam, {Box{1.0, 1.3, -0.2, 0.15, 0.3}});
  // On the middle of the box's front face: no edge within the 9×15 window.
  std::vector<ClassifiedFeature> f = {Feature(cam, {1.0, -0.02, 0.15}, FeatureClass::kObstacle)};
  EXPECT_TRUE(Contacts(cam, img, f).empty());
}

// Contacts with base tracing: the vertical trace, then the base followed sideways.
std::vector<ContactPoint> BaseContacts(const CameraModel& cam, const cv::Mat& img,
                                       const std::vector<ClassifiedFeature>& features, OutlineOptions oo = {}) {
  EdgeMapper edges;
  OutlineTracer tracer(oo);
  const cv::Mat& e = edges.Compute(img);
  tracer.Trace(e, edges.BaseEdges(), img, features);
  std::vector<ContactPoint> out;
  for (const Eigen::Vector2i& p : tracer.BaseContacts())
    if (auto c = ContactFromPixel(cam, p.cast<double>())) out.push_back(*c);
  return out;
}

TEST(ContactsTest, BaseTraceCoversTheWholeFrontOfABox) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.0, 1.3, -0.2, 0.15, 0.3};
  const cv::Mat img = RenderBoxes(cam, {box});
  // One obstacle feature, on the left vertical edge only.
  const std::vector<ClassifiedFeature> f = {Feature(cam, {1.0, 0.15, 0.15}, FeatureClass::kObstacle)};
  const auto contacts = BaseContacts(cam, img, f);
  ASSERT_GT(contacts.size(), 20u);
  double lo = 90, hi = -90;
  for (const ContactPoint& c : contacts) {
    // Every base contact lies on the box's front face line x = 1.0 (within 1.5 rows).
    const Expected e = Analytic(cam, 1.0, c.floor_m.y());
    EXPECT_NEAR(c.floor_m.x(), 1.0, e.range_tol_m) << c.pixel.transpose();
    lo = std::min(lo, c.bearing_deg);
    hi = std::max(hi, c.bearing_deg);
  }
  // ... and they span the front from one corner to the other (within a degree).
  EXPECT_NEAR(hi, RadToDeg(std::atan2(0.15, 1.0)), 1.0);
  EXPECT_NEAR(lo, RadToDeg(std::atan2(-0.2, 1.0)), 1.0);
  // Off: the paper's contacts only.
  OutlineOptions off;
  off.base_trace = false;
  EXPECT_TRUE(BaseContacts(cam, img, f, off).empty());
}

TEST(ContactsTest, BaseTraceStopsAtAGroundFeature) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.0, 1.3, -0.2, 0.15, 0.3};
  const cv::Mat img = RenderBoxes(cam, {box});
  // A ground feature on the base, at y = 0: the trace from the left corner stops before it.
  const std::vector<ClassifiedFeature> f = {Feature(cam, {1.0, 0.15, 0.15}, FeatureClass::kObstacle),
                                            Feature(cam, {1.0, 0.0, 0.0}, FeatureClass::kGround)};
  const auto contacts = BaseContacts(cam, img, f);
  ASSERT_FALSE(contacts.empty());
  for (const ContactPoint& c : contacts) EXPECT_GT(c.floor_m.y(), -0.01) << c.pixel.transpose();
}

TEST(ContactsTest, BaseBelowAFeatureOnTheFaceOfABox) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.0, 1.3, -0.2, 0.15, 0.3};
  const cv::Mat img = RenderBoxes(cam, {box});
  // One obstacle feature in the middle of the front face: no vertical edge within its window,
  // but the base straight below it.
  std::vector<ClassifiedFeature> f = {Feature(cam, {1.0, -0.02, 0.15}, FeatureClass::kObstacle)};
  ASSERT_TRUE(Contacts(cam, img, f).empty());
  auto contacts = BaseContacts(cam, img, f);
  ASSERT_GT(contacts.size(), 20u);
  double lo = 90, hi = -90;
  for (const ContactPoint& c : contacts) {
    EXPECT_NEAR(c.floor_m.x(), 1.0, Analytic(cam, 1.0, c.floor_m.y()).range_tol_m) << c.pixel.transpose();
    lo = std::min(lo, c.bearing_deg);
    hi = std::max(hi, c.bearing_deg);
  }
  EXPECT_NEAR(hi, RadToDeg(std::atan2(0.15, 1.0)), 1.0);
  EXPECT_NEAR(lo, RadToDeg(std::atan2(-0.2, 1.0)), 1.0);
  // Off: nothing.
  OutlineOptions off;
  off.base_below_features = false;
  EXPECT_TRUE(BaseContacts(cam, img, f, off).empty());
  // A ground feature on the face between the feature and the base, 3 columns aside: the floor
  // comes first (the feature may be a misclassified floor point), so no base.
  const Eigen::Vector2d px = f[0].pixel;
  const Eigen::Vector2d base = *cam.Project(Eigen::Vector3d(1.0, -0.02, 0.0));
  ClassifiedFeature g;
  g.pixel = g.previous_pixel = Eigen::Vector2d(px.x() + 3, 0.5 * (px.y() + base.y()));
  g.cls = FeatureClass::kGround;
  f.push_back(g);
  EXPECT_TRUE(BaseContacts(cam, img, f).empty());
}

TEST(ContactsTest, BaseTraceDoesNotFollowAThinFloorLine) {
  const CameraModel cam = ObstacleCamera();
  const Box box{1.0, 1.3, -0.2, 0.15, 0.3};
  cv::Mat img = RenderBoxes(cam, {box});
  // A dark 2-px line painted on the floor, continuing the box's base to the left edge of the image.
  const Eigen::Vector2d corner = *cam.Project(Eigen::Vector3d(1.0, 0.15, 0.0));
  const int row = static_cast<int>(std::lround(corner.y()));
  cv::Mat line = img.rowRange(row, row + 2).colRange(0, static_cast<int>(corner.x()) - 1);
  line.setTo(40);
  const std::vector<ClassifiedFeature> f = {Feature(cam, {1.0, 0.15, 0.15}, FeatureClass::kObstacle)};
  const auto contacts = BaseContacts(cam, img, f);
  ASSERT_GT(contacts.size(), 20u);
  for (const ContactPoint& c : contacts)
    EXPECT_LT(c.bearing_deg, RadToDeg(std::atan2(0.15, 1.0)) + 1.0) << "followed the floor line at " << c.pixel.transpose();
}

}  // namespace
}  // namespace squint::obstacles
