// Obstacle memory for the visual sonar: a toroidal grid of remembered floor-contact points in the
// odometry frame, cleared along the rays where floor was seen, queried for free travel.
#include "squint/explore/obstacle_memory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "squint/core/error.hpp"

namespace squint::explore {

std::string ObstacleMemoryOptions::Validate() const {
  if (!(cell_m > 0.0) || !std::isfinite(cell_m)) return "cell_m must be positive";
  if (cells < 8 || cells > 1024) return "cells must be in [8, 1024]";
  if (!(query_radius_m > 0.0) || !std::isfinite(query_radius_m)) return "query_radius_m must be positive";
  if (cells * cell_m < 2.0 * query_radius_m + 2.0 * cell_m) return "cells * cell_m must exceed 2 * query_radius_m";
  if (!(keep_seconds > 0.0) || !std::isfinite(keep_seconds)) return "keep_seconds must be positive";
  if (!(blocked_min_range_m > 0.0) || !std::isfinite(blocked_min_range_m)) return "blocked_min_range_m must be positive";
  if (!(clear_blind_min_range_m >= 0.0) || !std::isfinite(clear_blind_min_range_m)) return "clear_blind_min_range_m must be >= 0";
  if (!(blind_points_from_m >= 0.0) || !std::isfinite(blind_points_from_m)) return "blind_points_from_m must be >= 0";
  if (!(blind_points_keep_s > 0.0) || !std::isfinite(blind_points_keep_s)) return "blind_points_keep_s must be positive";
  if (!(blind_points_edge_keep_s >= 0.0) || !std::isfinite(blind_points_edge_keep_s)) return "blind_points_edge_keep_s must be >= 0";
  if (confirm_scans < 0 || confirm_scans > 1000) return "confirm_scans must be in [0, 1000]";
  if (!(clear_own_within_m >= 0.0) || !std::isfinite(clear_own_within_m)) return "clear_own_within_m must be zero or positive";
  if (!(confirm_baseline_m >= 0.0) || !std::isfinite(confirm_baseline_m)) return "confirm_baseline_m must be >= 0";
  if (!(blocked_view_fraction >= 0.0 && blocked_view_fraction <= 1.0)) return "blocked_view_fraction must be in [0, 1]";
  if (blocked_view_scans < 1 || blocked_view_scans > 100) return "blocked_view_scans must be in [1, 100]";
  if (!(blocked_hold_s >= 0.0 && blocked_hold_s <= 60.0)) return "blocked_hold_s must be in [0, 60]";
  if (blocked_hold_min_columns < 1 || blocked_hold_min_columns > 1000) return "blocked_hold_min_columns must be in [1, 1000]";
  if (blocked_hold_scans < 1 || blocked_hold_scans > 100) return "blocked_hold_scans must be in [1, 100]";
  if (!(blocked_edge_step_m >= 0.0 && blocked_edge_step_m <= 100.0)) return "blocked_edge_step_m must be in [0, 100]";
  return {};
}

ObstacleMemory::ObstacleMemory(const ObstacleMemoryOptions& options) : options_(options) {
  if (std::string e = options_.Validate(); !e.empty()) throw Error("obstacle memory: " + e);
  cells_.assign(static_cast<std::size_t>(options_.cells * options_.cells), Cell{});
  gathered_.reserve(cells_.size());
  gathered_range_.reserve(cells_.size());  // filled beside gathered_ on every Gather
  if (options_.blind_points_edge_keep_driving_only || options_.clear_own_driving_only) gathered_kept_.reserve(cells_.size());
}

void ObstacleMemory::Clear() {
  for (Cell& c : cells_) {
    c.stamp_s = c.free_stamp_s = c.known_free_s = -1.0;
    c.soft = false;
    c.driving_only = false;
    c.scans = 0;
    c.confirmed = false;
  }
  n_blocked_ = 0;
  n_columns_ = 0;
  blocked_view_run_ = 0;
  held_.clear();
  view_half_rad_ = -1.0;
  gathered_.clear();
  gathered_range_.clear();
  gathered_kept_.clear();
}

ObstacleMemory::Cell& ObstacleMemory::At(const Eigen::Vector2d& p) {
  const int n = options_.cells;
  const int i = static_cast<int>(std::floor(p.x() / options_.cell_m));
  const int j = static_cast<int>(std::floor(p.y() / options_.cell_m));
  const int ii = ((i % n) + n) % n;
  const int jj = ((j % n) + n) % n;
  return cells_[static_cast<std::size_t>(jj * n + ii)];
}

void ObstacleMemory::MarkKnownFree(const Eigen::Vector2d& p, double stamp_s) {
  if (!options_.mark_known_free) return;
  Cell& c = At(p);
  c.known_free_s = stamp_s;
  c.known_i = static_cast<int>(std::floor(p.x() / options_.cell_m));
  c.known_j = static_cast<int>(std::floor(p.y() / options_.cell_m));
}

void ObstacleMemory::MarkBlindKnownFree(const Eigen::Vector2d& origin, const Eigen::Vector2d& d, double to_m,
                                       double stamp_s) {
  // The column's floor shows from its bottom row: nothing standing taller than the bottom row's
  // ray (0.43 m at the camera foot, down to the floor at the blind range) crosses it there.
  if (!options_.mark_known_free) return;
  for (double s = 0.0; s < to_m; s += 0.5 * options_.cell_m) MarkKnownFree(origin + s * d, stamp_s);
}

bool ObstacleMemory::KnownFree(const Eigen::Vector2d& p, double now_s) const {
  const Cell& c = At(p);
  return c.known_free_s >= 0.0 && now_s - c.known_free_s <= options_.keep_seconds &&
         c.known_i == static_cast<int>(std::floor(p.x() / options_.cell_m)) &&
         c.known_j == static_cast<int>(std::floor(p.y() / options_.cell_m));
}

template <class F>
bool ObstacleMemory::AnyCellCentreWithin(const Eigen::Vector2d& o, double reach_m, F&& f) const {
  const double cell = options_.cell_m;
  const int i0 = static_cast<int>(std::floor((o.x() - reach_m) / cell));
  const int i1 = static_cast<int>(std::floor((o.x() + reach_m) / cell));
  const int j0 = static_cast<int>(std::floor((o.y() - reach_m) / cell));
  const int j1 = static_cast<int>(std::floor((o.y() + reach_m) / cell));
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i)
      if (f(Eigen::Vector2d((i + 0.5) * cell, (j + 0.5) * cell))) return true;
  return false;
}

