// Plot rendering: size, colours where the data says, legend and file output.
#include "squint/eval/plot.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

namespace squint::eval {
namespace {

TEST(PlotTest, RendersRequestedSizeAndDrawsSeriesInItsColour) {
  PlotOptions opt;
  opt.width_px = 400;
  opt.height_px = 300;
  opt.x_min = 0.0;
  opt.x_max = 1.0;
  opt.y_min = 0.0;
  opt.y_max = 1.0;
  opt.legend = false;
  opt.grid = false;
  PlotSeries s;
  s.x = {0.0, 1.0};
  s.y = {0.5, 0.5};
  s.rgb = std::array<std::uint8_t, 3>{255, 0, 0};
  s.line_width_px = 3;
  const cv::Mat img = RenderPlot({s}, opt);
  ASSERT_EQ(img.cols, 400);
  ASSERT_EQ(img.rows, 300);
  ASSERT_EQ(img.type(), CV_8UC3);
  // The plot area spans rows [20, 245); y = 0.5 sits in its middle row, about 132.
  int red_rows = 0;
  for (int r = 0; r < img.rows; ++r) {
    const cv::Vec3b p = img.at<cv::Vec3b>(r, 200);
    if (p[2] > 200 && p[1] < 80 && p[0] < 80) {
      ++red_rows;
      EXPECT_NEAR(r, 20 + (245 - 20) / 2, 3);
    }
  }
  EXPECT_GE(red_rows, 1);
}

TEST(PlotTest, WritesAReadablePng) {
  const auto path = std::filesystem::temp_directory_path() / "squint_plot_test.png";
  PlotSeries a{"roc", {0, 0.1, 1}, {0, 0.9, 1}, PlotStyle::kLineAndMarkers, std::nullopt};
  PlotSeries b{"scatter", {0.2, 0.4}, {0.3, 0.6}, PlotStyle::kScatter, std::nullopt};
  PlotOptions opt;
  opt.title = "title";
  opt.x_label = "x";
  opt.y_label = "y";
  opt.equal_aspect = true;
  WritePlotPng(path, {a, b}, opt);
  const cv::Mat back = cv::imread(path.string());
  EXPECT_EQ(back.cols, opt.width_px);
  EXPECT_EQ(back.rows, opt.height_px);
  std::filesystem::remove(path);
}

TEST(PlotTest, EmptyAndDegenerateDataStillRender) {
  PlotOptions opt;
  EXPECT_NO_THROW(RenderPlot({}, opt));
  PlotSeries s{"one point", {2.0}, {2.0}, PlotStyle::kScatter, std::nullopt};
  PlotSeries nan{"nan", {0.0, std::nan("")}, {1.0, 2.0}, PlotStyle::kLine, std::nullopt};
  EXPECT_NO_THROW(RenderPlot({s, nan}, opt));
}

}  // namespace
}  // namespace squint::eval
