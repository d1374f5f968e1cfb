// The robot's own body seen in a mirror: a constructed corridor whose end wall is a perfect
// mirror, the robot facing it at a known distance d. The reflected body must cover exactly the
// pixels whose rays, unfolded through the mirror, meet a cylinder of the robot's radius at 2d,
// with the image span of that cylinder's projected silhouette; primary rays never see it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/sim/renderer.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {
namespace {

constexpr double kMirrorX = 11.5;  // the end wall of a corridor from x = 0 to 10, 3 m wide

// `mirror_share` 1: the end wall shows only its reflection. `robot_extra` goes into the robot
// mapping (body keys).
World MirrorWorld(const std::string& robot_extra, bool with_mirror = true) {
  const std::string features = with_mirror ? ", features: [{kind: mirror, side: to_end, material: perfect}]" : "";
  return ParseWorld(fmt::format("format: squint-world/1\n"
                                "materials: {{perfect: {{base: mirror, mirror: 1.0}}}}\n"
                                "corridors: [{{from: [0, 0], to: [10, 0], width_m: 3, height_m: 3, lights: {{rows: centre, spacing_m: 2.0}}{}}}]\n"
                                "robot: {{start: [5, 0, 0]{}}}\n",
                                features, robot_extra),
                    "mirror.yaml");
}

CameraModel Camera(double pitch_deg, double height_m) {
  CameraMount m;
  m.width = 41;  // odd: column 20 is the optical axis's
  m.height = 31;
  m.hfov_deg = 60;
  m.pitch_deg = pitch_deg;
  m.height_m = height_m;
  return m.Model();
}

RenderOptions Exact() {
  RenderOptions o;
  o.supersample = 1;
  o.noise_sigma = 0.0;
  return o;
}

// Pixels where a black body and a white one differ: where the reflected body shows.
cv::Mat BodyMask(const CameraModel& cam, const Pose2& pose, const RenderOptions& o = Exact()) {
  Renderer dark(MirrorWorld(", body_grey: 0.0"), cam, o), light(MirrorWorld(", body_grey: 1.0"), cam, o);
  cv::Mat diff;
  cv::absdiff(dark.Render(pose), light.Render(pose), diff);
  return diff > 0;
}

// The virtual body (the real one mirrored in x = kMirrorX) in the robot frame.
Eigen::Vector2d VirtualCentre(const Pose2& pose) {
  const double dx = 2 * (kMirrorX - pose.x);
  return {std::cos(pose.yaw) * dx, -std::sin(pose.yaw) * dx};
}

TEST(MirrorBody, ReflectedBodyCoversExactlyTheRaysMeetingACylinderAtTwiceTheDistance) {
  const double radius = 0.25, cam_h = 0.5, top = cam_h + 0.1;  // world defaults
  for (double pitch : {0.0, -5.0, -12.0})
    for (const Pose2& pose : {Pose2{kMirrorX - 1.2, 0.0, 0.0}, Pose2{kMirrorX - 0.8, 0.3, DegToRad(8)},
                              Pose2{kMirrorX - 2.5, -0.4, DegToRad(-5)}}) {
      const CameraModel cam = Camera(pitch, cam_h);
      const cv::Mat mask = BodyMask(cam, pose);
      const Eigen::Vector2d c = VirtualCentre(pose);
      int body = 0, checked = 0;
      for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
          // The ray, unfolded: a straight line from the camera; where it enters the cylinder.
          const Eigen::Vector3d d = cam.PixelRayRobot({u, v});
          const double h = std::hypot(d.x(), d.y());
          const double dx = d.x() / h, dy = d.y() / h, k = d.z() / h;
          const double b = -(c.x() * dx + c.y() * dy), cc = c.squaredNorm() - radius * radius;
          const double disc = b * b - cc;
          bool hit = false, borderline = std::abs(disc) < 1e-9;
          if (disc > 0) {
            const double t = -b - std::sqrt(disc);
            const double z = cam_h + k * t;
            hit = t > 0 && z >= 0 && z <= top;
            borderline = borderline || std::abs(z) < 1e-6 || std::abs(z - top) < 1e-6;
          }
          if (borderline) continue;
          ++checked;
          body += hit;
          EXPECT_EQ(mask.at<std::uint8_t>(v, u) != 0, hit) << "pitch " << pitch << " pose x " << pose.x << " pixel " << u << "," << v;
        }
      EXPECT_GE(body, 8) << "pitch " << pitch << " pose x " << pose.x;
      EXPECT_GT(checked, cam.width * cam.height - 10);
    }
}

