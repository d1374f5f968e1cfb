// The light line (explore/light_line.hpp) on glances the simulator renders: the lateral offset
// and the heading it reads in built-in corridors, against the pose they were rendered from.
#include "squint/explore/light_line.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "squint/core/angles.hpp"
#include "squint/corridor/glance.hpp"
#include "squint/sim/renderer.hpp"
#include "squint/sim/world.hpp"

namespace squint::explore {
namespace {

struct Reading {
  std::size_t valid = 0, n = 0;
  std::vector<double> e_lat, e_hd;
  double Pct(std::vector<double> v, double q) const {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(std::min<double>(v.size() - 1, q * (v.size() - 1) + 0.5))];
  }
};

// Glances (32×24, 4×4 supersampled, as in the loop) at poses along a corridor (origin, axis yaw),
// at lateral offsets (left positive) and headings relative to its axis.
Reading Sweep(const std::string& world_name, Eigen::Vector2d origin, double axis_deg, double from_m, double to_m) {
  const sim::World world = sim::LoadWorld(world_name);
  const CameraModel cam = world.camera.Model().Scaled(corridor::kGlanceWidth, corridor::kGlanceHeight);
  sim::RenderOptions ro;
  ro.supersample = 4;
  sim::Renderer renderer(world, cam, ro);
  const double height = 2.2;
  const Eigen::Vector2d d(std::cos(DegToRad(axis_deg)), std::sin(DegToRad(axis_deg)));
  const Eigen::Vector2d n(-d.y(), d.x());
  Reading out;
  for (double s = from_m; s <= to_m; s += 1.3)
    for (double lat : {-0.6, -0.3, 0.0, 0.3, 0.6})
      for (double hd : {-10.0, -4.0, 0.0, 4.0, 10.0}) {
        const Eigen::Vector2d p = origin + s * d + lat * n;
        const cv::Mat img = renderer.Render(Pose2{p.x(), p.y(), DegToRad(axis_deg + hd)});
        const LightLine l = FindLightLine(GrayView{img.data, img.cols, img.rows, static_cast<std::ptrdiff_t>(img.step)}, cam);
        ++out.n;
        if (!l.valid) continue;
        ++out.valid;
        // As the loop gates it: a direction within 3 degrees of the heading the explorer holds
        // (here the truth), a lateral offset inside the corridor.
        if (std::abs(RadToDeg(-l.direction_rad) - hd) > 3.0 || std::abs(l.LateralM(height)) > 0.9) continue;
        out.e_lat.push_back(std::abs(l.LateralM(height) - lat));
        out.e_hd.push_back(std::abs(RadToDeg(-l.direction_rad) - hd));
      }
  std::printf("%s axis %.0f: valid %zu of %zu, %zu within the loop's gates; lateral error median %.2f p90 %.2f max %.2f m; heading error median %.1f p90 %.1f max %.1f deg\n",
              world_name.c_str(), axis_deg, out.valid, out.n, out.e_lat.size(), out.Pct(out.e_lat, 0.5), out.Pct(out.e_lat, 0.9),
              out.Pct(out.e_lat, 1.0), out.Pct(out.e_hd, 0.5), out.Pct(out.e_hd, 0.9), out.Pct(out.e_hd, 1.0));
  return out;
}

// Centre rows of lights (default's middle corridor: carpet; its south corridor: tiles, doors):
// most glances give a line, and as the loop gates them (direction within 3 degrees of the held
// heading, offset within 0.9 m) they are right to about a tenth of a metre. Measured: middle 176
// of 325 glances, lateral error p90 0.09 m, worst 0.30 m; south 227 of 550, p90 0.11, worst 0.18.
TEST(LightLineSim, CentreRowsGiveTheLateralOffset) {
  for (const Reading& r : {Sweep("default", {0.0, 12.5}, 0.0, 4.0, 20.0), Sweep("default", {0.0, 0.0}, 0.0, 4.0, 32.0)}) {
    EXPECT_GT(r.e_lat.size(), r.n / 3);
    EXPECT_LT(r.Pct(r.e_lat, 0.9), 0.15);
    EXPECT_LT(r.Pct(r.e_lat, 1.0), 0.4);
    EXPECT_LT(r.Pct(r.e_hd, 0.9), 1.5);
  }
}

// Two side rows (default's east corridor, corridor-2) are not supported: almost no glance passes,
// and what does may be one row read as the centre (printed, not asserted beyond that).
TEST(LightLineSim, SideRowsSeldomPass) {
  for (const Reading& r : {Sweep("default", {40.0, 0.0}, 90.0, 3.0, 20.0), Sweep("corridor-2", {0.0, 0.0}, 0.0, 2.0, 20.0)})
    EXPECT_LT(r.e_lat.size(), r.n / 50);
  Sweep("default", {40.0, 25.0}, 180.0, 4.0, 32.0);  // north: speckle floor, every 4th light off
}

}  // namespace
}  // namespace squint::explore
