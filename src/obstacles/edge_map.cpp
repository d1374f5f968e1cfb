// Edge map (obstacle paper §5.1): horizontal Gaussian-derivative filter + hysteresis.
#include "squint/obstacles/edge_map.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "squint/core/error.hpp"

namespace squint::obstacles {

std::string EdgeMapOptions::Validate() const {
  if (!(sigma_px >= 0.3 && sigma_px <= 10.0)) return "edges.sigma_px must be in [0.3, 10]";
  if (!(low_threshold > 0.0)) return "edges.low_threshold must be positive";
  if (!(high_threshold >= low_threshold)) return "edges.high_threshold must be >= edges.low_threshold";
  return {};
}

EdgeMapper::EdgeMapper(EdgeMapOptions options) : options_(options) {
  const std::string problem = options_.Validate();
  SQUINT_ENSURE(problem.empty(), problem);
  // Derivative of a Gaussian, sampled on [-3 sigma, 3 sigma]. Scaled so that the positive lobe
  // sums to 1: convolving an ideal step of height h then gives h at the step.
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * options_.sigma_px)));
  kernel_.create(1, 2 * radius + 1, CV_32F);
  double positive = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    const double x = static_cast<double>(i);
    // cv::filter2D correlates, so k(i) multiplies I(u + i): k(i) = -g'(i) = i g(i) / sigma^2
    // gives dI/du > 0 for intensity increasing to the right.
    const double v = x * std::exp(-0.5 * x * x / (options_.sigma_px * options_.sigma_px));
    kernel_.at<float>(0, i + radius) = static_cast<float>(v);
    if (v > 0) positive += v;
  }
  kernel_ /= positive;
  kernel_t_ = kernel_.t();
}

const cv::Mat& EdgeMapper::Compute(const cv::Mat& gray) {
  SQUINT_ENSURE(gray.type() == CV_8UC1 && !gray.empty(), "EdgeMapper::Compute needs a non-empty 8-bit grey image");
  cv::filter2D(gray, gradient_, CV_32F, kernel_, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
  gradient_ = cv::abs(gradient_);  // in place for a MatExpr of the same size and type
  Hysteresis(gradient_, edges_);
  if (options_.base_edges) {
    cv::filter2D(gray, gradient_v_, CV_32F, kernel_t_, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
    gradient_v_ = cv::abs(gradient_v_);
    Hysteresis(gradient_v_, base_edges_);
  } else {
    base_edges_.release();
  }
  return edges_;
}

void EdgeMapper::Hysteresis(const cv::Mat& gradient, cv::Mat& edges) {
  const int w = gradient.cols, h = gradient.rows;
  edges.create(h, w, CV_8U);
  edges.setTo(0);
  stack_.clear();
  const float lo = static_cast<float>(options_.low_threshold);
  const float hi = static_cast<float>(options_.high_threshold);
  // Seeds: every pixel above the high threshold.
  for (int v = 0; v < h; ++v) {
    const float* g = gradient.ptr<float>(v);
    std::uint8_t* e = edges.ptr<std::uint8_t>(v);
    for (int u = 0; u < w; ++u) {
      if (g[u] > hi) {
        e[u] = 255;
        stack_.push_back(v * w + u);
      }
    }
  }
  // Grow through 8-connected pixels above the low threshold (Canny's hysteresis): a weak pixel
  // is an edge when it is connected to a strong one.
  while (!stack_.empty()) {
    const int idx = stack_.back();
    stack_.pop_back();
    const int u0 = idx % w, v0 = idx / w;
    for (int dv = -1; dv <= 1; ++dv) {
      const int v = v0 + dv;
      if (v < 0 || v >= h) continue;
      const float* g = gradient.ptr<float>(v);
      std::uint8_t* e = edges.ptr<std::uint8_t>(v);
      for (int du = -1; du <= 1; ++du) {
        const int u = u0 + du;
        if (u < 0 || u >= w || e[u] != 0) continue;
        if (g[u] > lo) {
          e[u] = 255;
          stack_.push_back(v * w + u);
        }
      }
    }
  }
}

}  // namespace squint::obstacles