void ObstacleMemory::MarkFootprint(const Pose2& odom_T_robot, double radius_m, double stamp_s) {
  if (!options_.mark_known_free) return;
  const Eigen::Vector2d o = odom_T_robot.Translation();
  AnyCellCentreWithin(o, radius_m, [&](const Eigen::Vector2d& centre) {
    if ((centre - o).squaredNorm() <= radius_m * radius_m) MarkKnownFree(centre, stamp_s);
    return false;
  });
}

bool ObstacleMemory::UnknownBeside(const Pose2& odom_T_robot, double yaw, double radius_m, double step_m,
                                   double inner_m, double now_s) const {
  const Eigen::Vector2d o = odom_T_robot.Translation();
  const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d to = o + step_m * d;
  return AnyCellCentreWithin(o, radius_m + step_m, [&](const Eigen::Vector2d& centre) {
    const Eigen::Vector2d q = centre - o;
    // Newly covered by the moved disc, ahead of the centre, beside the path.
    if ((centre - to).squaredNorm() > radius_m * radius_m || q.squaredNorm() <= radius_m * radius_m) return false;
    if (q.dot(d) <= 0.0 || std::abs(d.x() * q.y() - d.y() * q.x()) < inner_m) return false;
    return !KnownFree(centre, now_s);
  });
}

void ObstacleMemory::Insert(const Eigen::Vector2d& p, const Eigen::Vector2d& from, double stamp_s) {
  Cell& c = At(p);
  if (c.stamp_s >= 0.0 && !c.soft && stamp_s - c.stamp_s <= options_.keep_seconds) {
    // Seen again in the same cell by a later scan: one more scan; confirmed once enough scans
    // from far enough apart (neighbouring columns of one scan may share a cell: counted once).
    if (stamp_s > c.stamp_s) ++c.scans;
    if (options_.confirm_scans > 0 && c.scans >= options_.confirm_scans &&
        (from - c.first_from).norm() >= options_.confirm_baseline_m)
      c.confirmed = true;
  } else {
    c.scans = 1;
    c.first_from = from;
    c.confirmed = false;
  }
  c.p = p;
  c.stamp_s = stamp_s;
  c.soft = false;
  c.driving_only = false;
  c.seen_range_m = (p - from).norm();
}

