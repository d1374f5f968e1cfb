// Renderer geometry and determinism: floor ranges against the camera model's analytic floor
// point, wall and obstacle ranges against known distances, labels consistent with range, and
// noise keyed by seed and frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/sim/renderer.hpp"
#include "squint/sim/world.hpp"
#include "../../src/sim/textures.hpp"  // internal: the box-filtered texture tables

namespace squint::sim {
namespace {

RenderOptions Exact() {
  RenderOptions o;
  o.supersample = 1;
  o.noise_sigma = 0.0;
  return o;
}

// An odd-sized camera so that the centre pixel's ray is the optical axis.
CameraModel Camera(double pitch_deg, double height_m = 0.5) {
  CameraMount m;
  m.width = 41;
  m.height = 31;
  m.hfov_deg = 60;
  m.pitch_deg = pitch_deg;
  m.height_m = height_m;
  return m.Model();
}

World Hall() {
  return ParseWorld(
      "format: squint-world/1\n"
      "corridors: [{from: [0, 0], to: [60, 0], width_m: 30, height_m: 3}]\n"
      "robot: {start: [5, 0, 0]}\n",
      "hall.yaml");
}

TEST(Renderer, FloorPixelsMeetTheFloorAtTheAnalyticDistance) {
  const World w = Hall();
  for (double pitch : {-5.0, -12.0}) {
    const CameraModel cam = Camera(pitch);
    Renderer r(w, cam, Exact());
    cv::Mat label, range;
    r.Render({5, 0, DegToRad(7)}, &label, &range);
    int checked = 0;
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        const auto fp = cam.FloorPoint({u, v});
        if (!fp || fp->norm() > 20) continue;  // within the hall
        const double expect = std::sqrt(fp->squaredNorm() + cam.height_m * cam.height_m);
        EXPECT_EQ(label.at<std::uint8_t>(v, u), kLabelFloor) << u << "," << v;
        EXPECT_NEAR(range.at<float>(v, u), expect, 1e-5 * expect) << u << "," << v;
        ++checked;
      }
    EXPECT_GT(checked, 200);
  }
}

TEST(Renderer, OpticalAxisMeetsTheEndWallAtItsDistance) {
  const World w = ParseWorld(
      "format: squint-world/1\ncorridors: [{from: [0, 0], to: [20, 0], width_m: 3, height_m: 3}]\n", "end.yaml");
  const CameraModel cam = Camera(0.0, 1.0);
  Renderer r(w, cam, Exact());
  cv::Mat label, range;
  // End wall at x = 21.5; robot at x = 4, y = 0.2, facing it.
  r.Render({4, 0.2, 0}, &label, &range);
  EXPECT_NEAR(range.at<float>(15, 20), 17.5, 1e-5);
  EXPECT_EQ(label.at<std::uint8_t>(15, 20), kLabelStanding);
  // Turned by 3 degrees the axis meets the same wall (at y = 1.12) 17.5 / cos(3) away.
  r.Render({4, 0.2, DegToRad(3)}, &label, &range);
  EXPECT_NEAR(range.at<float>(15, 20), 17.5 / std::cos(DegToRad(3)), 1e-4);
}

// Every pixel's range against an independent cast of its central ray (World::CastWalls over all
// walls, the floor and ceiling planes), in worlds without obstacles and from poses turned every
// way, so that walls just outside the view's wedge (skipped per frame) and just inside it meet
// the image border columns: the bearing table must lose no wall.
TEST(Renderer, RangesEqualAnIndependentCastOfEveryPixelsRay) {
  int checked = 0, worlds = 0;
  for (const std::string& name : BuiltinWorldNames()) {
    const World w = LoadWorld(name);
    if (!w.obstacles.empty()) continue;
    ++worlds;
    const CameraModel cam = w.camera.Model().Scaled(64, 48);
    Renderer r(w, cam, Exact());
    for (int k = 0; k < 24; ++k) {
      const Pose2 pose{w.start.x + 0.37 * k * std::cos(w.start.yaw), w.start.y + 0.37 * k * std::sin(w.start.yaw),
                       w.start.yaw + DegToRad(15.0 * k + 0.3)};
      cv::Mat label, range;
      r.Render(pose, &label, &range);
      const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
      for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
          const Eigen::Vector3d d = cam.PixelRayRobot({u, v});
          const double h = std::hypot(d.x(), d.y()), slope = d.z() / h;
          const Eigen::Vector2d dir((c * d.x() - s * d.y()) / h, (s * d.x() + c * d.y()) / h);
          double t = 1e30;  // horizontal distance
          bool floor = false;
          if (const auto hit = w.CastWalls({pose.x, pose.y}, dir)) t = hit->first;
          if (slope < 0 && cam.height_m / -slope < t) t = cam.height_m / -slope, floor = true;
          const double ceiling = w.CeilingAt({pose.x, pose.y});
          if (slope > 0 && (ceiling - cam.height_m) / slope < t) t = (ceiling - cam.height_m) / slope;
          ASSERT_LT(t, 1e29) << name << " " << u << "," << v;
          const double expect = t * std::sqrt(1 + slope * slope);
          EXPECT_NEAR(range.at<float>(v, u), expect, 1e-4 * expect) << name << " pose " << k << " pixel " << u << "," << v;
          EXPECT_EQ(label.at<std::uint8_t>(v, u), floor ? kLabelFloor : kLabelStanding) << name << " pose " << k << " pixel " << u << "," << v;
          ++checked;
        }
    }
  }
  EXPECT_GE(worlds, 5);
  EXPECT_EQ(checked, worlds * 24 * 64 * 48);
}

