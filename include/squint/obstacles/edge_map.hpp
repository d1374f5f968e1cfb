// Edge map for obstacle outlines (obstacle paper §5.1): one horizontal 1-D Gaussian-derivative
// convolution (vertical edges), then hysteresis thresholding. Beyond the paper, optionally the same
// with the kernel turned vertical (horizontal edges: where an obstacle's base meets the floor).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace squint::obstacles {

struct EdgeMapOptions {
  // Standard deviation of the Gaussian whose derivative is the horizontal kernel (pixels).
  double sigma_px = 1.0;
  // Hysteresis thresholds on |dI/du| (paper §6.1: low 40, high 50). The kernel is scaled so that
  // an ideal step of h grey levels gives a response of h at the step, so the thresholds read as
  // the intensity jump across a vertical edge, in grey levels.
  double low_threshold = 40.0;
  double high_threshold = 50.0;
  // Beyond the paper: also compute the horizontal-edge map (the same kernel and thresholds on
  // |dI/dv|), which the outline tracer follows along obstacle bases.
  bool base_edges = true;

  // Empty when valid, otherwise what is wrong.
  std::string Validate() const;
};

// Computes edge maps into buffers that are reused from frame to frame (no allocation once the
// image size is stable). Not thread-safe; use one per thread.
class EdgeMapper {
 public:
  explicit EdgeMapper(EdgeMapOptions options = {});

  // `gray` must be 8-bit single channel. Returns a CV_8U mask of the same size: 255 on edge
  // pixels, 0 elsewhere. The reference stays valid until the next call.
  const cv::Mat& Compute(const cv::Mat& gray);

  // The last horizontal-edge mask (|dI/dv| with the same hysteresis); empty when base_edges is off.
  const cv::Mat& BaseEdges() const { return base_edges_; }
  // The last |dI/du| response (CV_32F), for drawing and tests.
  const cv::Mat& Gradient() const { return gradient_; }
  const EdgeMapOptions& Options() const { return options_; }
  // The 1-D kernel (odd length, antisymmetric), for tests.
  const cv::Mat& Kernel() const { return kernel_; }

 private:
  EdgeMapOptions options_;
  cv::Mat kernel_;    // 1 x N, CV_32F
  cv::Mat gradient_;  // CV_32F, |response|
  cv::Mat edges_;     // CV_8U
  cv::Mat kernel_t_;  // N x 1: the kernel turned vertical
  cv::Mat gradient_v_;  // CV_32F, |dI/dv|
  cv::Mat base_edges_;  // CV_8U
  std::vector<int> stack_;

  void Hysteresis(const cv::Mat& gradient, cv::Mat& edges);
};

}  // namespace squint::obstacles