void ObstacleMemory::InsertConfirmed(const Eigen::Vector2d& p, double stamp_s) {
  Cell& c = At(p);
  c.p = p;
  c.stamp_s = stamp_s;
  c.soft = false;
  c.driving_only = false;
  c.scans = 1;
  c.first_from = p;
  c.confirmed = true;
  c.seen_range_m = 0.0;
}

void ObstacleMemory::InsertBlindRay(const Eigen::Vector2d& origin, double yaw, double to_m, double stamp_s, bool edge) {
  if (!(options_.blind_points_from_m > 0.0)) return;
  const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw));
  const double keep_s = edge ? options_.blind_points_edge_keep_s : options_.blind_points_keep_s;
  for (double s = options_.blind_points_from_m; s <= to_m; s += options_.cell_m) {
    const Eigen::Vector2d p = origin + s * d;
    Cell& c = At(p);
    if (c.free_stamp_s >= 0.0 && stamp_s - c.free_stamp_s <= options_.keep_seconds) continue;  // floor seen there
    if (c.stamp_s >= 0.0 && !c.soft) continue;  // a boundary seen there: keep it
    // A soft point already there keeps the later of the two ends (an edge's longer life).
    const double keep = c.stamp_s >= 0.0 ? std::max(c.soft_keep_s - (stamp_s - c.stamp_s), keep_s) : keep_s;
    c.p = p;
    c.stamp_s = stamp_s;
    c.soft = true;
    c.driving_only = false;
    c.soft_keep_s = keep;
    c.seen_range_m = 0.0;
    c.scans = 0;
    c.confirmed = false;
  }
}

void ObstacleMemory::ClearRay(const Eigen::Vector2d& origin, double yaw, double from_m, double to_m, double seen_from_m,
                              double stamp_s, double keep_from_m) {
  const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw));
  const double step = 0.5 * options_.cell_m;
  // Soft points (guesses along blocked-near rays) go wherever this ray saw the floor beyond the
  // blind range: the column is not blocked near after all; boundaries only from from_m on.
  const double start = std::min(from_m, options_.blind_points_from_m);
  for (double s = start; s < to_m; s += step) {
    Cell& c = At(origin + s * d);
    if (s >= seen_from_m) {
      c.free_stamp_s = stamp_s;
      MarkKnownFree(origin + s * d, stamp_s);
    }
    if (c.stamp_s < 0.0 || (s < from_m && !c.soft)) continue;
    // Only points on this side of the boundary and on the ray itself (within half the spacing
    // of neighbouring columns): a cell may hold a point beside the ray, such as a wall corner.
    const Eigen::Vector2d q = c.p - origin;
    const double along = q.dot(d);
    const double lateral = std::abs(d.x() * q.y() - d.y() * q.x());
    if (along < to_m && lateral <= 0.02 + 0.01 * along && !(c.confirmed && !c.soft)) {
      if (along >= keep_from_m) c.driving_only = true;
      else c.stamp_s = -1.0;
    }
  }
}

void ObstacleMemory::ClearUnknownRays(const std::vector<SonarColumn>& scan, const Pose2& odom_T_robot, double to_m) {
  const Eigen::Vector2d o = odom_T_robot.Translation();
  for (const SonarColumn& c : scan)
    if (c.kind == SonarReturn::kUnknown)
      ClearRay(o, odom_T_robot.yaw + c.bearing_rad, 0.0, to_m, std::numeric_limits<double>::infinity(), 0.0);
}

int ObstacleMemory::ClearRect(const Pose2& frame, double s0, double s1, double l0, double l1) {
  const Eigen::Vector2d o = frame.Translation();
  const Eigen::Vector2d d(std::cos(frame.yaw), std::sin(frame.yaw));
  int n = 0;
  for (Cell& c : cells_) {
    if (c.stamp_s < 0.0 || c.confirmed) continue;
    const Eigen::Vector2d q = c.p - o;
    const double s = q.dot(d);
    const double l = d.x() * q.y() - d.y() * q.x();
    if (s < s0 || s > s1 || l < l0 || l > l1) continue;
    c.stamp_s = -1.0;
    ++n;
  }
  return n;
}

