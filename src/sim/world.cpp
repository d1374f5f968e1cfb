// World geometry: the floor area as a compressed grid of corridor and recess rectangles, its
// boundary walls, wall decals, and the validation of the whole world (connectivity, obstacles
// and the robot's start inside the floor area).
#include "squint/sim/world.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"

namespace squint::sim {
namespace {

constexpr double kEps = 1e-9;

std::vector<double> Unique(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v)
    if (out.empty() || x - out.back() > 1e-9) out.push_back(x);
  return out;
}

// Index of the interval [v[i], v[i+1]) containing x, or -1.
int Interval(const std::vector<double>& v, double x) {
  if (v.size() < 2 || x < v.front() || x >= v.back()) return -1;
  return static_cast<int>(std::upper_bound(v.begin(), v.end(), x) - v.begin()) - 1;
}

double SegmentDistance(const Eigen::Vector2d& p, const WallSegment& w) {
  if (w.along_x) {
    const double x = std::clamp(p.x(), w.lo, w.hi);
    return std::hypot(p.x() - x, p.y() - w.coord);
  }
  const double y = std::clamp(p.y(), w.lo, w.hi);
  return std::hypot(p.x() - w.coord, p.y() - y);
}

// Distance from p to an obstacle's footprint (0 inside).
double FootprintDistance(const Eigen::Vector2d& p, const Obstacle& o) {
  if (o.shape == Obstacle::Shape::kCylinder) return std::max(0.0, (p - o.centre).norm() - o.radius);
  const double c = std::cos(o.yaw), s = std::sin(o.yaw);
  const Eigen::Vector2d d = p - o.centre;
  const double lx = c * d.x() + s * d.y(), ly = -s * d.x() + c * d.y();
  const double ex = std::max(0.0, std::abs(lx) - o.half_x), ey = std::max(0.0, std::abs(ly) - o.half_y);
  return std::hypot(ex, ey);
}

// Points along the outline of a footprint (about every 2 cm) and its centre.
std::vector<Eigen::Vector2d> Outline(const Obstacle& o) {
  std::vector<Eigen::Vector2d> pts{o.centre};
  if (o.shape == Obstacle::Shape::kCylinder) {
    const int n = std::max(16, static_cast<int>(2 * kPi * o.radius / 0.02));
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n;
      pts.emplace_back(o.centre + o.radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    return pts;
  }
  const double c = std::cos(o.yaw), s = std::sin(o.yaw);
  auto to_world = [&](double lx, double ly) {
    return Eigen::Vector2d(o.centre.x() + c * lx - s * ly, o.centre.y() + s * lx + c * ly);
  };
  const int nx = std::max(2, static_cast<int>(2 * o.half_x / 0.02)), ny = std::max(2, static_cast<int>(2 * o.half_y / 0.02));
  for (int i = 0; i <= nx; ++i) {
    const double lx = -o.half_x + 2 * o.half_x * i / nx;
    pts.push_back(to_world(lx, -o.half_y));
    pts.push_back(to_world(lx, o.half_y));
  }
  for (int j = 0; j <= ny; ++j) {
    const double ly = -o.half_y + 2 * o.half_y * j / ny;
    pts.push_back(to_world(-o.half_x, ly));
    pts.push_back(to_world(o.half_x, ly));
  }
  return pts;
}

}  // namespace

CameraModel CameraMount::Model() const {
  CameraModel m;
  m.width = width;
  m.height = height;
  m.fx = m.fy = 0.5 * width / std::tan(DegToRad(hfov_deg) / 2.0);
  m.cx = 0.5 * width - 0.5;
  m.cy = 0.5 * height - 0.5;
  m.height_m = height_m;
  m.pitch_deg = pitch_deg;
  return m;
}

void World::Build() {
  auto fail = [&](const std::string& what) { throw Error(fmt::format("{}: {}", source, what)); };
  if (corridors.empty()) fail("corridors: at least one corridor is required");

  // Corridor rectangles.
  for (std::size_t i = 0; i < corridors.size(); ++i) {
    Corridor& c = corridors[i];
    const std::string id = fmt::format("corridors[{}] '{}'", i, c.name);
    const Eigen::Vector2d d = c.to - c.from;
    if (!(c.width_m > 0) || !(c.height_m > 0)) fail(id + ": width_m and height_m must be positive");
    if (std::abs(d.x()) > kEps && std::abs(d.y()) > kEps)
      fail(id + ": corridors must be axis-aligned (from and to must share x or y)");
    if (d.norm() < 1e-6) fail(id + ": from and to are the same point (length must be positive)");
    const double h = c.width_m / 2;
    c.rect = {std::min(c.from.x(), c.to.x()) - h, std::min(c.from.y(), c.to.y()) - h,
              std::max(c.from.x(), c.to.x()) + h, std::max(c.from.y(), c.to.y()) + h};
  }

  // Recesses behind doors.
  recesses.clear();
  recess_owner_.clear();
  std::vector<int>& recess_owner = recess_owner_;
  auto feature_frame = [](const Corridor& c, const WallFeature& f, Eigen::Vector2d* centre, Eigen::Vector2d* normal_out,
                          Eigen::Vector2d* along) {
    const Eigen::Vector2d ax = c.Axis();
    const Eigen::Vector2d left(-ax.y(), ax.x());
    switch (f.side) {
      case WallSide::kLeft:
        *centre = c.from + ax * f.at_m + left * (c.width_m / 2);
        *normal_out = left;
        *along = ax;
        break;
      case WallSide::kRight:
        *centre = c.from + ax * f.at_m - left * (c.width_m / 2);
        *normal_out = -left;
        *along = ax;
        break;
      case WallSide::kFromEnd:
        *centre = c.from - ax * (c.width_m / 2) + left * f.at_m;
        *normal_out = -ax;
        *along = left;
        break;
      case WallSide::kToEnd:
        *centre = c.to + ax * (c.width_m / 2) + left * f.at_m;
        *normal_out = ax;
        *along = left;
        break;
    }
  };
  for (std::size_t i = 0; i < corridors.size(); ++i) {
    for (std::size_t k = 0; k < corridors[i].features.size(); ++k) {
      const WallFeature& f = corridors[i].features[k];
      const std::string id = fmt::format("corridors[{}] '{}' features[{}]", i, corridors[i].name, k);
      if (!(f.width_m > 0) || !(f.height_m > 0)) fail(id + ": width_m and height_m must be positive");
      if (f.z_m < 0 || f.recess_m < 0) fail(id + ": z_m and recess_m must not be negative");
      if (f.z_m + f.height_m > corridors[i].height_m + 1e-9) fail(id + ": reaches above the ceiling");
      {
        const bool end = f.side == WallSide::kFromEnd || f.side == WallSide::kToEnd;
        const double half_w = corridors[i].width_m / 2;
        const double lo = end ? -half_w : -half_w, hi = end ? half_w : corridors[i].Length() + half_w;
        if (f.at_m - f.width_m / 2 < lo - 1e-9 || f.at_m + f.width_m / 2 > hi + 1e-9)
          fail(id + ": runs past the end of its wall");
      }
      if (f.recess_m > 0) {
        Eigen::Vector2d centre = Eigen::Vector2d::Zero(), n = Eigen::Vector2d::Zero(), along = Eigen::Vector2d::Zero();
        feature_frame(corridors[i], f, &centre, &n, &along);
        const Eigen::Vector2d a = centre - along * (f.width_m / 2), b = centre + along * (f.width_m / 2) + n * f.recess_m;
        recesses.push_back({std::min(a.x(), b.x()), std::min(a.y(), b.y()), std::max(a.x(), b.x()), std::max(a.y(), b.y())});
        recess_owner.push_back(static_cast<int>(i));
      }
    }
  }

  // Connectivity of the corridors (positive-area overlap).
  {
    const std::size_t n = corridors.size();
    std::vector<int> seen(n, 0), stack{0};
    seen[0] = 1;
    while (!stack.empty()) {
      const int a = stack.back();
      stack.pop_back();
      for (std::size_t b = 0; b < n; ++b) {
        if (seen[b]) continue;
        const Box2 &ra = corridors[a].rect, &rb = corridors[b].rect;
        const double ox = std::min(ra.x1, rb.x1) - std::max(ra.x0, rb.x0);
        const double oy = std::min(ra.y1, rb.y1) - std::max(ra.y0, rb.y0);
        if (ox > 1e-6 && oy > 1e-6) {
          seen[b] = 1;
          stack.push_back(static_cast<int>(b));
        }
      }
    }
    for (std::size_t b = 0; b < n; ++b)
      if (!seen[b])
        fail(fmt::format("corridors[{}] '{}' does not connect to corridors[0] '{}' (their floors must overlap)", b,
                         corridors[b].name, corridors[0].name));
  }

  // Compressed grid.
  std::vector<Box2> all;
  std::vector<int> owner;
  for (std::size_t i = 0; i < corridors.size(); ++i) {
    all.push_back(corridors[i].rect);
    owner.push_back(static_cast<int>(i));
  }
  for (std::size_t i = 0; i < recesses.size(); ++i) {
    all.push_back(recesses[i]);
    owner.push_back(recess_owner[i]);
  }
  {
    std::vector<double> xs, ys;
    for (const Box2& b : all) {
      xs.push_back(b.x0), xs.push_back(b.x1);
      ys.push_back(b.y0), ys.push_back(b.y1);
    }
    xs_ = Unique(xs);
    ys_ = Unique(ys);
  }
  const int nx = static_cast<int>(xs_.size()) - 1, ny = static_cast<int>(ys_.size()) - 1;
  free_.assign(static_cast<std::size_t>(nx) * ny, 0);
  std::vector<int> cell_owner(free_.size(), -1);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const Eigen::Vector2d c(0.5 * (xs_[i] + xs_[i + 1]), 0.5 * (ys_[j] + ys_[j + 1]));
      for (std::size_t k = 0; k < all.size(); ++k)
        if (all[k].Contains(c)) {
          free_[i * ny + j] = 1;
          if (cell_owner[i * ny + j] < 0) cell_owner[i * ny + j] = owner[k];
        }
    }
  auto is_free_cell = [&](int i, int j) { return i >= 0 && j >= 0 && i < nx && j < ny && free_[i * ny + j]; };

