#include "squint/explore/mirror_watch.hpp"

#include <algorithm>
#include <cmath>

namespace squint::explore {

std::string MirrorWatchOptions::Validate() const {
  if (!(body_radius_m > 0.0 && body_radius_m <= 2.0)) return "mirror watch: body_radius_m must be in (0, 2]";
  if (!(max_range_m > 0.0 && max_range_m <= 20.0)) return "mirror watch: max_range_m must be in (0, 20]";
  if (min_columns < 2) return "mirror watch: min_columns must be at least 2";
  if (!(width_tolerance >= 0.0 && width_tolerance < 1.0)) return "mirror watch: width_tolerance must be in [0, 1)";
  if (!(jump_m > 0.0 && jump_m <= 5.0)) return "mirror watch: jump_m must be in (0, 5]";
  if (!(min_baseline_m > 0.0 && min_baseline_m <= 5.0)) return "mirror watch: min_baseline_m must be in (0, 5]";
  if (!(history_s > 0.0 && history_s <= 60.0)) return "mirror watch: history_s must be in (0, 60]";
  if (!(match_m > 0.0 && match_m <= 0.5 * discriminate_m)) return "mirror watch: match_m must be in (0, discriminate_m / 2]";
  if (!(discriminate_m > 0.0 && discriminate_m <= min_baseline_m))
    return "mirror watch: discriminate_m must be in (0, min_baseline_m]";
  if (min_matches < 1) return "mirror watch: min_matches must be at least 1";
  if (!(distinct_m >= 0.0 && distinct_m <= discriminate_m)) return "mirror watch: distinct_m must be in [0, discriminate_m]";
  return {};
}

MirrorWatch::MirrorWatch(const MirrorWatchOptions& options) : options_(options) {}

std::vector<Eigen::Vector2d> MirrorWatch::Candidates(const std::vector<SonarColumn>& scan, const Pose2& odom_T_robot,
                                                     const MirrorWatchOptions& options) {
  std::vector<Eigen::Vector2d> out;
  const Eigen::Vector2d o = odom_T_robot.Translation();
  const int n = static_cast<int>(scan.size());
  const double r = options.body_radius_m;
  auto in_run = [&](int i) {
    return scan[static_cast<std::size_t>(i)].kind == SonarReturn::kBoundary &&
           scan[static_cast<std::size_t>(i)].range_m < options.max_range_m;
  };
  int i = 0;
  while (i < n) {
    if (!in_run(i)) {
      ++i;
      continue;
    }
    int j = i + 1;
    while (j < n && in_run(j) &&
           std::abs(scan[static_cast<std::size_t>(j)].range_m - scan[static_cast<std::size_t>(j - 1)].range_m) <=
               options.jump_m)
      ++j;
    // Columns [i, j): one run. A run cut by the view's edge or by a nearer thing beside it shows
    // only part of the arc: its width says nothing, so it is no candidate.
    auto hides = [&](int e, int inner) {  // column e, beside the run's end column inner, stands nearer
      if (e < 0 || e >= n) return true;      // the view's edge
      const SonarColumn& c = scan[static_cast<std::size_t>(e)];
      return c.kind == SonarReturn::kBlockedNear ||
             (c.kind == SonarReturn::kBoundary && c.range_m < scan[static_cast<std::size_t>(inner)].range_m);
    };
    const bool cut_left = hides(i - 1, i);
    const bool cut_right = hides(j, j - 1);
    if (j - i >= options.min_columns && !cut_left && !cut_right && n > 1) {
      int k = i;
      for (int m = i + 1; m < j; ++m)
        if (scan[static_cast<std::size_t>(m)].range_m < scan[static_cast<std::size_t>(k)].range_m) k = m;
      const SonarColumn& near = scan[static_cast<std::size_t>(k)];
      const double d = near.range_m + r;  // the disc's centre
      const double disc = 2.0 * std::asin(std::min(1.0, r / d));
      // The run spans its columns' bearings plus one column's width.
      const double step = std::abs(scan.back().bearing_rad - scan.front().bearing_rad) / static_cast<double>(n - 1);
      const double width =
          std::abs(scan[static_cast<std::size_t>(j - 1)].bearing_rad - scan[static_cast<std::size_t>(i)].bearing_rad) +
          step;
      if (width >= (1.0 - options.width_tolerance) * disc && width <= (1.0 + options.width_tolerance) * disc) {
        const double yaw = odom_T_robot.yaw + near.bearing_rad;
        out.push_back(o + d * Eigen::Vector2d(std::cos(yaw), std::sin(yaw)));
      }
    }
    i = j;
  }
  return out;
}

bool MirrorWatch::Update(const std::vector<SonarColumn>& scan, const Pose2& odom_T_robot, double stamp_s) {
  while (!history_.empty() && stamp_s - history_.front().stamp_s > options_.history_s) history_.pop_front();
  Entry e;
  e.from = odom_T_robot.Translation();
  e.stamp_s = stamp_s;
  e.centres = Candidates(scan, odom_T_robot, options_);
  bool found = false;
  for (const Eigen::Vector2d& c : e.centres) {
    // The mirror if c is the robot's reflection: the perpendicular bisector of the robot and c.
    const Eigen::Vector2d u = c - e.from;
    const double len = u.norm();
    if (!(len > 1e-9)) continue;
    const Eigen::Vector2d nrm = u / len;
    const Eigen::Vector2d mid = 0.5 * (e.from + c);
    int matches = 0;
    double baseline = 0.0;
    bool stands = false;
    counted_.clear();
    for (const Entry& h : history_) {
      const double apart = (e.from - h.from).norm();
      if (apart < options_.match_m || h.centres.empty()) continue;
      // Where that scan would have seen the robot's reflection in this mirror: as far from c as
      // the robot was from where it stands now. A thing standing still was seen at c itself.
      const Eigen::Vector2d predicted = h.from + 2.0 * (mid - h.from).dot(nrm) * nrm;
      bool match = false;
      for (const Eigen::Vector2d& hc : h.centres) {
        const double to_c = (hc - c).norm(), to_predicted = (hc - predicted).norm();
        if (to_c <= 0.5 * apart && to_c < to_predicted) stands = true;
        if (to_predicted <= options_.match_m) match = true;
      }
      // Scans taken nearer than discriminate_m to this one cannot tell the two apart. Scans taken
      // from one place (a robot standing) are one observation.
      if (!match || apart < options_.discriminate_m) continue;
      const bool again = std::any_of(counted_.begin(), counted_.end(),
                                     [&](const Eigen::Vector2d& q) { return (q - h.from).norm() < options_.distinct_m; });
      if (!again) {
        counted_.push_back(h.from);
        ++matches;
      }
      baseline = std::max(baseline, apart);
    }
    // A reflection moves as the robot does, one scan at a time: the latest earlier scan that saw
    // any candidate saw one no farther from c than the robot has moved since (and match_m). A thing
    // standing whose range reading jumped toward the robot by about its travel does not.
    bool continues = true;
    for (auto h = history_.rbegin(); options_.continuity && h != history_.rend(); ++h) {
      if (h->centres.empty()) continue;
      const double reach = (e.from - h->from).norm() + options_.match_m;
      continues = std::any_of(h->centres.begin(), h->centres.end(),
                              [&](const Eigen::Vector2d& hc) { return (hc - c).norm() <= reach; });
      break;
    }
    if (!stands && continues && matches >= options_.min_matches && baseline >= options_.min_baseline_m) {
      latest_.found = true;
      latest_.normal = nrm;
      latest_.point = mid;
      latest_.stamp_s = stamp_s;
      latest_.matches = matches;
      found = true;
    }
  }
  if (found) ++found_;
  history_.push_back(std::move(e));
  return found;
}

}  // namespace squint::explore