// The silhouette's projection: the columns between the cylinder's two vertical tangent lines
// (projected through the camera model), and at the optical axis's column the rows between the
// nearest point's top and foot.
TEST(MirrorBody, ReflectedBodySpansTheProjectionOfACylinderAtTwiceTheDistance) {
  const double radius = 0.25, cam_h = 0.5, top = 0.6;
  for (double pitch : {0.0, -8.0}) {
    const CameraModel cam = Camera(pitch, cam_h);
    const double d = 1.2;
    const Pose2 pose{kMirrorX - d, 0.0, 0.0};
    const cv::Mat mask = BodyMask(cam, pose);
    const double dist = 2 * d, half = std::asin(radius / dist), l = std::sqrt(dist * dist - radius * radius);
    // Rows at the centre column: from the projection of the nearest point's top to its foot.
    const auto front_top = cam.Project({dist - radius, 0, top}), front_foot = cam.Project({dist - radius, 0, 0});
    ASSERT_TRUE(front_top && front_foot);
    int first = -1, last = -1;
    for (int v = 0; v < cam.height; ++v)
      if (mask.at<std::uint8_t>(v, 20)) last = v, first = first < 0 ? v : first;
    EXPECT_EQ(first, static_cast<int>(std::ceil(front_top->y()))) << "pitch " << pitch;
    EXPECT_EQ(last, std::min(cam.height - 1, static_cast<int>(std::floor(front_foot->y())))) << "pitch " << pitch;
    // Columns in each row that the tangent lines span over their whole height.
    auto line_at = [&](double bearing, double v) {
      const auto a = cam.Project({l * std::cos(bearing), l * std::sin(bearing), top});
      const auto b = cam.Project({l * std::cos(bearing), l * std::sin(bearing), 0.0});
      return std::make_pair(a->x() + (b->x() - a->x()) * (v - a->y()) / (b->y() - a->y()), std::make_pair(a->y(), b->y()));
    };
    int rows = 0;
    for (int v = 0; v < cam.height; ++v) {
      const auto [u_left, left_rows] = line_at(half, v);    // left in the image: bearing +half
      const auto [u_right, right_rows] = line_at(-half, v);
      if (v <= std::max(left_rows.first, front_top->y()) + 1 || v >= std::min(left_rows.second, front_foot->y()) - 1) continue;
      int lo = -1, hi = -1;
      for (int u = 0; u < cam.width; ++u)
        if (mask.at<std::uint8_t>(v, u)) hi = u, lo = lo < 0 ? u : lo;
      if (std::abs(u_left - std::round(u_left)) > 1e-6) {
        EXPECT_EQ(lo, static_cast<int>(std::ceil(u_left))) << "row " << v;
      }
      if (std::abs(u_right - std::round(u_right)) > 1e-6) {
        EXPECT_EQ(hi, static_cast<int>(std::floor(u_right))) << "row " << v;
      }
      ++rows;
    }
    EXPECT_GT(rows, 3) << "pitch " << pitch;
  }
}

TEST(MirrorBody, GrowsAsTheRobotApproachesTheMirror) {
  const CameraModel cam = Camera(-5.0, 0.5);
  int previous = 0;
  for (double d : {3.0, 2.0, 1.2, 0.7}) {
    const int count = cv::countNonZero(BodyMask(cam, {kMirrorX - d, 0.0, 0.0}));
    EXPECT_GT(count, previous) << "at " << d << " m";
    previous = count;
  }
}

