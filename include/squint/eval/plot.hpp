// Small PNG plots for reports: line and scatter series on linear axes with ticks, labels, a title
// and a legend, drawn with OpenCV (ROC curves, error-vs-truth plots, exploration traces).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace squint::eval {

enum class PlotStyle { kLine, kScatter, kLineAndMarkers };

struct PlotSeries {
  std::string label;  // legend text; empty = not in the legend
  std::vector<double> x;
  std::vector<double> y;  // same length as x; non-finite points are skipped (lines break there)
  PlotStyle style = PlotStyle::kLine;
  // RGB colour; none = the next colour of a fixed palette (by series index).
  std::optional<std::array<std::uint8_t, 3>> rgb;
  int line_width_px = 2;
  int marker_radius_px = 3;
  bool dashed = false;
};

struct PlotOptions {
  std::string title;
  std::string x_label;
  std::string y_label;
  int width_px = 800;
  int height_px = 600;
  // Axis ranges; none = fitted to the data with a small margin.
  std::optional<double> x_min, x_max, y_min, y_max;
  // Same scale on both axes (maps, trajectories).
  bool equal_aspect = false;
  bool grid = true;
  bool legend = true;

  std::string Validate() const;
};

// Renders the plot into an 8-bit BGR image of width_px × height_px. Invalid options or series of
// mismatched lengths: SQUINT_ENSURE (programmer errors).
cv::Mat RenderPlot(const std::vector<PlotSeries>& series, const PlotOptions& options);

// Renders and writes a PNG atomically. Throws squint::Error naming the file when it cannot be written.
void WritePlotPng(const std::filesystem::path& path, const std::vector<PlotSeries>& series,
                  const PlotOptions& options);

// Encodes any 8-bit image as PNG and writes it atomically (for overlays drawn elsewhere).
void WritePng(const std::filesystem::path& path, const cv::Mat& image);

}  // namespace squint::eval
