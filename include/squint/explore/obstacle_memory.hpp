// A short-term memory of what the visual sonar saw standing on the floor, kept in the odometry
// frame so that walls and obstacles stay known after they leave the 60° view or enter the
// camera's near blind zone; answers how far the robot's disc can travel along a heading.
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "squint/core/pose.hpp"
#include "squint/explore/visual_sonar.hpp"

namespace squint::explore {

struct ObstacleMemoryOptions {
  double cell_m = 0.1;            // one remembered point per cell of this size
  int cells = 64;                 // toroidal grid of cells × cells (its period must exceed 2 × query radius)
  double query_radius_m = 3.0;    // points farther than this from the robot are ignored
  double keep_seconds = 60.0;     // points older than this are forgotten
  // A column whose floor reaches at least this far (metres) also clears the blind zone in front
  // of it (an obstacle standing there would have hidden the bottom rows).
  double clear_blind_min_range_m = 1.6;
  // A blocked-near column may hide something this close (metres): the directions it blocks
  // are those whose swept band meets its ray at this range, a sector of half-width
  // asin(radius / blocked_min_range_m) about the column (radius: the disc with its margin; ±36°
  // for 0.35 m). A thing nearer than that, inside the blind range, can be met with the disc's
  // flank along the sector's edge (the obstacle course's column 0.36 m away, start 1 of seed 4;
  // corridor-9's convex corner 0.38 m away, start 2 of seed 17). 0.45 (±51°) clears those and
  // every other failing seeded start of seeds 1-32, but a 45-minute run (seed 12) then turned off
  // the carpeted middle corridor's axis into its wall: 0.6 stays the default
  // (`squint explore --blocked-min-range`; docs/explore.md, session 27).
  double blocked_min_range_m = 0.6;
  // A blocked-near column is also remembered along its ray, from this range (metres) out to the
  // blind range, as "soft" points: something stands somewhere there. Cells whose floor was seen
  // (within keep_seconds) are skipped, and later floor seen along a ray removes them like any
  // point. They keep a corner that passed through the blind zone (and out of view while the
  // robot turns) known. 0 turns them off.
  double blind_points_from_m = 0.6;
  double blind_points_keep_s = 5.0;   // soft points older than this are forgotten
  // ...except those of a near thing's edge (a run of blocked-near columns with no floor step near
  // the blind range beside it, blocked_edge_step_m, and floor running on beyond that on at least
  // one side: a convex corner or an obstacle's side, not a wall running on into the blind zone nor
  // one filling the view), kept this long (seconds; 0: blind_points_keep_s; 15 by default since
  // session 39, with blind_points_edge_keep_driving_only, docs/explore.md). 15 s
  // outlasts a full look around in place (10.5 s at the explorer's scan rate) and the alignment
  // after it: with 5 s a convex corner seen in the first half of a start's scan is forgotten by
  // the set-off (corridor-7, start 4 of seed 98). Every soft point kept that long (not only an
  // edge's) held robots still in corridor-1's narrow cross corridor (docs/explore.md, session 37).
  double blind_points_edge_keep_s = 15.0;
  // With blind_points_edge_keep_s: an edge's soft points past blind_points_keep_s serve driving
  // only (FreeTravel with kept_edges), not the judgements of where walls and openings are (the
  // gathered points, the side distances, PointsFreeTravel), which see them for
  // blind_points_keep_s as every soft point. The longer life is for a set-off beside a corner
  // seen during a look around; kept for every query the points also moved the centring and the
  // side openings' judgements and with them the route, and at 45 minutes `default` missed its
  // middle corridor on 2 of 8 seeds. For driving only, the 45-minute runs of seeds 1-17 are
  // byte-identical to those without the longer life (docs/explore.md, session 38). On by default
  // since session 39.
  bool blind_points_edge_keep_driving_only = true;
  // A boundary seen again at the same place (cell) by this many scans, from positions at least
  // confirm_baseline_m apart, is confirmed: floor seen beyond it later no longer removes it (only
  // age does). Something standing stays where it is as the robot moves; what contradicts it is
  // a reflection (a mirror shows the floor continuing behind its base). 0 turns it off: the
  // default, because floor texture seen consistently from afar gets confirmed as well (default
  // world, 45 min: coverage 0.85 -> 0.12 with 3 scans / 0.3 m, the robot penned in by such points).
  int confirm_scans = 0;
  double confirm_baseline_m = 1.0;
  // A column clears remembered points only up to its own reading (SonarColumn::own_range_m)
  // where that is nearer than this (metres) and nearer than the column's median range; a column
  // that was itself blocked near clears nothing. The median across columns votes out a thin thing
  // (a chair leg 4 cm thick spans 2-3 columns at 1 m, and flickers between blocked near and a
  // boundary in the blind zone), and the floor seen beyond it under a chair's seat otherwise
  // erases what was remembered of it. 0 turns it off: the default (session 14: the obstacle
  // course's seeded starts 144 -> 153 of 160 with 1.2 m, but `default`'s 45-minute runs lost the
  // carpeted middle corridor on two of 16 seeds and met a wall on one; docs/explore.md).
  double clear_own_within_m = 0.0;
  // With clear_own_within_m: what a column's own reading does not clear (beyond its own step,
  // anywhere along a column itself blocked near) is cleared for the queries that judge walls and
  // openings as without it, and kept for driving only (FreeTravel with kept_edges), as
  // blind_points_edge_keep_driving_only keeps an edge's soft points: a chair leg the median voted
  // out still stops the disc, but a carpet's blocked-near columns no longer close a corridor to
  // the judgements. Off here; the explorer's memory has it on since session 49
  // (ExplorerMemoryDefaults).
  bool clear_own_driving_only = false;
  // A scan with at least this fraction of its columns blocked near shows a wall filling the view
  // (nothing of the floor in sight): its blockage stops forward travel even where the floor in the
  // blind zone was seen from farther back (FreeTravel's use_blocked = false). Floor "seen" through
  // a wall that has the floor's grey (corridor-2's panels over its carpet) is no proof. 0 turns
  // it off.
  double blocked_view_fraction = 0.75;
  int blocked_view_scans = 3;  // ...on this many consecutive scans (a single one is often a view without floor contrast)
  // The blocked-near columns of the scans of the last blocked_hold_s seconds (not only the
  // latest one's) limit the free travel where blocked columns count in full (FreeTravel's
  // use_blocked), each from where its scan was taken and with the same exemption where the floor
  // there was seen from farther back: a chair's legs, 4 cm thick, are blocked near in one frame
  // and read as a boundary beyond the seat's shadow in the next, so the latest scan alone lets
  // the robot creep on into the seat. 0 turns it off; 0.5 by default since session 21 (the
  // obstacle course's seeded starts, seeds 17-40: 12 of 240 met something with 0, none with 0.5;
  // it costs corridor-2's seeded starts coverage, 0.796 -> 0.689; docs/explore.md).
  double blocked_hold_s = 0.5;
  // Only scans with at least this many blocked-near columns are held: the sonar's median over 7
  // columns makes a real blockage several columns wide, while single columns come and go on a
  // smooth carpet (the explorer's blind-texture rules mark columns one by one).
  int blocked_hold_min_columns = 3;
  // ...and they count only where this many scans within the hold (the latest one included) block
  // the direction (2: corridor-2's coverage 0.764, but 6 of the 240 obstacle-course runs meet
  // something again).
  int blocked_hold_scans = 1;
  // ...and only their columns the latest scan still looks along (within its view): a held column
  // that has left the view is no flicker to outlast. A robot started 0.35 m from a wall and turning
  // away from it to get clear was held by the wall's columns for half a second after the wall had
  // left the view, the stall guard gave the direction up, and a later scan set it off into the wall
  // (`default`, start 2 of seed 12). It also fixed corridor-2's start 2 of seed 13 and the
  // 45-minute runs' missed middle corridor (seeds 2 and 9). Off in session 22 (the main job's route
  // changed with it and met the inner corner of the north-east L after a false opening 2 m early);
  // on by default since session 23, whose side_wall_cluster_m removed that false opening
  // (`squint explore --no-blocked-hold-in-view`; docs/explore.md, sessions 22 and 23).
  bool blocked_hold_in_view = true;
  // A run of blocked-near columns is a near thing's edge where no neighbouring column (one on
  // each side of the run, where the view has it) shows a floor step nearer than the blind range
  // plus this margin (metres): the run ends in floor running far, or in nothing floor-like. Beside
  // such a step it is a wall running on into the blind zone (a corridor's wall 0.6 m to the side
  // fills the view's outer columns' bottom rows). FreeTravel's standing_m holds only the edges'
  // columns out of the view.
  double blocked_edge_step_m = 0.6;
  // Keep which cells are known free of anything standing (UnknownBeside; the explorer's
  // guard_unknown_step_m turns it on): floor seen there, a column whose floor shows from its
  // bottom row crossing it in the blind zone, or the robot's disc (MarkFootprint).
  bool mark_known_free = false;
  std::string Validate() const;
};

// The options the explorer's memory has by default: ObstacleMemoryOptions' own, with own-range
// clearing for driving only (clear_own_within_m 1.2, clear_own_driving_only).
inline ObstacleMemoryOptions ExplorerMemoryDefaults() {
  ObstacleMemoryOptions o;
  o.clear_own_within_m = 1.2;
  o.clear_own_driving_only = true;
  return o;
}

class ObstacleMemory {
 public:
  explicit ObstacleMemory(const ObstacleMemoryOptions& options = {});