  // Walls: boundaries between free and solid cells, merged while the owner stays the same.
  walls.clear();
  auto add_wall = [&](bool along_x, double coord, double lo, double hi, Eigen::Vector2d normal, int corridor) {
    if (!walls.empty()) {
      WallSegment& w = walls.back();
      if (w.along_x == along_x && std::abs(w.coord - coord) < 1e-9 && std::abs(w.hi - lo) < 1e-9 && w.normal == normal &&
          w.corridor == corridor) {
        w.hi = hi;
        return;
      }
    }
    WallSegment w;
    w.along_x = along_x;
    w.coord = coord;
    w.lo = lo;
    w.hi = hi;
    w.normal = normal;
    w.corridor = corridor;
    w.material = corridors[corridor].wall_material;
    w.height_m = corridors[corridor].height_m;
    walls.push_back(w);
  };
  for (int i = 0; i <= nx; ++i)  // walls on x = xs_[i]
    for (int j = 0; j < ny; ++j) {
      const bool l = is_free_cell(i - 1, j), r = is_free_cell(i, j);
      if (l == r) continue;
      const int own = l ? cell_owner[(i - 1) * ny + j] : cell_owner[i * ny + j];
      add_wall(false, xs_[i], ys_[j], ys_[j + 1], Eigen::Vector2d(l ? -1.0 : 1.0, 0.0), own);
    }
  for (int j = 0; j <= ny; ++j)  // walls on y = ys_[j]
    for (int i = 0; i < nx; ++i) {
      const bool b = is_free_cell(i, j - 1), t = is_free_cell(i, j);
      if (b == t) continue;
      const int own = b ? cell_owner[i * ny + j - 1] : cell_owner[i * ny + j];
      add_wall(true, ys_[j], xs_[i], xs_[i + 1], Eigen::Vector2d(0.0, b ? -1.0 : 1.0), own);
    }

