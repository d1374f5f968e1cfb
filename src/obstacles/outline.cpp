// Obstacle outline tracing (obstacle paper §5.1, §6.3).
#include "squint/obstacles/outline.hpp"

#include <cmath>

#include "squint/core/error.hpp"

namespace squint::obstacles {

std::string OutlineOptions::Validate() const {
  if (window_width_px < 1 || window_width_px % 2 == 0) return "outline.window_width_px must be a positive odd number";
  if (window_height_px < 1 || window_height_px % 2 == 0) return "outline.window_height_px must be a positive odd number";
  if (ground_stop_radius_px < 0) return "outline.ground_stop_radius_px must be >= 0";
  if (max_gap_rows < 0) return "outline.max_gap_rows must be >= 0";
  return {};
}

OutlineTracer::OutlineTracer(OutlineOptions options) : options_(options) {
  const std::string problem = options_.Validate();
  SQUINT_ENSURE(problem.empty(), problem);
}

namespace {
bool Inside(const cv::Mat& m, int u, int v) { return u >= 0 && v >= 0 && u < m.cols && v < m.rows; }
int RoundPx(double x) { return static_cast<int>(std::lround(x)); }
}  // namespace

const std::vector<OutlineTrace>& OutlineTracer::Trace(const cv::Mat& edges,
                                                       std::span<const ClassifiedFeature> features) {
  SQUINT_ENSURE(edges.type() == CV_8UC1, "OutlineTracer::Trace needs a CV_8U edge mask");
  const int w = edges.cols, h = edges.rows;
  traces_.clear();
  pixels_.clear();
  ground_.create(h, w, CV_8U);
  ground_.setTo(0);
  visited_.create(h, w, CV_8U);
  visited_.setTo(0);

  const int r = options_.ground_stop_radius_px;
  for (const ClassifiedFeature& f : features) {
    if (f.cls != FeatureClass::kGround) continue;
    const int u0 = RoundPx(f.pixel.x()), v0 = RoundPx(f.pixel.y());
    for (int v = std::max(0, v0 - r); v <= std::min(h - 1, v0 + r); ++v) {
      for (int u = std::max(0, u0 - r); u <= std::min(w - 1, u0 + r); ++u) ground_.at<std::uint8_t>(v, u) = 1;
    }
  }

  const int hw = options_.window_width_px / 2, hh = options_.window_height_px / 2;
  for (const ClassifiedFeature& f : features) {
    if (f.cls != FeatureClass::kObstacle) continue;
    if (!std::isfinite(f.pixel.x()) || !std::isfinite(f.pixel.y())) continue;
    const int fu = RoundPx(f.pixel.x()), fv = RoundPx(f.pixel.y());
    for (int sv = fv - hh; sv <= fv + hh; ++sv) {
      for (int su = fu - hw; su <= fu + hw; ++su) {
        if (!Inside(edges, su, sv) || edges.at<std::uint8_t>(sv, su) == 0 || visited_.at<std::uint8_t>(sv, su) != 0)
          continue;
        // Trace down from this seed.
        OutlineTrace trace;
        trace.first = static_cast<int>(pixels_.size());
        int u = su, v = sv;
        bool merged = false;
        while (true) {
          visited_.at<std::uint8_t>(v, u) = 1;
          pixels_.emplace_back(u, v);
          ++trace.count;
          if (ground_.at<std::uint8_t>(v, u) != 0) {
            trace.stopped_on_ground = true;
            break;
          }
          // Next pixel: straight down first, then down-left, down-right; a visited one means this
          // edge joins an outline already traced (whose contact is already known).
          bool found = false;
          for (int dv = 1; dv <= 1 + options_.max_gap_rows && !found && !merged; ++dv) {
            const int nv = v + dv;
            if (nv >= h) break;
            for (const int du : {0, -1, 1}) {
              const int nu = u + du;
              if (nu < 0 || nu >= w) continue;
              if (visited_.at<std::uint8_t>(nv, nu) != 0) {
                merged = true;
                break;
              }
            }
            if (merged) break;
            for (const int du : {0, -1, 1}) {
              const int nu = u + du;
              if (nu < 0 || nu >= w) continue;
              if (edges.at<std::uint8_t>(nv, nu) != 0) {
                u = nu;
                v = nv;
                found = true;
                break;
              }
            }
          }
          if (!found) break;
        }
        trace.contact_px = Eigen::Vector2i(u, v);
        // A branch that merged keeps its pixels (for drawing) but adds no contact.
        if (!merged) traces_.push_back(trace);
      }
    }
  }
  return traces_;
}

}  // namespace squint::obstacles