// The body's face turned to the mirror, straight ahead: its grey level is the response to
// body_grey times the irradiance that worlds.md documents for a surface with that normal (the
// ambient plus each light ahead: intensity h^2 cos(light) cos(surface) / distance^2, taken
// 1 cm in front of the face at half the body's height).
TEST(MirrorBody, IsLitLikeOtherSurfacesAndShowsItsGrey) {
  CameraMount mount;
  mount.width = 161;
  mount.height = 121;
  mount.hfov_deg = 60;
  mount.pitch_deg = 0;
  mount.height_m = 0.5;
  const CameraModel cam = mount.Model();
  const Pose2 pose{7.0, 0.0, 0.0};
  const World w = MirrorWorld(", body_grey: 0.5");
  Renderer r(w, cam, Exact());
  const double g = r.Render(pose).at<std::uint8_t>(60, 80);
  const double radius = 0.25, mid = 0.3;
  const Eigen::Vector3d p(pose.x + radius + 0.01, pose.y, mid), normal(1, 0, 0);
  double e = w.ambient;
  for (const Light& l : w.lights) {
    const Eigen::Vector3d to(l.centre.x() - p.x(), l.centre.y() - p.y(), l.z_m - p.z());
    const double d2 = to.squaredNorm(), d = std::sqrt(d2);
    if (to.dot(normal) > 0 && d < 10) e += l.intensity * l.z_m * l.z_m * (to.z() / d) * (to.dot(normal) / d) / d2;
  }
  EXPECT_GT(e, w.ambient * 1.5) << "lights ahead of the body";
  const double expect = 255 * std::pow(0.55 * 0.5 * e, 1 / 2.2);
  EXPECT_NEAR(g, expect, 1.0);
  // The adaptive 4×4 glance path traces mirror pixels in full: the body shows there too.
  RenderOptions o;
  o.supersample = 4;
  o.noise_sigma = 0.0;
  const CameraModel small = Camera(-5.0, 0.5);
  EXPECT_TRUE(BodyMask(small, {kMirrorX - 1.0, 0.0, 0.0}, o).at<std::uint8_t>(20, 20)) << "the body straight ahead at 2 m";
}

TEST(MirrorBody, PrimaryRaysNeverSeeTheBodyAndMirrorlessWorldsAreUnchanged) {
  // A steep camera looks down past the body's edge; without a mirror the body keys change nothing.
  for (double pitch : {-5.0, -40.0}) {
    const CameraModel cam = Camera(pitch, 0.5);
    Renderer a(MirrorWorld(", body_grey: 0.0, body_above_camera_m: 0.0", false), cam, RenderOptions{}),
        b(MirrorWorld(", body_grey: 1.0, body_above_camera_m: 1.0", false), cam, RenderOptions{});
    for (const Pose2& pose : {Pose2{5, 0, 0}, Pose2{10.9, 0.2, 0.1}, Pose2{3, -1.0, 2.0}})
      EXPECT_EQ(cv::norm(a.Render(pose), b.Render(pose), cv::NORM_INF), 0.0) << pitch;
  }
  // With the mirror behind the robot, the body does not show either.
  const CameraModel cam = Camera(-5.0, 0.5);
  Renderer a(MirrorWorld(", body_grey: 0.0"), cam, RenderOptions{}), b(MirrorWorld(", body_grey: 1.0"), cam, RenderOptions{});
  EXPECT_EQ(cv::norm(a.Render({10.5, 0, kPi}), b.Render({10.5, 0, kPi}), cv::NORM_INF), 0.0);
}

TEST(MirrorBody, BadBodyKeysAreRejected) {
  EXPECT_THROW(MirrorWorld(", body_grey: 1.5"), Error);
  EXPECT_THROW(MirrorWorld(", body_above_camera_m: -0.1"), Error);
  EXPECT_THROW(MirrorWorld(", body_colour: 0.3"), Error);
}

}  // namespace
}  // namespace squint::sim