TEST(Renderer, BoxInFrontIsSeenAtItsFaceDistance) {
  const World w = ParseWorld(
      "format: squint-world/1\ncorridors: [{from: [0, 0], to: [20, 0], width_m: 4, height_m: 3}]\n"
      "obstacles: [{type: box, at: [6, 0], size: [0.4, 1.0, 1.5]}]\n",
      "box.yaml");
  const CameraModel cam = Camera(0.0, 1.0);
  Renderer r(w, cam, Exact());
  cv::Mat label, range;
  r.Render({2, 0, 0}, &label, &range);
  EXPECT_NEAR(range.at<float>(15, 20), 3.8, 1e-5);  // face at x = 5.8
  EXPECT_EQ(label.at<std::uint8_t>(15, 20), kLabelStanding);
}

// A cylinder is the same whatever its yaw (chair legs inherit the chair's): every pixel whose ray
// passes well inside one of two columns, found by an independent ray-circle cast in the world
// frame, sees it at the analytic distance, labelled standing.
TEST(Renderer, ColumnIsSeenAtItsDistanceWhateverItsYaw) {
  for (const double yaw_deg : {0.0, 37.0, 90.0, 180.0}) {
    const std::string doc =
        "format: squint-world/1\ncorridors: [{from: [0, 0], to: [20, 0], width_m: 4, height_m: 3}]\n"
        "obstacles: [{type: column, at: [6, 0.3], radius_m: 0.25, height_m: 1.5, yaw_deg: " +
        std::to_string(yaw_deg) + "},\n"
        "            {type: column, at: [5, -1.1], radius_m: 0.1, height_m: 1.5, yaw_deg: " +
        std::to_string(yaw_deg) + "}]\n";
    const World w = ParseWorld(doc, "columns.yaml");
    const CameraModel cam = Camera(-5.0, 1.0);
    Renderer r(w, cam, Exact());
    const Pose2 pose{2, 0.1, DegToRad(3)};
    cv::Mat label, range;
    r.Render(pose, &label, &range);
    const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
    int inside = 0;
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        const Eigen::Vector3d d = cam.PixelRayRobot({u, v});
        const double h = std::hypot(d.x(), d.y()), slope = d.z() / h;
        const Eigen::Vector2d dir((c * d.x() - s * d.y()) / h, (s * d.x() + c * d.y()) / h);
        for (const Obstacle& ob : w.obstacles) {
          const Eigen::Vector2d rel = Eigen::Vector2d(pose.x, pose.y) - ob.centre;
          const double b = rel.dot(dir), miss = std::abs(rel.x() * dir.y() - rel.y() * dir.x());
          if (b > 0 || miss > 0.8 * ob.radius) continue;  // not well inside the silhouette
          const double t = -b - std::sqrt(b * b - (rel.squaredNorm() - ob.radius * ob.radius));
          const double z = cam.height_m + slope * t;
          if (z < 0.05 || z > ob.z1 - 0.05) continue;
          EXPECT_NEAR(range.at<float>(v, u), t * std::sqrt(1 + slope * slope), 1e-4)
              << "yaw " << yaw_deg << " pixel " << u << "," << v;
          EXPECT_EQ(label.at<std::uint8_t>(v, u), kLabelStanding) << "yaw " << yaw_deg << " pixel " << u << "," << v;
          ++inside;
        }
      }
    EXPECT_GT(inside, 40) << "yaw " << yaw_deg;
  }
}

