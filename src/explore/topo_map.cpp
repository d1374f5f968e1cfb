// The topological map of corridors and junctions, and the choice of the next branch.
#include "squint/explore/topo_map.hpp"

#include <cmath>
#include <limits>
#include <queue>
#include <algorithm>
#include <functional>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::explore {

const char* BranchName(Branch b) {
  switch (b) {
    case Branch::kUnknown: return "unknown";
    case Branch::kWall: return "wall";
    case Branch::kOpen: return "open";
    case Branch::kExplored: return "explored";
  }
  return "?";
}

std::string TopoMapOptions::Validate() const {
  if (!(merge_radius_m > 0.0) || !std::isfinite(merge_radius_m)) return "merge_radius_m must be positive";
  return {};
}

int DirectionOfYaw(double yaw_rad) {
  const int k = static_cast<int>(std::lround(WrapPi(yaw_rad) / (kPi / 2.0)));
  return ((k % 4) + 4) % 4;
}

double YawOfDirection(int dir) { return WrapPi((dir & 3) * kPi / 2.0); }

TopoMap::TopoMap(const TopoMapOptions& options) : options_(options) {
  const std::string err = options_.Validate();
  SQUINT_ENSURE(err.empty(), "TopoMapOptions: " + err);
}

int TopoMap::FindNear(const Eigen::Vector2d& p) const {
  int best = -1;
  double best_d = options_.merge_radius_m;
  for (int i = 0; i < static_cast<int>(nodes_.size()); ++i) {
    const double d = (nodes_[i].position_m - p).norm();
    if (d <= best_d) {
      best_d = d;
      best = i;
    }
  }
  return best;
}

int TopoMap::Arrive(const Eigen::Vector2d& position_m, int travel_dir, bool came_along) {
  SQUINT_ENSURE(travel_dir >= 0 && travel_dir < 4, "travel_dir must be 0..3");
  int id = FindNear(position_m);
  if (id < 0) {
    nodes_.push_back(TopoNode{});
    id = static_cast<int>(nodes_.size()) - 1;
    nodes_[id].position_m = position_m;
  } else {
    TopoNode& n = nodes_[id];
    n.position_m += (position_m - n.position_m) / static_cast<double>(n.arrivals + 1);
  }
  TopoNode& node = nodes_[id];
  ++node.arrivals;
  if (options_.reopen_blocked_driven) {
    for (int k = 0; k < 4; ++k) {
      if (node.blocked_driven[k] && node.branch[k] == Branch::kWall) node.branch[k] = Branch::kExplored;
      node.blocked_driven[k] = false;
    }
  }
  const int back = Opposite(travel_dir);
  if (came_along || pending_node_ >= 0) node.branch[back] = Branch::kExplored;
  if (pending_node_ >= 0 && pending_node_ != id) {
    const double length = (position_m - pending_from_m_).norm();
    TopoNode& from = nodes_[pending_node_];
    from.neighbour[pending_dir_] = id;
    from.length_m[pending_dir_] = length;
    node.neighbour[back] = pending_node_;
    node.length_m[back] = length;
  }
  pending_node_ = -1;
  return id;
}

void TopoMap::SetBranch(int node, int dir, Branch state, bool force) {
  SQUINT_ENSURE(node >= 0 && node < static_cast<int>(nodes_.size()), "unknown node");
  SQUINT_ENSURE(dir >= 0 && dir < 4, "dir must be 0..3");
  TopoNode& n = nodes_[node];
  Branch& b = n.branch[dir];
  if (!force && b == Branch::kExplored && state != Branch::kExplored) return;
  n.blocked_driven[dir] = force && state == Branch::kWall && n.neighbour[dir] >= 0;
  b = state;
}

void TopoMap::Depart(int node, int dir) {
  SQUINT_ENSURE(node >= 0 && node < static_cast<int>(nodes_.size()), "unknown node");
  SQUINT_ENSURE(dir >= 0 && dir < 4, "dir must be 0..3");
  TopoNode& n = nodes_[node];
  n.branch[dir] = Branch::kExplored;
  n.last_departure[dir] = departures_++;
  pending_node_ = node;
  pending_dir_ = dir;
  pending_from_m_ = n.position_m;
}

bool TopoMap::HasUnexplored() const {
  for (const TopoNode& n : nodes_)
    for (Branch b : n.branch)
      if (b == Branch::kOpen) return true;
  return false;
}

int TopoMap::NumEdges() const {
  int twice = 0;
  for (const TopoNode& n : nodes_)
    for (int nb : n.neighbour)
      if (nb >= 0) ++twice;
  return twice / 2;
}

int TopoMap::ChooseBranch(int node, int arrival_dir) const {
  SQUINT_ENSURE(node >= 0 && node < static_cast<int>(nodes_.size()), "unknown node");
  const TopoNode& here = nodes_[node];
  const int order[4] = {(arrival_dir + 1) & 3, (arrival_dir + 3) & 3, arrival_dir & 3, Opposite(arrival_dir)};

  // 1. An open branch nobody has driven yet.
  for (int d : order)
    if (here.branch[d] == Branch::kOpen) return d;

  // 2. Shortest path (Dijkstra on edge lengths) to the nearest node with an open branch.
  const int n = static_cast<int>(nodes_.size());
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<int> first_dir(n, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  dist[node] = 0.0;
  queue.push({0.0, node});
  while (!queue.empty()) {
    auto [d, u] = queue.top();
    queue.pop();
    if (d > dist[u]) continue;
    if (u != node) {
      bool open = false;
      for (Branch b : nodes_[u].branch) open = open || b == Branch::kOpen;
      if (open) return first_dir[u];
    }
    for (int k = 0; k < 4; ++k) {
      const int v = nodes_[u].neighbour[k];
      if (v < 0 || !Passable(nodes_[u].branch[k])) continue;
      const double nd = d + std::max(nodes_[u].length_m[k], 1e-3);
      if (nd < dist[v]) {
        dist[v] = nd;
        first_dir[v] = u == node ? k : first_dir[u];
        queue.push({nd, v});
      }
    }
  }

  // 3. Everything reachable is explored: patrol, least recently taken first, the way back last.
  int best = -1;
  int best_stamp = std::numeric_limits<int>::max();
  for (int i = 0; i < 3; ++i) {
    const int d = order[i];
    if (!Passable(here.branch[d])) continue;
    if (here.last_departure[d] < best_stamp) {
      best_stamp = here.last_departure[d];
      best = d;
    }
  }
  if (best >= 0) return best;
  return Passable(here.branch[order[3]]) ? order[3] : -1;
}

}  // namespace squint::explore