  // Decals on walls.
  decals.clear();
  for (std::size_t i = 0; i < corridors.size(); ++i) {
    for (std::size_t k = 0; k < corridors[i].features.size(); ++k) {
      const WallFeature& f = corridors[i].features[k];
      Eigen::Vector2d centre = Eigen::Vector2d::Zero(), n = Eigen::Vector2d::Zero(), along = Eigen::Vector2d::Zero();
      feature_frame(corridors[i], f, &centre, &n, &along);
      centre += n * f.recess_m;
      const bool wall_along_x = std::abs(n.y()) > 0.5;
      const double coord = wall_along_x ? centre.y() : centre.x();
      const double mid = wall_along_x ? centre.x() : centre.y();
      const double lo = mid - f.width_m / 2, hi = mid + f.width_m / 2;
      double covered = 0.0;
      for (std::size_t w = 0; w < walls.size(); ++w) {
        const WallSegment& ws = walls[w];
        if (ws.along_x != wall_along_x || std::abs(ws.coord - coord) > 1e-6 || ws.normal.dot(n) > -0.5) continue;
        const double a = std::max(lo, ws.lo), b = std::min(hi, ws.hi);
        if (b - a <= 1e-9) continue;
        decals.push_back({static_cast<int>(w), a, b, f.z_m, f.z_m + f.height_m, f.material});
        covered += b - a;
      }
      if (covered < f.width_m - 1e-6)
        fail(fmt::format("corridors[{}] '{}' features[{}]: the feature does not lie wholly on a wall (an opening or "
                         "junction is there, or it runs past the wall's end)",
                         i, corridors[i].name, k));
    }
  }

