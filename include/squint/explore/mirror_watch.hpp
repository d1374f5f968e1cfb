// A mirror ahead, recognised by the robot's own reflection moving as only a reflection can.
//
// A mirror shows the floor and the corridor going on behind its base, so the visual sonar reads
// free floor where a wall stands (corridor-5's mirror end: the robot weaves into it). The robot
// itself gives the mirror away. Its reflection is a disc of the robot's radius standing where the
// robot would be if it were mirrored in the wall, and the sonar reads the near arc of that disc's
// base as a boundary. Anything that stands still keeps its place in the odometry frame as the
// robot moves; the reflection does not: it is the robot's position reflected in the mirror's
// plane, so it comes nearer at twice the robot's speed toward the mirror and slides with it along
// the mirror. Two scans taken from positions at least min_baseline_m apart tell the two apart
// (the reflection moves by as much as the robot did), and the pair gives the mirror's plane: the
// perpendicular bisector of the robot's position and its reflection's centre.
//
// Per scan: the runs of neighbouring boundary columns (split where the range jumps by more than
// jump_m) nearer than max_range_m whose angular width is that of a disc of the body's radius at
// their range (within width_tolerance); each gives a candidate centre, body_radius_m beyond the
// run's nearest reading along its bearing. A candidate c implies a mirror, the perpendicular
// bisector of the robot and c; it is the robot's reflection when at least min_matches earlier
// scans of the last history_s seconds, taken discriminate_m or more away (the farthest at least
// min_baseline_m, and no two of them taken within distinct_m of each other: a robot standing
// still looks once however many scans it takes), show a candidate within match_m of where that
// mirror puts the reflection of the robot as it stood then; no earlier scan taken match_m or
// more away shows a candidate nearer c itself than that scan's reflection would be and within
// half the distance between the two scans' positions of c (a thing standing still, seen there);
// and the latest earlier scan with any candidate has one within the robot's travel since (plus
// match_m) of c (continuity).
#pragma once

#include <deque>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "squint/core/pose.hpp"
#include "squint/explore/visual_sonar.hpp"

namespace squint::explore {

struct MirrorWatchOptions {
  double body_radius_m = 0.25;   // the robot's disc: its reflection's base is an arc of this radius
  double max_range_m = 2.6;      // runs nearer than this (the sonar's range steps grow with range)
  int min_columns = 4;           // a run of at least this many columns
  double width_tolerance = 0.5;  // a run's angular width within (1 ± this) × the disc's at its range
  double jump_m = 0.15;          // neighbouring columns further apart in range are different things
  double match_m = 0.1;          // a reflection within this of where the mirror puts it
  double discriminate_m = 0.2;   // earlier scans taken at least this far away are compared
  int min_matches = 3;           // ...at least this many of them show the reflection in the mirror,
  double distinct_m = 0.04;      // ...taken this far from each other (a robot standing still looks once)
  double min_baseline_m = 0.35;  // ...the farthest of them at least this far away
  double history_s = 2.0;        // earlier scans kept
  // The latest earlier scan that saw any candidate saw one within the robot's travel since (and
  // match_m) of c: a reflection moves one scan at a time; a thing standing whose range reading
  // jumped toward the robot by about its travel mimics one (three such in the obstacle course).
  bool continuity = true;
  std::string Validate() const;
};

struct Mirror {
  bool found = false;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();   // on the mirror's plane (odometry frame)
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();  // unit, from the robot toward the mirror
  double stamp_s = 0.0;                              // the scan that found it
  int matches = 0;                                   // earlier scans that agreed
};

class MirrorWatch {
 public:
  explicit MirrorWatch(const MirrorWatchOptions& options = {});

  // One sonar scan taken at odom_T_robot. True when it shows the robot's reflection; Latest()
  // then holds the mirror.
  bool Update(const std::vector<SonarColumn>& scan, const Pose2& odom_T_robot, double stamp_s);
  const Mirror& Latest() const { return latest_; }
  int Found() const { return found_; }  // scans that found a mirror

  // The candidate reflections' centres (odometry frame) in one scan.
  static std::vector<Eigen::Vector2d> Candidates(const std::vector<SonarColumn>& scan, const Pose2& odom_T_robot,
                                                 const MirrorWatchOptions& options);

 private:
  struct Entry {
    Eigen::Vector2d from = Eigen::Vector2d::Zero();
    double stamp_s = 0.0;
    std::vector<Eigen::Vector2d> centres;
  };
  MirrorWatchOptions options_;
  std::deque<Entry> history_;
  std::vector<Eigen::Vector2d> counted_;  // Update's scratch: where the matching scans were taken
  Mirror latest_;
  int found_ = 0;
};

}  // namespace squint::explore