  // One sonar scan taken at odom_T_robot: clears what the floor seen proves free, stores the
  // boundaries and near blockages. `near_blind_m`: the sonar's blind range.
  void Update(const std::vector<SonarColumn>& scan, const Pose2& odom_T_robot, double stamp_s, double near_blind_m);
  // Per column of `scan`: 1 where it is blocked near and its run of blocked-near columns is a near
  // thing's edge, no neighbouring column of the run a floor step nearer than `step_within_m`
  // (blocked_edge_step_m); 0 elsewhere.
  // `floor_beside`: only runs with a neighbouring column (where the view has one) whose floor runs
  // on to step_within_m or farther (a boundary there or beyond, or floor to the horizon), not a run
  // bounded by the view's edges or by unknown columns alone.
  static std::vector<char> NearEdgeRuns(const std::vector<SonarColumn>& scan, double step_within_m,
                                        bool floor_beside = false);
  // Collects the remembered points within the query radius of `odom_T_robot` (call once after
  // the robot moved, before the queries below).
  void Gather(const Pose2& odom_T_robot, double stamp_s);

  // How far (metres, up to max_m) the disc of `radius_m` can drive straight from the gathered
  // pose along odometry yaw `yaw` before it touches a remembered point; zero along a direction
  // the latest scan saw blocked nearer than its blind range.
  // `use_blocked`: false ignores those of the latest scan's blocked-near columns along which the
  // floor in the blind zone was seen from farther back (a robot that drove into its present view),
  // unless the scan's view was blocked (blocked_view_fraction). `seen_free_exempts` (with
  // use_blocked false): false keeps those columns too, in the narrower sector at the blind range
  // (the explorer: the latest frame shows a brick wall's lines, whose base may have been read as
  // floor from farther back).
  // The earlier scans' blockages (blocked_hold_s) count only with use_blocked.
  // `min_range_m` > 0 replaces blocked_min_range_m for this query. `standing_m` > 0: the columns
  // of a near thing's edge (blocked_edge_step_m) in a held scan taken within standing_m of the
  // gathered pose count outside the latest scan's view too (blocked_hold_in_view leaves them out
  // otherwise).
  // `kept_edges` (blind_points_edge_keep_driving_only): false leaves out the edges' soft points
  // kept past blind_points_keep_s, as the queries that judge walls and openings do.
  double FreeTravel(const Pose2& odom_T_robot, double yaw, double radius_m, double max_m, bool use_blocked = true,
                    bool seen_free_exempts = true, double min_range_m = 0.0, double standing_m = 0.0,
                    bool kept_edges = true) const;
  // The same sweep against the gathered points only (no blocked-near columns), leaving out the
  // points whose distance along `yaw` lies in (skip_from_m, skip_to_m] (none when skip_to_m <=
  // skip_from_m); the edges' kept soft points count only with `kept_edges`. `coarse_from_m` > 0
  // leaves out too the points beyond skip_from_m last seen from farther than coarse_from_m.
  double PointsFreeTravel(const Pose2& odom_T_robot, double yaw, double radius_m, double max_m, double skip_from_m = 0.0,
                          double skip_to_m = 0.0, bool kept_edges = false, double coarse_from_m = 0.0) const;
  // Nearest remembered point abeam on each side, as lateral distances from the robot along the
  // axis `axis_yaw` (odometry frame), among points within ±along_window_m along the axis.
  // Negative when none. With cluster_m > 0 a side's distance is that of the nearest point with
  // another remembered point within cluster_m of it (a wall is two points at least, not one stray
  // point).
  void SideDistances(const Pose2& odom_T_robot, double axis_yaw, double along_window_m, double max_lateral_m,
                     double* left_m, double* right_m, double cluster_m = 0.0) const;
  // True when no other gathered point lies within radius_m of `point` (a gathered point itself).
  bool Isolated(const Eigen::Vector2d& point, double radius_m) const;
  const std::vector<Eigen::Vector2d>& Gathered() const { return gathered_; }
  // The range each gathered point was last seen from, in the same order (0: a soft point, or one
  // remembered by other means than the sonar). At 64×48 one row of the sonar's frame spans about
  // 0.3 m of floor at 3 m and 0.5 m at 4 m, so far points may lie that much short of the thing.
  const std::vector<double>& GatheredSeenRanges() const { return gathered_range_; }
  // The dominant direction of the gathered points' wall lines modulo 90 degrees (radians in
  // (-pi/4, pi/4], odometry frame), from every pair of gathered points 0.2-0.6 m apart: the mean
  // of 4x their directions. `strength`: that mean's resultant length (1: all pairs parallel or
  // perpendicular to the result, near 0: no direction); `pairs`: how many pairs. Quadratic in the
  // gathered points.
  double WallAxisMod90(double* strength, int* pairs) const;
  void Clear();
  // Removes remembered boundaries (and soft points) along the rays of the scan's unknown columns
  // out to to_m, without marking any floor as seen (the explorer's blind views: a corridor in the
  // glance, so nothing stands within the sonar's blind range ahead).
  void ClearUnknownRays(const std::vector<SonarColumn>& scan, const Pose2& odom_T_robot, double to_m);
  // Removes the remembered points (not confirmed ones) inside the rectangle [s0, s1] × [l0, l1] of
  // the frame `frame` (s along its yaw, l to its left); returns how many. Gather again after it.
  int ClearRect(const Pose2& frame, double s0, double s1, double l0, double l1);
  // The cells under a disc of radius_m around the robot are known free (it stands there). Called
  // every frame; nothing else changes.
  void MarkFootprint(const Pose2& odom_T_robot, double radius_m, double stamp_s);
  // Remembers a confirmed point at p (a wall known by other means than the floor seen: floor seen
  // beyond it later does not remove it, only age does).
  void InsertConfirmed(const Eigen::Vector2d& p, double stamp_s);
  // True when the disc of radius_m, moved step_m along `yaw`, would cover a cell whose centre is
  // at least inner_m to the side of its path (the camera's view does not reach beside the robot)
  // and which was not known free within keep_seconds of now_s: floor never seen there, beside
  // the robot where something may stand that the camera lost in its near blind zone.
  bool UnknownBeside(const Pose2& odom_T_robot, double yaw, double radius_m, double step_m, double inner_m,
                     double now_s) const;
  // The remembered boundary points (not soft ones, not older than keep_seconds at now_s) inside
  // the rectangle [s0, s1] × [l0, l1] of `frame`, appended to *out as (s, l), whatever their
  // distance from the robot (the grid's period bounds what can still be there).
  void PointsInRect(const Pose2& frame, double s0, double s1, double l0, double l1, double now_s,
                    std::vector<Eigen::Vector2d>* out) const;