TEST(Renderer, LabelsAgreeWithRangeEverywhere) {
  for (const char* name : {"obstacle-course", "default", "corridor-9"}) {
    const World w = LoadWorld(name);
    const CameraModel cam = w.camera.Model();
    RenderOptions o;
    o.supersample = 2;
    Renderer r(w, cam, o);
    cv::Mat label, range;
    r.Render(w.start, &label, &range);
    int floor = 0, standing = 0;
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        const Eigen::Vector3d p = cam.RobotCameraCentre() + cam.PixelRayRobot({u, v}) * range.at<float>(v, u);
        ASSERT_TRUE(std::isfinite(p.z()));
        if (label.at<std::uint8_t>(v, u) == kLabelFloor) {
          EXPECT_NEAR(p.z(), 0.0, 1e-4) << name << " " << u << "," << v;
          ++floor;
        } else {
          // Something standing: above the floor, and met before the floor would be.
          const Eigen::Vector3d d = cam.PixelRayRobot({u, v});
          const double floor_range = d.z() < 0 ? cam.height_m / -d.z() : 1e30;
          EXPECT_GT(p.z(), -1e-4) << name << " " << u << "," << v;
          EXPECT_LT(range.at<float>(v, u), floor_range * (1 + 1e-6)) << name << " " << u << "," << v;
          ++standing;
        }
      }
    EXPECT_GT(floor, cam.width * cam.height / 10) << name;
    EXPECT_GT(standing, cam.width * cam.height / 10) << name;
  }
}

TEST(Renderer, ObstacleCourseShowsObstaclesStandingOnTheFloor) {
  const World w = LoadWorld("obstacle-course");
  const CameraModel cam = w.camera.Model();
  Renderer r(w, cam, Exact());
  cv::Mat label;
  r.Render(w.start, &label);
  // The box at (3.5, 0.9) (0.5 high) stands 2.5 m ahead, left: project its front-bottom centre.
  const auto px = cam.Project({3.5 - 0.25 - 1.0, 0.9, 0.2});
  ASSERT_TRUE(px);
  EXPECT_EQ(label.at<std::uint8_t>(static_cast<int>(std::lround(px->y())), static_cast<int>(std::lround(px->x()))),
            kLabelStanding);
  // The paper sheet at (2.5, -0.3) is floor.
  const auto pp = cam.Project({2.5 - 1.0, -0.3, 0.0});
  ASSERT_TRUE(pp);
  EXPECT_EQ(label.at<std::uint8_t>(static_cast<int>(std::lround(pp->y())), static_cast<int>(std::lround(pp->x()))),
            kLabelFloor);
}

TEST(Renderer, DeterministicPerSeedAndFrame) {
  const World w = LoadWorld("corridor-0");
  RenderOptions o;
  o.noise_sigma = 3.0;
  o.seed = 5;
  Renderer a(w, w.camera.Model().Scaled(64, 48), o), b(w, w.camera.Model().Scaled(64, 48), o);
  const cv::Mat ia = a.Render(w.start, nullptr, nullptr, 3), ib = b.Render(w.start, nullptr, nullptr, 3);
  EXPECT_EQ(cv::norm(ia, ib, cv::NORM_INF), 0.0);
  const cv::Mat next = a.Render(w.start, nullptr, nullptr, 4);
  EXPECT_GT(cv::norm(ia, next, cv::NORM_L1), 0.0);
  o.seed = 6;
  Renderer c(w, w.camera.Model().Scaled(64, 48), o);
  EXPECT_GT(cv::norm(ia, c.Render(w.start, nullptr, nullptr, 3), cv::NORM_L1), 0.0);
}

TEST(Renderer, LightsAreTheBrightestAndTheImageIsNotFlat) {
  for (const std::string& name : BuiltinWorldNames()) {
    const World w = LoadWorld(name);
    Renderer r(w, w.camera.Model().Scaled(32, 24), RenderOptions{});
    const cv::Mat img = r.Render(w.start);
    double lo, hi;
    cv::minMaxLoc(img, &lo, &hi);
    EXPECT_GE(hi - lo, 60) << name;
    cv::Scalar mean, sd;
    cv::meanStdDev(img, mean, sd);
    EXPECT_GT(sd[0], 10) << name;
  }
}

