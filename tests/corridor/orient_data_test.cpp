// The heading targets on the ray-traced dev corridors (../shared/data/orient-*), default options,
// no calibration, no gate. Skips when the data is absent. Asserts the targets (estimate
// on >= 95% of frames, fused RMSE <= 6 deg, right sign on >= 90% of frames with |heading| >= 5)
// and a regression guard on the median error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "squint/corridor/perceiver.hpp"
#include "squint/io/sequence.hpp"

namespace squint::corridor {
namespace {

namespace fs = std::filesystem;

TEST(OrientData, CoverageAndMedianErrorOnDevCorridors) {
  const fs::path root = SQUINT_SHARED_DATA_DIR;
  std::vector<fs::path> dirs;
  if (fs::is_directory(root))
    for (const auto& e : fs::directory_iterator(root))
      if (e.is_directory() && e.path().filename().string().rfind("orient-", 0) == 0) dirs.push_back(e.path());
  if (dirs.empty()) GTEST_SKIP() << "no orient-* sequences under " << root;
  std::sort(dirs.begin(), dirs.end());
  CorridorOptions options;
  options.gate.enabled = false;
  std::vector<double> abs_err;
  double sq = 0.0;
  int frames = 0, sign_frames = 0, sign_ok = 0;
  for (const fs::path& dir : dirs) {
    const io::Sequence seq = io::Sequence::Read(dir);
    Perceiver perceiver(options, seq.Camera());
    for (std::size_t i = 0; i < seq.Size(); ++i) {
      const cv::Mat img = seq.LoadImage(i);
      const PerceptionResult r =
          perceiver.Process(GrayView{img.data, img.cols, img.rows, static_cast<std::ptrdiff_t>(img.step[0])}, std::nullopt, 0.5);
      const auto gt = seq.Frames()[i].gt.heading_deg;
      ASSERT_TRUE(gt.has_value());
      ++frames;
      if (std::abs(*gt) >= 5.0) ++sign_frames;
      if (!r.heading_deg) continue;
      ASSERT_TRUE(std::isfinite(*r.heading_deg));
      const double e = *r.heading_deg - *gt;
      abs_err.push_back(std::abs(e));
      sq += e * e;
      if (std::abs(*gt) >= 5.0 && (*r.heading_deg > 0) == (*gt > 0)) ++sign_ok;
    }
  }
  ASSERT_GT(frames, 0);
  std::sort(abs_err.begin(), abs_err.end());
  const double coverage = static_cast<double>(abs_err.size()) / frames;
  const double median = abs_err.empty() ? 1e9 : abs_err[abs_err.size() / 2];
  std::printf("orient-*: %d frames, estimate on %.1f%%, RMSE %.2f deg, median %.2f deg, sign %.1f%%\n", frames,
              100.0 * coverage, std::sqrt(sq / std::max<std::size_t>(1, abs_err.size())), median,
              100.0 * sign_ok / std::max(1, sign_frames));
  EXPECT_GE(coverage, 0.95);
  EXPECT_LE(std::sqrt(sq / std::max<std::size_t>(1, abs_err.size())), 6.0);
  EXPECT_GE(static_cast<double>(sign_ok) / std::max(1, sign_frames), 0.90);
  EXPECT_LE(median, 2.0);
}

}  // namespace
}  // namespace squint::corridor