void ObstacleMemory::PointsInRect(const Pose2& frame, double s0, double s1, double l0, double l1, double now_s,
                                  std::vector<Eigen::Vector2d>* out) const {
  const Eigen::Vector2d o = frame.Translation();
  const Eigen::Vector2d d(std::cos(frame.yaw), std::sin(frame.yaw));
  for (const Cell& c : cells_) {
    if (c.stamp_s < 0.0 || c.soft || c.driving_only || now_s - c.stamp_s > options_.keep_seconds) continue;
    const Eigen::Vector2d q = c.p - o;
    const double s = q.dot(d);
    const double l = d.x() * q.y() - d.y() * q.x();
    if (s < s0 || s > s1 || l < l0 || l > l1) continue;
    out->emplace_back(s, l);
  }
}

bool ObstacleMemory::SeenFree(const Eigen::Vector2d& origin, double yaw, double from_m, double to_m, double now_s) const {
  const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw));
  const double step = 0.5 * options_.cell_m;
  for (double s = from_m; s < to_m; s += step) {
    const Cell& c = At(origin + s * d);
    if (c.free_stamp_s < 0.0 || now_s - c.free_stamp_s > options_.keep_seconds) return false;
  }
  return true;
}

std::vector<char> ObstacleMemory::NearEdgeRuns(const std::vector<SonarColumn>& scan, double step_within_m,
                                               bool floor_beside) {
  std::vector<char> edge(scan.size(), 0);
  const auto step_near = [&](std::size_t k) {
    return scan[k].kind == SonarReturn::kBoundary && scan[k].range_m < step_within_m;
  };
  const auto floor_far = [&](std::size_t k) {
    return scan[k].kind == SonarReturn::kFar || (scan[k].kind == SonarReturn::kBoundary && scan[k].range_m >= step_within_m);
  };
  for (std::size_t i = 0; i < scan.size();) {
    if (scan[i].kind != SonarReturn::kBlockedNear) {
      ++i;
      continue;
    }
    std::size_t j = i;  // the run is columns i..j
    while (j + 1 < scan.size() && scan[j + 1].kind == SonarReturn::kBlockedNear) ++j;
    const bool far_beside = (i > 0 && floor_far(i - 1)) || (j + 1 < scan.size() && floor_far(j + 1));
    const char e = !(i > 0 && step_near(i - 1)) && !(j + 1 < scan.size() && step_near(j + 1)) &&
                           (!floor_beside || far_beside)
                       ? 1
                       : 0;
    std::fill(edge.begin() + static_cast<std::ptrdiff_t>(i), edge.begin() + static_cast<std::ptrdiff_t>(j + 1), e);
    i = j + 1;
  }
  return edge;
}

