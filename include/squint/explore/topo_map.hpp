// A topological map of a Manhattan building built from odometry and turn decisions: nodes are
// the places where the robot stopped (corridor ends, junctions) or passed a side branch, each
// with four branches (map directions 0..3 = 0°, 90°, 180°, 270°), and edges are the corridors
// driven between them.
// It answers one question: which branch to take next so that unexplored corridors come first.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace squint::explore {

enum class Branch : unsigned char {
  kUnknown,   // never looked at
  kWall,      // looked at: a wall (entropy rule) or the end wall the robot stopped at
  kOpen,      // looked at: an open corridor, not yet driven
  kExplored,  // driven along (out of or into this node)
};

const char* BranchName(Branch b);

struct TopoMapOptions {
  // Stops closer than this to an existing node are the same place (odometry drift included).
  double merge_radius_m = 3.0;
  // A corridor the robot has driven (a branch with a neighbour) that SetBranch(..., force) closed
  // because the robot found it blocked right after setting off along it is closed for the rest of
  // that visit only: the next arrival at the node opens it again (explored). The robot stood
  // somewhere it could not set off from (inside a side branch's mouth, beside a corner), which
  // says nothing of the corridor. Otherwise a T whose bar was closed that way from its stem leaves
  // the robot shuttling between the stem's dead end and the T for the rest of the run (`default`,
  // 45 minutes with --wall-line-align: coverage 0.21). false: closed for good (before session 35).
  bool reopen_blocked_driven = false;
  std::string Validate() const;
};

struct TopoNode {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  // map frame, running mean of arrivals
  std::array<Branch, 4> branch{Branch::kUnknown, Branch::kUnknown, Branch::kUnknown, Branch::kUnknown};
  std::array<int, 4> neighbour{-1, -1, -1, -1};  // node reached along each branch, -1 when none yet
  std::array<double, 4> length_m{0.0, 0.0, 0.0, 0.0};
  std::array<int, 4> last_departure{-1, -1, -1, -1};  // departure counter when last taken
  // Driven, then forced closed (found blocked right after setting off along it): reopened on the
  // next arrival when TopoMapOptions::reopen_blocked_driven.
  std::array<bool, 4> blocked_driven{false, false, false, false};
  int arrivals = 0;
};

// Map direction index of a yaw (radians, map frame): the nearest multiple of 90°.
int DirectionOfYaw(double yaw_rad);
// Yaw (radians) of a map direction.
double YawOfDirection(int dir);
inline int Opposite(int dir) { return (dir + 2) & 3; }

class TopoMap {
 public:
  explicit TopoMap(const TopoMapOptions& options = {});

  // The robot stopped at `position_m` after travelling along direction `travel_dir`. Returns the
  // node (new, or an existing one within merge_radius_m); links it with the node the robot last
  // departed from and marks the branch it came in by as explored. `came_along` false: the robot
  // did not come in along that branch (it started here, facing that way), which stays as it was.
  int Arrive(const Eigen::Vector2d& position_m, int travel_dir, bool came_along = true);
  // What looking (or bumping) told about a branch. An explored branch stays explored unless
  // `force` (the robot found it blocked right after setting off along it; with
  // reopen_blocked_driven a driven one is reopened on the next arrival).
  void SetBranch(int node, int dir, Branch state, bool force = false);
  // The robot leaves `node` along `dir`.
  void Depart(int node, int dir);
  // Forget the pending departure (the robot turned around mid-corridor, say).
  void CancelDeparture() { pending_node_ = -1; }
  // The node the robot last departed from and has not yet arrived anywhere since, or -1.
  int DepartedFrom() const { return pending_node_; }

  // The branch to take from `node`, where the robot arrived travelling along `arrival_dir`:
  // an open, unexplored branch first (ties in the order left, right, straight on); else the first
  // step of the shortest path (edge lengths) to the nearest node that still has an open branch;
  // else, when everything is explored, the least recently taken passable branch, the way back
  // last. Returns -1 when no branch is passable.
  int ChooseBranch(int node, int arrival_dir) const;

  // The node within merge_radius_m of `position_m` (the nearest), or -1.
  int NodeNear(const Eigen::Vector2d& position_m) const { return FindNear(position_m); }

  bool HasUnexplored() const;
  const std::vector<TopoNode>& Nodes() const { return nodes_; }
  int NumEdges() const;

 private:
  int FindNear(const Eigen::Vector2d& p) const;
  static bool Passable(Branch b) { return b == Branch::kOpen || b == Branch::kExplored; }

  TopoMapOptions options_;
  std::vector<TopoNode> nodes_;
  int pending_node_ = -1;
  int pending_dir_ = -1;
  Eigen::Vector2d pending_from_m_ = Eigen::Vector2d::Zero();
  int departures_ = 0;
};

}  // namespace squint::explore