  // Lights inside their corridor.
  for (std::size_t i = 0; i < lights.size(); ++i)
    if (!IsFree(lights[i].centre))
      fail(fmt::format("light {} of corridor '{}' at ({:.2f}, {:.2f}) is outside the floor area", i,
                       lights[i].corridor >= 0 ? corridors[lights[i].corridor].name : "?", lights[i].centre.x(),
                       lights[i].centre.y()));

  // Obstacles and flat items inside the floor area, clear of walls.
  for (const Obstacle& o : obstacles) {
    if ((o.shape == Obstacle::Shape::kBox && (!(o.half_x > 0) || !(o.half_y > 0))) ||
        (o.shape == Obstacle::Shape::kCylinder && !(o.radius > 0)) || !(o.z1 > o.z0) || o.z0 < 0)
      fail(o.source + ": sizes must be positive");
    for (const Eigen::Vector2d& p : Outline(o))
      if (!IsFree(p)) fail(fmt::format("{} at ({:.2f}, {:.2f}) is inside or crosses a wall", o.source, o.centre.x(), o.centre.y()));
    for (const WallSegment& w : walls) {
      const Eigen::Vector2d a = w.along_x ? Eigen::Vector2d(w.lo, w.coord) : Eigen::Vector2d(w.coord, w.lo);
      const Eigen::Vector2d b = w.along_x ? Eigen::Vector2d(w.hi, w.coord) : Eigen::Vector2d(w.coord, w.hi);
      bool hit = FootprintDistance(a, o) <= 0 || FootprintDistance(b, o) <= 0;
      if (o.shape == Obstacle::Shape::kCylinder) hit = hit || SegmentDistance(o.centre, w) < o.radius;
      if (hit) fail(fmt::format("{} at ({:.2f}, {:.2f}) is inside or crosses a wall", o.source, o.centre.x(), o.centre.y()));
    }
  }
  for (const FlatItem& f : flat_items) {
    if (!(f.half_x > 0) || !(f.half_y > 0)) fail(f.source + ": sizes must be positive");
    const double c = std::cos(f.yaw), s = std::sin(f.yaw);
    for (int sx = -1; sx <= 1; sx += 2)
      for (int sy = -1; sy <= 1; sy += 2) {
        const Eigen::Vector2d p = f.centre + Eigen::Vector2d(c * sx * f.half_x - s * sy * f.half_y, s * sx * f.half_x + c * sy * f.half_y);
        if (!IsFree(p)) fail(fmt::format("{} at ({:.2f}, {:.2f}) reaches into a wall", f.source, f.centre.x(), f.centre.y()));
      }
  }