 private:
  struct Cell {
    Eigen::Vector2d p = Eigen::Vector2d::Zero();
    double stamp_s = -1.0;       // < 0: empty
    double free_stamp_s = -1.0;  // when floor was last seen here (< 0: never)
    bool soft = false;           // from a blocked-near column (position along its ray unknown)
    double soft_keep_s = 0.0;    // a soft point is forgotten this long after stamp_s
    int scans = 0;               // scans that saw a boundary in this cell (see confirm_scans)
    double seen_range_m = 0.0;   // the range it was last seen from (0: soft or confirmed points)
    Eigen::Vector2d first_from = Eigen::Vector2d::Zero();  // where the first of them was taken
    bool confirmed = false;
    bool driving_only = false;  // kept by a column's own reading only (clear_own_driving_only)
    // When this cell was last known free of anything standing (< 0: never): floor seen there, a
    // column whose floor showed from its bottom row crossing it in the blind zone, or the robot's
    // own disc on it. known_i/known_j name the cell unwrapped (the grid is toroidal).
    double known_free_s = -1.0;
    int known_i = 0, known_j = 0;
  };
  Cell& At(const Eigen::Vector2d& p);
  const Cell& At(const Eigen::Vector2d& p) const { return const_cast<ObstacleMemory*>(this)->At(p); }
  // True when floor was seen (within keep_seconds of `now_s`) along the ray from from_m to to_m.
  bool SeenFree(const Eigen::Vector2d& origin, double yaw, double from_m, double to_m, double now_s) const;
  void Insert(const Eigen::Vector2d& p, const Eigen::Vector2d& from, double stamp_s);
  // Calls f(centre) for each cell centre in the square of half side reach_m around o, until f
  // returns true (then true).
  template <class F>
  bool AnyCellCentreWithin(const Eigen::Vector2d& o, double reach_m, F&& f) const;
  // Marks the cell holding p known free at stamp_s.
  void MarkKnownFree(const Eigen::Vector2d& p, double stamp_s);
  bool KnownFree(const Eigen::Vector2d& p, double now_s) const;
  // Marks the cells along a column's ray in the near blind zone (to to_m) known free.
  void MarkBlindKnownFree(const Eigen::Vector2d& origin, const Eigen::Vector2d& d, double to_m, double stamp_s);
  // Soft points along a blocked-near ray where the floor was not seen.
  // `edge`: the column belongs to a near thing's edge (kept blind_points_edge_keep_s).
  void InsertBlindRay(const Eigen::Vector2d& origin, double yaw, double to_m, double stamp_s, bool edge);
  // Removes points along the ray from from_m to to_m; marks floor seen from seen_from_m on. Points
  // from keep_from_m on are kept for driving only (clear_own_driving_only) instead of removed.
  void ClearRay(const Eigen::Vector2d& origin, double yaw, double from_m, double to_m, double seen_from_m, double stamp_s,
                double keep_from_m = std::numeric_limits<double>::infinity());

