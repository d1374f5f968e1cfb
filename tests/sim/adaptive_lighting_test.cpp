// Adaptive glance shading of plain one-surface pixels uses the light map's mean over the pixel's
// footprint (summed-area tables): no single pixel may stray far from full 4×4 supersampling,
// even where a pool of light lies between its corners (wide wall footprints far down a
// corridor). The corner-lighting shading it replaced reached 70 grey levels on these views.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "squint/sim/renderer.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {
namespace {

TEST(AdaptiveLighting, NoPixelStraysFarFromFullSupersampling) {
  const World w = LoadWorld("default");
  RenderOptions full;
  full.supersample = 4;
  full.noise_sigma = 0.0;
  full.adaptive = false;
  RenderOptions fast = full;
  fast.adaptive = true;
  const CameraModel cam = w.camera.Model().Scaled(32, 24);
  Renderer exact(w, cam, full), adaptive(w, cam, fast);
  double worst = 0, total = 0;
  int images = 0;
  for (int i = 0; i < 48; ++i) {  // down the south corridor and up the east one, turning a little
    const double yaw = 0.35 * std::sin(i * 0.7);
    const Pose2 pose = i < 32 ? Pose2{1.0 + i * 1.2, 0.3 * std::sin(i * 0.3), yaw}
                              : Pose2{40.0 + 0.3 * std::sin(i * 0.3), (i - 32) * 0.75, 1.5708 + yaw};
    const cv::Mat a = exact.Render(pose), b = adaptive.Render(pose);
    const double worst_here = cv::norm(a, b, cv::NORM_INF);
    EXPECT_LE(worst_here, 32) << "pose " << i;
    worst = std::max(worst, worst_here);
    total += cv::norm(a, b, cv::NORM_L1) / a.total();
    ++images;
  }
  std::printf("adaptive vs full 4x4 over %d views: mean %.3f, worst pixel %.0f grey levels\n", images, total / images, worst);
  EXPECT_LE(total / images, 1.0);
}

}  // namespace
}  // namespace squint::sim