void ObstacleMemory::Update(const std::vector<SonarColumn>& scan, const Pose2& odom_T_robot, double stamp_s,
                            double near_blind_m) {
  const Eigen::Vector2d o = odom_T_robot.Translation();
  const double clear_margin = 1.5 * options_.cell_m;
  if (options_.blocked_hold_s > 0.0) {
    // The scan before this one joins the held ones; those older than the hold go.
    if (n_blocked_ >= options_.blocked_hold_min_columns)
      held_.push_back({std::vector<double>(blocked_yaws_.begin(), blocked_yaws_.begin() + n_blocked_),
                       std::vector<char>(blocked_edge_.begin(), blocked_edge_.begin() + n_blocked_), blocked_from_,
                       blocked_range_m_, blocked_stamp_s_});
    while (!held_.empty() && stamp_s - held_.front().stamp_s > options_.blocked_hold_s) held_.pop_front();
  }
  if (blocked_yaws_.size() < scan.size()) blocked_yaws_.resize(scan.size());
  if (blocked_edge_.size() < scan.size()) blocked_edge_.resize(scan.size());
  // Which blocked-near columns belong to a near thing's edge (blocked_edge_step_m): runs of them
  // whose neighbours show no floor step near the blind range.
  const std::vector<char> edge = NearEdgeRuns(scan, near_blind_m + options_.blocked_edge_step_m);
  // ...and which of those end in floor running far on a side the view has (a convex corner, an
  // obstacle's side), not in the view's edge alone (a wall filling the view): their soft points
  // are kept blind_points_edge_keep_s.
  // Only computed where that longer life is on (an empty vector otherwise).
  const bool long_edges = options_.blind_points_edge_keep_s > 0.0;
  const std::vector<char> corner_edge =
      long_edges ? NearEdgeRuns(scan, near_blind_m + options_.blocked_edge_step_m, true) : std::vector<char>{};
  n_blocked_ = 0;
  n_columns_ = static_cast<int>(scan.size());
  blocked_from_ = o;
  blocked_range_m_ = near_blind_m;
  blocked_stamp_s_ = stamp_s;
  view_half_rad_ = -1.0;
  if (options_.blocked_hold_in_view && !scan.empty()) {
    double lo = scan.front().bearing_rad, hi = lo;
    for (const SonarColumn& c : scan) {
      lo = std::min(lo, c.bearing_rad);
      hi = std::max(hi, c.bearing_rad);
    }
    // Half a column's width beyond the outermost columns' bearings.
    const double pad = scan.size() > 1 ? 0.5 * (hi - lo) / static_cast<double>(scan.size() - 1) : 0.0;
    view_centre_yaw_ = odom_T_robot.yaw + 0.5 * (lo + hi);
    view_half_rad_ = 0.5 * (hi - lo) + pad;
  }
  for (std::size_t ci = 0; ci < scan.size(); ++ci) {
    const SonarColumn& c = scan[ci];
    const double yaw = odom_T_robot.yaw + c.bearing_rad;
    // How far this column's own reading proves the floor (clear_own_within_m): up to its own
    // step, or nowhere when it was itself blocked near.
    const bool own_limits = options_.clear_own_within_m > 0.0 && c.own_range_m < options_.clear_own_within_m &&
                            c.own_range_m < c.range_m;
    const double own_to = own_limits ? c.own_range_m - clear_margin : std::numeric_limits<double>::infinity();
    // clear_own_driving_only: the ray is cleared in full, what lies beyond own_to kept for driving.
    const double own_clear_to = options_.clear_own_driving_only ? std::numeric_limits<double>::infinity() : own_to;
    const double keep_from = options_.clear_own_driving_only ? own_to : std::numeric_limits<double>::infinity();
    const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw));
    // A column whose bottom rows show floor (a boundary above it, the floor up to the horizon, or
    // floor-like rows without a step): nothing stands in front of it inside the blind zone.
    if (c.kind != SonarReturn::kBlockedNear) MarkBlindKnownFree(o, d, near_blind_m, stamp_s);
    switch (c.kind) {
      case SonarReturn::kBlockedNear:
        // Something nearer than the blind range, at an unknown distance: not remembered (it
        // would block later paths wherever it is put), but held as the latest scan's blockage.
        blocked_edge_[static_cast<std::size_t>(n_blocked_)] = edge[ci];
        blocked_yaws_[static_cast<std::size_t>(n_blocked_++)] = yaw;
        InsertBlindRay(o, yaw, near_blind_m, stamp_s, long_edges && corner_edge[ci] != 0);
        break;
      case SonarReturn::kBoundary: {
        const double from = c.range_m >= options_.clear_blind_min_range_m ? 0.0 : near_blind_m;
        ClearRay(o, yaw, from, std::min(c.range_m - clear_margin, own_clear_to), near_blind_m, stamp_s, keep_from);
        Insert(o + c.range_m * d, o, stamp_s);
        break;
      }
      case SonarReturn::kUnknown:
        break;
      case SonarReturn::kFar:
        ClearRay(o, yaw, 0.0, std::min({c.range_m, options_.query_radius_m + options_.cell_m, own_clear_to}), near_blind_m,
                 stamp_s, keep_from);
        break;
    }
  }
  const bool view = n_columns_ > 0 && n_blocked_ >= options_.blocked_view_fraction * n_columns_;
  blocked_view_run_ = view ? blocked_view_run_ + 1 : 0;
}