  ObstacleMemoryOptions options_;
  std::vector<Cell> cells_;
  std::vector<Eigen::Vector2d> gathered_;
  std::vector<double> gathered_range_;  // Cell::seen_range_m of each gathered point
  // With blind_points_edge_keep_driving_only: the gathered soft points older than
  // blind_points_keep_s (an edge's, kept longer), which only driving queries see; with
  // clear_own_driving_only, the points kept for driving only too.
  std::vector<Eigen::Vector2d> gathered_kept_;
  // The latest scan's blocked-near columns (odometry yaws), where it was taken, its blind range.
  std::vector<double> blocked_yaws_;
  std::vector<char> blocked_edge_;  // per blocked column of the latest scan: a near thing's edge
  int n_blocked_ = 0;
  int n_columns_ = 0;  // columns of the latest scan
  int blocked_view_run_ = 0;  // consecutive scans with a blocked view (blocked_view_fraction)
  Eigen::Vector2d blocked_from_ = Eigen::Vector2d::Zero();
  double blocked_range_m_ = 0.0;
  double blocked_stamp_s_ = 0.0;
  // The latest scan's view: the odometry yaw of its centre and its half-width (blocked_hold_in_view).
  double view_centre_yaw_ = 0.0;
  double view_half_rad_ = -1.0;  // < 0: no scan yet
  // Earlier scans' blocked-near columns within blocked_hold_s (ObstacleMemoryOptions).
  struct HeldBlockage {
    std::vector<double> yaws;
    std::vector<char> edge;  // per yaw: a near thing's edge (blocked_edge_step_m)
    Eigen::Vector2d from = Eigen::Vector2d::Zero();
    double range_m = 0.0;
    double stamp_s = 0.0;
  };
  std::deque<HeldBlockage> held_;
  // FreeTravel's test against one scan's blocked-near columns.
  double BlockedFree(const double* yaws, int n, const Eigen::Vector2d& from, double range_m, double stamp_s,
                     const Eigen::Vector2d& o, double yaw, double radius_m, bool use_blocked, bool seen_free_exempts,
                     bool view_blocked, double free, bool in_view_only, double min_range_m,
                     const char* edge_out_of_view = nullptr) const;
};

}  // namespace squint::explore