// Adaptive supersampling against the full n×n supersampling, on every built-in world from its
// start and turned ±25°, and from further poses down the default building. The yardstick is
// the full 4×4 image's own sampling error, measured against full 8×8 supersampling: the
// adaptive image must stay within 2 grey levels mean absolute difference of the 4×4 one on
// every view and within 1 on average, and on average no further from it than the 4×4 image
// is from the 8×8 one (box-filtered textures replace 16 point samples of the same texels).
TEST(Renderer, AdaptiveSupersamplingStaysCloseToFullSupersampling) {
  RenderOptions full;
  full.supersample = 4;
  full.noise_sigma = 0.0;
  full.adaptive = false;
  RenderOptions fine = full;
  fine.supersample = 8;
  RenderOptions fast = full;
  fast.adaptive = true;
  double total = 0, total_ref = 0;
  int images = 0;
  for (const std::string& name : BuiltinWorldNames()) {
    const World w = LoadWorld(name);
    const CameraModel cam = w.camera.Model().Scaled(32, 24);
    Renderer exact(w, cam, full), reference(w, cam, fine), adaptive(w, cam, fast);
    std::vector<Pose2> poses;
    for (double turn : {0.0, 0.45, -0.45}) poses.push_back({w.start.x, w.start.y, w.start.yaw + turn});
    if (name == "default")
      for (const Pose2& p : {Pose2{9.0, 0.4, 0.2}, Pose2{19.5, -0.3, -0.3}, Pose2{40.2, 6.0, 1.7}, Pose2{20.0, -6.0, -1.5},
                             Pose2{13.0, 12.2, 3.0}, Pose2{30.0, 25.3, 2.9}})
        poses.push_back(p);
    for (const Pose2& pose : poses) {
      const cv::Mat a = exact.Render(pose), b = adaptive.Render(pose), c = reference.Render(pose);
      const double mae = cv::norm(a, b, cv::NORM_L1) / a.total();
      const double mae_ref = cv::norm(a, c, cv::NORM_L1) / a.total();
      EXPECT_LE(mae, 2.0) << name << " at " << pose.x << "," << pose.y << "," << pose.yaw;
      total += mae;
      total_ref += mae_ref;
      ++images;
    }
  }
  std::printf("mean absolute difference to 4x4 over %d views: adaptive %.3f, 8x8 %.3f grey levels\n", images,
              total / images, total_ref / images);
  EXPECT_LE(total / images, 1.0);
  EXPECT_LE(total, total_ref);
}

TEST(Renderer, AdaptiveSupersamplingIsDeterministicAndKeepsExactRanges) {
  const World w = LoadWorld("default");
  RenderOptions o;
  o.supersample = 4;
  o.noise_sigma = 2.0;
  const CameraModel cam = w.camera.Model().Scaled(32, 24);
  Renderer a(w, cam, o), b(w, cam, o);
  o.adaptive = false;
  Renderer full(w, cam, o);
  const Pose2 pose{19.5, -0.3, -0.3};
  cv::Mat la, ra, lf, rf;
  const cv::Mat ia = a.Render(pose, &la, &ra, 7);
  a.Render({9.0, 0.4, 0.2}, nullptr, nullptr, 8);  // state from another frame must not leak
  EXPECT_EQ(cv::norm(ia, a.Render(pose, nullptr, nullptr, 7), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(ia, b.Render(pose, nullptr, nullptr, 7), cv::NORM_INF), 0.0);
  // Labels and ranges come from the same traced central rays either way.
  full.Render(pose, &lf, &rf, 7);
  EXPECT_EQ(cv::norm(la, lf, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(ra, rf, cv::NORM_INF), 0.0);
}

// The summed-area box mean against summing the texels one by one, for boxes anywhere (negative
// coordinates, across the table's period, wider than it, a single texel).
TEST(Renderer, TextureBoxMeanEqualsTheTexelAverage) {
  Material m;
  m.texture = Texture::kCarpet;
  m.scale_m = 0.37;
  m.contrast = 0.6;
  const detail::TextureTable t = detail::MakeTexture(m, 3);
  constexpr int kN = detail::kTexSize;
  auto brute = [&](double u0, double u1, double v0, double v1) {
    const auto x0 = static_cast<long>(std::floor(u0 * t.inv_texel_m)), y0 = static_cast<long>(std::floor(v0 * t.inv_texel_m));
    const long x1 = std::min(static_cast<long>(std::floor(u1 * t.inv_texel_m)) + 1, x0 + kN);
    const long y1 = std::min(static_cast<long>(std::floor(v1 * t.inv_texel_m)) + 1, y0 + kN);
    double sum = 0;
    for (long y = y0; y < y1; ++y)
      for (long x = x0; x < x1; ++x) sum += t.texels[((y % kN + kN) % kN) * kN + (x % kN + kN) % kN];
    return sum / static_cast<double>((x1 - x0) * (y1 - y0)) * t.gain;
  };
  const double boxes[][4] = {{0.01, 0.02, 0.01, 0.02},     {0.1, 0.3, 0.05, 0.5},   {-0.93, -0.41, 2.2, 2.31},
                             {0.70, 0.80, -0.05, 0.05},    {-3.0, 5.0, -0.2, 0.1},  {11.37, 11.9, -7.7, -7.05},
                             {0.3333, 0.3334, 0.5, 0.5}};
  for (const auto& b : boxes) EXPECT_NEAR(t.BoxMean(b[0], b[1], b[2], b[3]), brute(b[0], b[1], b[2], b[3]), 1e-5) << b[0] << " " << b[2];
}

TEST(Renderer, BadOptionsAreRejected) {
  const World w = Hall();
  RenderOptions o;
  o.supersample = 0;
  EXPECT_THROW(Renderer(w, Camera(0), o), Error);
  CameraModel bad = Camera(0);
  bad.fx = 0;
  EXPECT_THROW(Renderer(w, bad, RenderOptions{}), Error);
}

}  // namespace
}  // namespace squint::sim
