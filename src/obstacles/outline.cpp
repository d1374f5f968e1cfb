// Obstacle outline tracing (obstacle paper §5.1, §6.3).
#include "squint/obstacles/outline.hpp"

#include <cmath>
#include <optional>
#include <utility>

#include "squint/core/error.hpp"

namespace squint::obstacles {

std::string OutlineOptions::Validate() const {
  if (window_width_px < 1 || window_width_px % 2 == 0) return "outline.window_width_px must be a positive odd number";
  if (window_height_px < 1 || window_height_px % 2 == 0) return "outline.window_height_px must be a positive odd number";
  if (ground_stop_radius_px < 0) return "outline.ground_stop_radius_px must be >= 0";
  if (max_gap_rows < 0) return "outline.max_gap_rows must be >= 0";
  if (base_max_rise_px < 0 || base_max_rise_px > 8) return "outline.base_max_rise_px must be in [0, 8]";
  if (!(base_min_step >= 0.0 && base_min_step <= 255.0)) return "outline.base_min_step must be in [0, 255]";
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
  return Trace(edges, cv::Mat(), cv::Mat(), features);
}

const std::vector<OutlineTrace>& OutlineTracer::Trace(const cv::Mat& edges, const cv::Mat& base_edges,
                                                       const cv::Mat& gray,
                                                       std::span<const ClassifiedFeature> features) {
  SQUINT_ENSURE(edges.type() == CV_8UC1, "OutlineTracer::Trace needs a CV_8U edge mask");
  const bool base = options_.base_trace && !base_edges.empty();
  if (base) {
    SQUINT_ENSURE(base_edges.type() == CV_8UC1 && base_edges.size() == edges.size() && gray.type() == CV_8UC1 &&
                      gray.size() == edges.size(),
                  "OutlineTracer::Trace needs a CV_8U base-edge mask and grey image of the edge mask's size");
  }
  base_.clear();
  const int w = edges.cols, h = edges.rows;
  traces_.clear();
  pixels_.clear();
  ground_.create(h, w, CV_8U);
  ground_.setTo(0);
  visited_.create(h, w, CV_8U);
  visited_.setTo(0);
  if (base) {
    base_visited_.create(h, w, CV_8U);
    base_visited_.setTo(0);
  }

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
        if (merged) continue;
        if (base) TraceBase(base_edges, gray, &trace);
        traces_.push_back(trace);
      }
    }
  }
  if (base && options_.base_below_features) {
    // An obstacle feature away from any vertical border (on a box's face, a wall): the first base
    // straight below it, unless the floor (a ground feature within the window's half-width of the
    // column) comes first.
    for (const ClassifiedFeature& f : features) {
      if (f.cls != FeatureClass::kObstacle) continue;
      if (!std::isfinite(f.pixel.x()) || !std::isfinite(f.pixel.y())) continue;
      const int fu = RoundPx(f.pixel.x()), fv = RoundPx(f.pixel.y());
      if (fu < 0 || fu >= w || fv < 0 || fv >= h) continue;
      bool floor = false;
      for (int v = fv + 1; v < h && !floor; ++v) {
        if (base_visited_.at<std::uint8_t>(v, fu) != 0) break;
        // The floor comes first: a ground feature within the window's half-width of the column.
        const std::uint8_t* g = ground_.ptr<std::uint8_t>(v);
        for (int u = std::max(0, fu - hw); u <= std::min(w - 1, fu + hw) && !floor; ++u) floor = g[u] != 0;
        if (floor) break;
        if (base_edges.at<std::uint8_t>(v, fu) == 0) continue;
        OutlineTrace drop;
        drop.contact_px = Eigen::Vector2i(fu, v);
        drop.below_feature = true;
        TraceBase(base_edges, gray, &drop);
        if (drop.base_count == 0) continue;  // not a step (a line or texture): look further down
        traces_.push_back(drop);
        break;
      }
    }
  }
  return traces_;
}

namespace {
// Mean grey of rows v+from..v+to (clamped to the image) in column u.
double ColumnMean(const cv::Mat& gray, int u, int v, int from, int to) {
  double sum = 0.0;
  int n = 0;
  for (int dv = from; dv <= to; ++dv) {
    const int r = v + dv;
    if (r < 0 || r >= gray.rows) continue;
    sum += gray.at<std::uint8_t>(r, u);
    ++n;
  }
  return n ? sum / n : 0.0;
}
}  // namespace

void OutlineTracer::TraceBase(const cv::Mat& base_edges, const cv::Mat& gray, OutlineTrace* trace) {
  trace->base_first = static_cast<int>(base_.size());
  const int w = base_edges.cols, h = base_edges.rows;
  // Grey step across a base pixel: below minus above (a dark obstacle on a light floor is positive).
  auto step = [&](int u, int v) { return ColumnMean(gray, u, v, 3, 6) - ColumnMean(gray, u, v, -6, -3); };
  // The base pixel in column u nearest row v (0, -1, +1, -2, +2, ... up to `rise`) that is not
  // yet traced and steps with `sign` (any sign when 0); none at a traced base or (unless
  // at_ground_ok: the corner of a trace that stopped on the floor) a ground feature.
  auto next = [&](int u, int v, int rise, int sign, bool at_ground_ok) -> std::optional<std::pair<int, int>> {
    if (u < 0 || u >= w) return std::nullopt;
    for (int k = 0; k <= 2 * rise; ++k) {
      const int nv = v + ((k % 2 == 0) ? k / 2 : -(k + 1) / 2);
      if (nv < 0 || nv >= h || base_edges.at<std::uint8_t>(nv, u) == 0) continue;
      if (base_visited_.at<std::uint8_t>(nv, u) != 0 || (!at_ground_ok && ground_.at<std::uint8_t>(nv, u) != 0))
        return std::nullopt;
      const double s = step(u, nv);
      if (std::abs(s) < options_.base_min_step) continue;
      const int sg = s > 0 ? 1 : -1;
      if (sign != 0 && sg != sign) continue;
      return std::make_pair(nv, sg);
    }
    return std::nullopt;
  };
  auto add = [&](int u, int v) {
    base_visited_.at<std::uint8_t>(v, u) = 1;
    base_.emplace_back(u, v);
    pixels_.emplace_back(u, v);
  };
  // The corner: the base pixel at or next to the contact. A trace may overshoot the base by a few
  // rows (a reflection or shadow edge continuing below the corner), so look up to kCornerRows
  // above it, and a little below, in the contact's column and two on either side (the vertical
  // edge band is a few pixels wide).
  constexpr int kCornerRows = 4;
  const Eigen::Vector2i c = trace->contact_px;
  std::optional<std::pair<int, int>> corner;
  int corner_u = c.x();
  for (const int du : {0, -1, 1, -2, 2}) {
    for (const int dv : {0, -1, 1, -2, 2, -3, -kCornerRows}) {
      corner = next(c.x() + du, c.y() + dv, 0, 0, true);
      if (corner) break;
    }
    if (corner) {
      corner_u = c.x() + du;
      break;
    }
  }
  if (corner) {
    add(corner_u, corner->first);
    const int sign = corner->second;
    for (const int dir : {-1, 1}) {
      int u = corner_u, v = corner->first;
      while (const auto n = next(u + dir, v, options_.base_max_rise_px, sign, false)) {
        u += dir;
        v = n->first;
        add(u, v);
      }
    }
  }
  trace->base_count = static_cast<int>(base_.size()) - trace->base_first;
}

}  // namespace squint::obstacles
