// PNG plots with OpenCV: axes with "nice" ticks, grid, series, legend and labels.
#include "squint/eval/plot.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "squint/core/error.hpp"
#include "squint/io/atomic_output.hpp"

namespace squint::eval {

std::string PlotOptions::Validate() const {
  std::ostringstream why;
  if (width_px < 200 || height_px < 150) why << "the plot must be at least 200x150 pixels; ";
  if (x_min && x_max && !(*x_min < *x_max)) why << "x_min must be below x_max; ";
  if (y_min && y_max && !(*y_min < *y_max)) why << "y_min must be below y_max; ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

namespace {

// Tableau-like palette, RGB.
constexpr std::array<std::array<std::uint8_t, 3>, 8> kPalette = {{{31, 119, 180},
                                                                  {214, 39, 40},
                                                                  {44, 160, 44},
                                                                  {255, 127, 14},
                                                                  {148, 103, 189},
                                                                  {140, 86, 75},
                                                                  {227, 119, 194},
                                                                  {127, 127, 127}}};

cv::Scalar Bgr(const std::array<std::uint8_t, 3>& rgb) { return cv::Scalar(rgb[2], rgb[1], rgb[0]); }

// A tick step of 1, 2 or 5 × 10^k giving about `target` intervals.
double NiceStep(double span, int target) {
  const double raw = span / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double nice = f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0;
  return nice * mag;
}

std::string TickLabel(double v, double step) {
  if (std::abs(v) < step * 1e-6) v = 0.0;
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  if (std::abs(v) >= 1e5 || (std::abs(v) > 0 && std::abs(v) < 1e-4)) return fmt::format("{:.2g}", v);
  return fmt::format("{:.{}f}", v, decimals);
}

struct Range {
  double lo = 0.0, hi = 1.0;
};

Range FitRange(const std::vector<PlotSeries>& series, bool use_x, std::optional<double> lo,
               std::optional<double> hi) {
  double mn = INFINITY, mx = -INFINITY;
  for (const auto& s : series) {
    const auto& v = use_x ? s.x : s.y;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      mn = std::min(mn, v[i]);
      mx = std::max(mx, v[i]);
    }
  }
  if (!std::isfinite(mn)) mn = 0.0, mx = 1.0;
  if (mx - mn < 1e-12) {
    const double pad = std::max(1e-6, std::abs(mn) * 0.1 + (mn == 0.0 ? 1.0 : 0.0));
    mn -= pad;
    mx += pad;
  } else {
    const double pad = 0.04 * (mx - mn);
    mn -= pad;
    mx += pad;
  }
  return {lo.value_or(mn), hi.value_or(mx)};
}

void DrawDashedLine(cv::Mat& img, cv::Point a, cv::Point b, const cv::Scalar& c, int w) {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const double dash = 8.0;
  for (double t = 0.0; t < len; t += 2 * dash) {
    const double t1 = std::min(len, t + dash);
    cv::Point p(static_cast<int>(a.x + (b.x - a.x) * t / len), static_cast<int>(a.y + (b.y - a.y) * t / len));
    cv::Point q(static_cast<int>(a.x + (b.x - a.x) * t1 / len), static_cast<int>(a.y + (b.y - a.y) * t1 / len));
    cv::line(img, p, q, c, w, cv::LINE_AA);
  }
}

}  // namespace

cv::Mat RenderPlot(const std::vector<PlotSeries>& series, const PlotOptions& options) {
  SQUINT_ENSURE(options.Validate().empty(), options.Validate());
  for (const auto& s : series) SQUINT_ENSURE(s.x.size() == s.y.size(), "plot series '" + s.label + "': x and y differ in length");
  cv::Mat img(options.height_px, options.width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double fs = 0.45;
  const int left = 70, right = 20, top = options.title.empty() ? 20 : 40, bottom = 55;
  cv::Rect area(left, top, options.width_px - left - right, options.height_px - top - bottom);

  Range xr = FitRange(series, true, options.x_min, options.x_max);
  Range yr = FitRange(series, false, options.y_min, options.y_max);
  if (options.equal_aspect) {
    // Widen the tighter axis so one unit spans the same number of pixels on both.
    const double sx = (xr.hi - xr.lo) / area.width, sy = (yr.hi - yr.lo) / area.height;
    if (sx > sy) {
      const double c = 0.5 * (yr.lo + yr.hi), h = 0.5 * sx * area.height;
      yr = {c - h, c + h};
    } else {
      const double c = 0.5 * (xr.lo + xr.hi), h = 0.5 * sy * area.width;
      xr = {c - h, c + h};
    }
  }
  auto px = [&](double x, double y) {
    return cv::Point2d(area.x + (x - xr.lo) / (xr.hi - xr.lo) * area.width,
                       area.y + area.height - (y - yr.lo) / (yr.hi - yr.lo) * area.height);
  };
  auto ipx = [&](double x, double y) {
    const cv::Point2d p = px(x, y);
    return cv::Point(static_cast<int>(std::lround(std::clamp(p.x, -1e5, 1e5))),
                     static_cast<int>(std::lround(std::clamp(p.y, -1e5, 1e5))));
  };

  // Ticks and grid.
  const cv::Scalar grid_colour(225, 225, 225), axis_colour(60, 60, 60);
  const double xstep = NiceStep(xr.hi - xr.lo, 8), ystep = NiceStep(yr.hi - yr.lo, 6);
  for (double x = std::ceil(xr.lo / xstep) * xstep; x <= xr.hi + 1e-9 * xstep; x += xstep) {
    const cv::Point a = ipx(x, yr.lo), b = ipx(x, yr.hi);
    if (options.grid) cv::line(img, a, b, grid_colour, 1);
    cv::line(img, a, a + cv::Point(0, 5), axis_colour, 1);
    const std::string t = TickLabel(x, xstep);
    int base = 0;
    const cv::Size sz = cv::getTextSize(t, font, fs, 1, &base);
    cv::putText(img, t, a + cv::Point(-sz.width / 2, 20), font, fs, axis_colour, 1, cv::LINE_AA);
  }
  for (double y = std::ceil(yr.lo / ystep) * ystep; y <= yr.hi + 1e-9 * ystep; y += ystep) {
    const cv::Point a = ipx(xr.lo, y), b = ipx(xr.hi, y);
    if (options.grid) cv::line(img, a, b, grid_colour, 1);
    cv::line(img, a, a - cv::Point(5, 0), axis_colour, 1);
    const std::string t = TickLabel(y, ystep);
    int base = 0;
    const cv::Size sz = cv::getTextSize(t, font, fs, 1, &base);
    cv::putText(img, t, a + cv::Point(-sz.width - 8, sz.height / 2), font, fs, axis_colour, 1, cv::LINE_AA);
  }
  cv::rectangle(img, area, axis_colour, 1);

  // Series, clipped to the plot area.
  cv::Mat canvas = img(area);
  const cv::Point offset(area.x, area.y);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const PlotSeries& s = series[k];
    const cv::Scalar colour = Bgr(s.rgb.value_or(kPalette[k % kPalette.size()]));
    const bool line = s.style != PlotStyle::kScatter;
    const bool markers = s.style != PlotStyle::kLine;
    std::optional<cv::Point> last;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        last.reset();
        continue;
      }
      const cv::Point p = ipx(s.x[i], s.y[i]) - offset;
      if (line && last) {
        if (s.dashed) DrawDashedLine(canvas, *last, p, colour, s.line_width_px);
        else cv::line(canvas, *last, p, colour, s.line_width_px, cv::LINE_AA);
      }
      if (markers) cv::circle(canvas, p, s.marker_radius_px, colour, cv::FILLED, cv::LINE_AA);
      last = p;
    }
  }

  // Labels and title.
  int base = 0;
  if (!options.title.empty()) {
    const cv::Size sz = cv::getTextSize(options.title, font, 0.6, 1, &base);
    cv::putText(img, options.title, {(options.width_px - sz.width) / 2, 26}, font, 0.6, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  }
  if (!options.x_label.empty()) {
    const cv::Size sz = cv::getTextSize(options.x_label, font, 0.5, 1, &base);
    cv::putText(img, options.x_label, {area.x + (area.width - sz.width) / 2, options.height_px - 10}, font, 0.5,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  if (!options.y_label.empty()) {
    const cv::Size sz = cv::getTextSize(options.y_label, font, 0.5, 1, &base);
    cv::Mat text(sz.height + base + 4, sz.width + 4, CV_8UC3, cv::Scalar(255, 255, 255));
    cv::putText(text, options.y_label, {2, sz.height + 2}, font, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    cv::Mat rotated;
    cv::rotate(text, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int y0 = std::max(0, area.y + (area.height - rotated.rows) / 2);
    const int x0 = 4;
    if (y0 + rotated.rows <= img.rows && x0 + rotated.cols <= img.cols)
      rotated.copyTo(img(cv::Rect(x0, y0, rotated.cols, rotated.rows)));
  }

  // Legend, top right inside the plot area.
  if (options.legend) {
    std::vector<std::size_t> shown;
    int text_w = 0;
    for (std::size_t k = 0; k < series.size(); ++k) {
      if (series[k].label.empty()) continue;
      shown.push_back(k);
      text_w = std::max(text_w, cv::getTextSize(series[k].label, font, fs, 1, &base).width);
    }
    if (!shown.empty()) {
      const int row_h = 18, w = text_w + 44, h = static_cast<int>(shown.size()) * row_h + 8;
      const cv::Rect box(area.x + area.width - w - 8, area.y + 8, w, h);
      cv::rectangle(img, box, cv::Scalar(255, 255, 255), cv::FILLED);
      cv::rectangle(img, box, cv::Scalar(160, 160, 160), 1);
      for (std::size_t r = 0; r < shown.size(); ++r) {
        const PlotSeries& s = series[shown[r]];
        const cv::Scalar colour = Bgr(s.rgb.value_or(kPalette[shown[r] % kPalette.size()]));
        const int yc = box.y + 4 + static_cast<int>(r) * row_h + row_h / 2;
        if (s.style != PlotStyle::kScatter) cv::line(img, {box.x + 6, yc}, {box.x + 30, yc}, colour, 2, cv::LINE_AA);
        if (s.style != PlotStyle::kLine) cv::circle(img, {box.x + 18, yc}, 3, colour, cv::FILLED, cv::LINE_AA);
        cv::putText(img, s.label, {box.x + 36, yc + 5}, font, fs, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
      }
    }
  }
  return img;
}

void WritePng(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  if (image.empty() || !cv::imencode(".png", image, bytes))
    throw Error(path.string() + ": cannot encode the image as PNG");
  io::WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

void WritePlotPng(const std::filesystem::path& path, const std::vector<PlotSeries>& series,
                  const PlotOptions& options) {
  WritePng(path, RenderPlot(series, options));
}

}  // namespace squint::eval
