// Vertical edges ranged by motion parallax between two frames' horizon profiles.
#include "squint/explore/near_edges.hpp"

#include <algorithm>
#include <cmath>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::explore {

std::string NearEdgeOptions::Validate() const {
  if (!(min_step > 0.0) || !std::isfinite(min_step)) return "min_step must be positive";
  if (!(level_tolerance > 0.0) || !std::isfinite(level_tolerance)) return "level_tolerance must be positive";
  if (!(min_baseline_m > 0.0 && max_baseline_m > min_baseline_m) || !std::isfinite(max_baseline_m))
    return "baselines must satisfy 0 < min_baseline_m < max_baseline_m";
  if (!(match_window_rad > 0.0 && match_window_rad < 0.5)) return "match_window_rad must be in (0, 0.5)";
  if (!(min_range_m > 0.0 && max_range_m > min_range_m) || !std::isfinite(max_range_m))
    return "ranges must satisfy 0 < min_range_m < max_range_m";
  if (!(min_off_axis_rad >= 0.0 && min_off_axis_rad < 1.0)) return "min_off_axis_rad must be in [0, 1)";
  if (!(angle_noise_rad >= 0.0 && angle_noise_rad < 0.2)) return "angle_noise_rad must be in [0, 0.2)";
  if (border_columns < 1 || border_columns > 16) return "border_columns must be in [1, 16]";
  if (!(max_turn_rad > 0.0 && max_turn_rad < 1.0)) return "max_turn_rad must be in (0, 1)";
  if (history < 2 || history > 100) return "history must be in [2, 100]";
  if (!(agree_fraction > 0.0 && agree_fraction < 1.0)) return "agree_fraction must be in (0, 1)";
  return {};
}

NearEdgeRanger::NearEdgeRanger(const NearEdgeOptions& options) : options_(options) {
  if (std::string e = options_.Validate(); !e.empty()) throw Error("near edges: " + e);
}

void NearEdgeRanger::FindEdges(const std::vector<float>& p, const std::vector<double>& bearings,
                               std::vector<Edge>* out) const {
  out->clear();
  const int n = static_cast<int>(p.size());
  // The step across column u (from u - 1 to u + 1): an edge falling between two columns shares
  // its step between them, and this sees it whole.
  auto g = [&](int u) { return static_cast<double>(p[static_cast<std::size_t>(u + 1)] - p[static_cast<std::size_t>(u - 1)]); };
  const int lo = std::max(options_.border_columns, 2), hi = n - 1 - std::max(options_.border_columns, 2);
  for (int u = lo; u <= hi; ++u) {
    const double s = g(u);
    if (std::abs(s) < options_.min_step) continue;
    const double a = g(u - 1), b = g(u + 1);
    if (!(std::abs(s) >= std::abs(a) && std::abs(s) > std::abs(b))) continue;
    // Sub-column position: the parabola through the three steps (same sign only).
    double off = 0.0;
    const double sa = a * s > 0.0 ? std::abs(a) : 0.0, sb = b * s > 0.0 ? std::abs(b) : 0.0, sm = std::abs(s);
    const double den = sa - 2.0 * sm + sb;
    if (den < 0.0) off = std::clamp(0.5 * (sa - sb) / den, -0.5, 0.5);
    const double x = u + off;  // in columns
    const int i = std::clamp(static_cast<int>(std::floor(x)), 0, n - 2);
    const double t = x - i;
    Edge e;
    e.bearing = (1.0 - t) * bearings[static_cast<std::size_t>(i)] + t * bearings[static_cast<std::size_t>(i + 1)];
    e.column = x;
    e.sign = s > 0.0 ? 1 : -1;
    e.left = p[static_cast<std::size_t>(u - 2)];
    e.right = p[static_cast<std::size_t>(u + 2)];
    out->push_back(e);
  }
}

double NearEdgeRanger::Range(const Edge& e, const Pose2& pose, const Frame& ref) const {
  constexpr double kNone = -1.0;
  const Eigen::Vector2d b = pose.Translation() - ref.pose.Translation();
  const double baseline = b.norm();
  const double phi = std::atan2(b.y(), b.x());
  const double th1 = pose.yaw + e.bearing;
  // The only kept edge like it near the bearing a far edge would have had.
  const Edge* match = nullptr;
  int candidates = 0;
  for (const Edge& r : ref.edges) {
    if (r.sign != e.sign || std::abs(r.left - e.left) > options_.level_tolerance ||
        std::abs(r.right - e.right) > options_.level_tolerance)
      continue;
    if (std::abs(WrapPi(ref.pose.yaw + r.bearing - th1)) > options_.match_window_rad) continue;
    match = &r;
    ++candidates;
  }
  if (candidates != 1) return kNone;
  const double th0 = ref.pose.yaw + match->bearing;
  const double alpha = WrapPi(th0 - phi);  // the first ray against the baseline
  const double gamma = WrapPi(th1 - th0);  // the angle the edge moved through
  if (std::abs(std::sin(alpha)) < std::sin(options_.min_off_axis_rad) || std::abs(alpha) > kPi / 2) return kNone;
  if (!(alpha * gamma > 0.0)) return kNone;  // moved the wrong way (or not at all): far, or no match
  const double range = baseline * std::sin(alpha) / std::sin(gamma);
  if (!(range >= options_.min_range_m && range <= options_.max_range_m)) return kNone;
  // Within range even if the edge moved by angle_noise_rad less.
  const double slack = std::abs(gamma) - options_.angle_noise_rad;
  if (!(slack > 0.0) || std::abs(baseline * std::sin(alpha)) / std::sin(slack) > options_.max_range_m) return kNone;
  return range;
}

const std::vector<NearEdge>& NearEdgeRanger::Process(const std::vector<float>& profile, const std::vector<double>& bearings,
                                                     const Pose2& odom_T_robot) {
  SQUINT_ENSURE(profile.size() == bearings.size() && profile.size() >= 4,
                "near edges: the profile and the bearings must have the same length, at least 4");
  out_.clear();
  const Eigen::Vector2d p1 = odom_T_robot.Translation();
  FindEdges(profile, bearings, &cur_);
  // The kept frames far enough away, not too far, facing about the same way: the oldest (the
  // longest baseline) and the newest, which must agree.
  const Frame* oldest = nullptr;
  const Frame* newest = nullptr;
  for (const Frame& f : history_) {
    const double baseline = (p1 - f.pose.Translation()).norm();
    if (baseline >= options_.min_baseline_m && baseline <= options_.max_baseline_m &&
        std::abs(WrapPi(odom_T_robot.yaw - f.pose.yaw)) <= options_.max_turn_rad) {
      if (oldest == nullptr) oldest = &f;
      newest = &f;
    }
  }
  if (oldest != nullptr && newest != oldest) {
    for (const Edge& e : cur_) {
      const double r0 = Range(e, odom_T_robot, *oldest);
      if (r0 < 0.0) continue;
      const double r1 = Range(e, odom_T_robot, *newest);
      if (r1 < 0.0 || std::abs(r0 - r1) > options_.agree_fraction * std::max(r0, r1)) continue;
      NearEdge ne;
      ne.range_m = 0.5 * (r0 + r1);
      ne.bearing_rad = e.bearing;
      ne.column = e.column;
      const double th1 = odom_T_robot.yaw + e.bearing;
      ne.point = p1 + ne.range_m * Eigen::Vector2d(std::cos(th1), std::sin(th1));
      out_.push_back(ne);
    }
  }
  history_.push_back({odom_T_robot, cur_});
  while (static_cast<int>(history_.size()) > options_.history) history_.pop_front();
  return out_;
}

}  // namespace squint::explore