  // The robot's body (as mirrors show it).
  if (!(robot.body_above_camera_m >= 0) || !std::isfinite(robot.body_above_camera_m))
    fail("robot.body_above_camera_m must not be negative");
  if (!(robot.body_grey >= 0 && robot.body_grey <= 1)) fail("robot.body_grey must lie in [0, 1]");

  // The robot's start.
  const Eigen::Vector2d s = start.Translation();
  if (!IsFree(s) || DistanceToWalls(s) < robot.radius_m)
    fail(fmt::format("robot.start ({:.2f}, {:.2f}) puts the robot (radius {:.2f} m) inside or against a wall", s.x(), s.y(),
                     robot.radius_m));
  if (DistanceToObstacles(s) < robot.radius_m)
    fail(fmt::format("robot.start ({:.2f}, {:.2f}) puts the robot inside an obstacle", s.x(), s.y()));
}

bool World::IsFree(const Eigen::Vector2d& p) const {
  const int i = Interval(xs_, p.x()), j = Interval(ys_, p.y());
  if (i < 0 || j < 0) return false;
  return free_[static_cast<std::size_t>(i) * (ys_.size() - 1) + j] != 0;
}

double World::DistanceToWalls(const Eigen::Vector2d& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const WallSegment& w : walls) best = std::min(best, SegmentDistance(p, w));
  return best;
}

std::pair<double, int> World::NearestObstacle(const Eigen::Vector2d& p) const {
  double best = std::numeric_limits<double>::infinity();
  int best_i = -1;
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const double d = FootprintDistance(p, obstacles[i]);
    if (d < best) best = d, best_i = static_cast<int>(i);
  }
  return {best, best_i};
}

std::optional<std::pair<double, int>> World::CastWalls(const Eigen::Vector2d& p, const Eigen::Vector2d& dir) const {
  double best = std::numeric_limits<double>::infinity();
  int best_i = -1;
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const WallSegment& w = walls[i];
    double t, along;
    if (w.along_x) {
      if (std::abs(dir.y()) < 1e-12) continue;
      t = (w.coord - p.y()) / dir.y();
      along = p.x() + t * dir.x();
    } else {
      if (std::abs(dir.x()) < 1e-12) continue;
      t = (w.coord - p.x()) / dir.x();
      along = p.y() + t * dir.y();
    }
    if (t <= 1e-12 || t >= best || along < w.lo - 1e-9 || along > w.hi + 1e-9) continue;
    // Only walls seen from their free side.
    if (w.normal.dot(dir) >= 0) continue;
    best = t;
    best_i = static_cast<int>(i);
  }
  if (best_i < 0) return std::nullopt;
  return std::make_pair(best, best_i);
}

double World::CeilingAt(const Eigen::Vector2d& p) const {
  double h = 0.0;
  for (const Corridor& c : corridors)
    if (c.rect.Contains(p)) h = std::max(h, c.height_m);
  if (h == 0.0)
    for (std::size_t i = 0; i < recesses.size(); ++i)
      if (recesses[i].Contains(p)) h = std::max(h, corridors[recess_owner_[i]].height_m);
  return h;
}

Box2 World::Bounds() const {
  if (xs_.empty()) return {};
  return {xs_.front(), ys_.front(), xs_.back(), ys_.back()};
}

double World::CorridorLength() const {
  double s = 0;
  for (const Corridor& c : corridors) s += c.Length();
  return s;
}

}  // namespace squint::sim