void ObstacleMemory::Gather(const Pose2& odom_T_robot, double stamp_s) {
  gathered_.clear();
  gathered_kept_.clear();
  gathered_range_.clear();
  const double r = options_.query_radius_m;
  const double r2 = r * r;
  const Eigen::Vector2d o = odom_T_robot.Translation();
  const int n = options_.cells;
  const int i0 = static_cast<int>(std::floor((o.x() - r) / options_.cell_m));
  const int i1 = static_cast<int>(std::floor((o.x() + r) / options_.cell_m));
  const int j0 = static_cast<int>(std::floor((o.y() - r) / options_.cell_m));
  const int j1 = static_cast<int>(std::floor((o.y() + r) / options_.cell_m));
  for (int j = j0; j <= j1; ++j) {
    const int jj = ((j % n) + n) % n;
    for (int i = i0; i <= i1; ++i) {
      Cell& c = cells_[static_cast<std::size_t>(jj * n + ((i % n) + n) % n)];
      if (c.stamp_s < 0.0) continue;
      if (stamp_s - c.stamp_s > (c.soft ? c.soft_keep_s : options_.keep_seconds)) {
        c.stamp_s = -1.0;
        continue;
      }
      if ((c.p - o).squaredNorm() > r2) continue;
      const bool kept_only = (options_.blind_points_edge_keep_driving_only && c.soft &&
                              stamp_s - c.stamp_s > options_.blind_points_keep_s) ||
                             c.driving_only;
      if (kept_only) {
        gathered_kept_.push_back(c.p);
      } else {
        gathered_.push_back(c.p);
        gathered_range_.push_back(c.seen_range_m);
      }
    }
  }
}

double ObstacleMemory::FreeTravel(const Pose2& odom_T_robot, double yaw, double radius_m, double max_m,
                                  bool use_blocked, bool seen_free_exempts, double min_range_m,
                                  double standing_m, bool kept_edges) const {
  const double near_m = min_range_m > 0.0 ? min_range_m : options_.blocked_min_range_m;
  const Eigen::Vector2d o = odom_T_robot.Translation();
  double free = max_m;
  // The latest scan's columns blocked nearer than the blind range: a direction whose swept band
  // meets one of them at the blind range has no free travel (from where that scan was taken).
  // How wide: when blocked columns count in full (use_blocked), the thing may be anywhere from
  // just outside the disc to the blind range, so the sector is the one a point at
  // options_.blocked_min_range_m would need; otherwise (the floor was mostly seen) the sector
  // at the blind range.
  // A wall filling the view: its blockage counts whatever the floor seen from farther back said.
  const bool view_blocked = options_.blocked_view_fraction > 0.0 && blocked_view_run_ >= options_.blocked_view_scans;
  const double latest = BlockedFree(blocked_yaws_.data(), n_blocked_, blocked_from_, blocked_range_m_,
                                    blocked_stamp_s_, o, yaw, radius_m, use_blocked, seen_free_exempts, view_blocked, free,
                                    false, near_m);
  // The held scans count where at least blocked_hold_scans scans (held ones and the latest) block
  // this direction: a blockage seen once is a flicker of the floor's texture.
  int blocking = latest < free ? 1 : 0;
  double held = free;
  if (use_blocked)
    for (const HeldBlockage& h : held_) {
      const bool standing = standing_m > 0.0 && (h.from - o).norm() <= standing_m;
      const double f = BlockedFree(h.yaws.data(), static_cast<int>(h.yaws.size()), h.from, h.range_m, h.stamp_s, o, yaw,
                                   radius_m, use_blocked, seen_free_exempts, view_blocked, free,
                                   options_.blocked_hold_in_view, near_m, standing ? h.edge.data() : nullptr);
      if (f < free) {
        ++blocking;
        held = std::min(held, f);
      }
    }
  free = blocking >= options_.blocked_hold_scans ? std::min(latest, held) : latest;
  return std::min(free, PointsFreeTravel(odom_T_robot, yaw, radius_m, max_m, 0.0, 0.0, kept_edges));
}

double ObstacleMemory::BlockedFree(const double* yaws, int n, const Eigen::Vector2d& from, double range_m,
                                   double stamp_s, const Eigen::Vector2d& o, double yaw, double radius_m,
                                   bool use_blocked, bool seen_free_exempts, bool view_blocked, double free,
                                   bool in_view_only, double min_range_m, const char* edge_out_of_view) const {
  const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw));
  const double half = use_blocked ? std::asin(std::min(1.0, radius_m / std::max(min_range_m, radius_m)))
                                  : std::atan2(radius_m, std::max(range_m, radius_m));
  for (int i = 0; i < n; ++i) {
    const double byaw = yaws[i];
    const bool out_of_view =
        view_half_rad_ >= 0.0 && std::abs(std::remainder(byaw - view_centre_yaw_, 2.0 * M_PI)) > view_half_rad_;
    // Out of the latest scan's view: skipped, but a near thing's edge seen where the robot stands.
    if (in_view_only && out_of_view && !(edge_out_of_view != nullptr && edge_out_of_view[i])) continue;
    const double dy = std::remainder(byaw - yaw, 2.0 * M_PI);
    if (std::abs(dy) < half) {
      if (!use_blocked && seen_free_exempts && !view_blocked && SeenFree(from, byaw, radius_m, range_m, stamp_s))
        continue;
      return std::min(free, std::max(0.0, (from - o).dot(d)));
    }
  }
  return free;
}

double ObstacleMemory::PointsFreeTravel(const Pose2& odom_T_robot, double yaw, double radius_m, double max_m,
                                        double skip_from_m, double skip_to_m, bool kept_edges,
                                        double coarse_from_m) const {
  const Eigen::Vector2d o = odom_T_robot.Translation();
  const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw));
  const double r2 = radius_m * radius_m;
  double free = max_m;
  auto sweep = [&](const std::vector<Eigen::Vector2d>& points, const std::vector<double>* ranges) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d q = points[i] - o;
      const double s = q.dot(d);
      const double l = d.x() * q.y() - d.y() * q.x();
      if (l * l >= r2 || s < 0.0) continue;  // beside the swept band, or behind the centre
      if (s > skip_from_m && s <= skip_to_m) continue;
      if (ranges != nullptr && s > skip_from_m && (*ranges)[i] > coarse_from_m) continue;
      const double hit = s - std::sqrt(r2 - l * l);
      free = std::min(free, std::max(0.0, hit));
    }
  };
  sweep(gathered_, coarse_from_m > 0.0 ? &gathered_range_ : nullptr);
  if (kept_edges) sweep(gathered_kept_, nullptr);
  return free;
}

double ObstacleMemory::WallAxisMod90(double* strength, int* pairs) const {
  double c = 0.0, s = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < gathered_.size(); ++i)
    for (std::size_t j = i + 1; j < gathered_.size(); ++j) {
      const Eigen::Vector2d d = gathered_[j] - gathered_[i];
      const double d2 = d.squaredNorm();
      if (d2 < 0.04 || d2 > 0.36) continue;
      const double a = 4.0 * std::atan2(d.y(), d.x());
      c += std::cos(a);
      s += std::sin(a);
      ++n;
    }
  *pairs = n;
  *strength = n > 0 ? std::hypot(c, s) / n : 0.0;
  return n > 0 ? std::atan2(s, c) / 4.0 : 0.0;
}

void ObstacleMemory::SideDistances(const Pose2& odom_T_robot, double axis_yaw, double along_window_m,
                                   double max_lateral_m, double* left_m, double* right_m, double cluster_m) const {
  const Eigen::Vector2d o = odom_T_robot.Translation();
  const Eigen::Vector2d d(std::cos(axis_yaw), std::sin(axis_yaw));
  double best[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  for (const Eigen::Vector2d& p : gathered_) {
    const Eigen::Vector2d q = p - o;
    const double s = q.dot(d);
    if (std::abs(s) > along_window_m) continue;
    const double l = d.x() * q.y() - d.y() * q.x();
    if (l == 0.0 || std::abs(l) >= max_lateral_m) continue;
    double& b = best[l > 0.0 ? 0 : 1];
    // With cluster_m a wall is two points at least: an isolated point is skipped.
    if (std::abs(l) < b && (cluster_m <= 0.0 || !Isolated(p, cluster_m))) b = std::abs(l);
  }
  *left_m = std::isfinite(best[0]) ? best[0] : -1.0;
  *right_m = std::isfinite(best[1]) ? best[1] : -1.0;
}

bool ObstacleMemory::Isolated(const Eigen::Vector2d& point, double radius_m) const {
  const double r2 = radius_m * radius_m;
  int within = 0;  // the point itself counts once
  for (const Eigen::Vector2d& q : gathered_)
    if ((q - point).squaredNorm() <= r2 && ++within > 1) return false;
  return true;
}

}  // namespace squint::explore
