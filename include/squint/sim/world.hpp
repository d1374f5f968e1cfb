// Simulated buildings: a Manhattan floor plan of corridors with materials, lights, wall features
// (doors, posters, glass, windows, mirrors), standing obstacles and flat floor items, loaded
// from the YAML world format documented in docs/worlds.md.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "squint/core/camera.hpp"
#include "squint/core/pose.hpp"

namespace squint::sim {

// Procedural textures; each is a precomputed periodic lookup table (see textures.hpp).
enum class Texture { kPlain, kTiles, kSpeckle, kCarpet, kBrick, kPanels, kPoster, kWindow, kGlass };

struct Material {
  std::string name;
  double albedo = 0.5;                // diffuse reflectance in [0, 1]
  Texture texture = Texture::kPlain;
  double scale_m = 0.5;               // texture period (tile size, brick length, panel width)
  double contrast = 0.2;              // amplitude of the pattern in [0, 1]
  double emission = 0.0;              // self-lit radiance added (windows, glass); >= 0
  double mirror = 0.0;                // share of mirror reflection in [0, 1] (walls only)
};

// Axis-aligned rectangle in world metres.
struct Box2 {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  bool Contains(const Eigen::Vector2d& p, double margin = 0.0) const {
    return p.x() >= x0 - margin && p.x() <= x1 + margin && p.y() >= y0 - margin && p.y() <= y1 + margin;
  }
};

// Which wall of a corridor a feature sits on: left/right as seen walking from `from` to `to`,
// or the end walls behind `from` / beyond `to` (only meaningful at a dead end).
enum class WallSide { kLeft, kRight, kFromEnd, kToEnd };

struct WallFeature {
  enum class Kind { kDoor, kPoster, kGlassDoor, kWindow, kMirror };
  Kind kind = Kind::kDoor;
  WallSide side = WallSide::kLeft;
  double at_m = 0.0;      // centre: along the corridor from `from` (sides), or lateral offset (ends, left +)
  double width_m = 0.9;
  double height_m = 2.1;
  double z_m = 0.0;       // bottom edge above the floor
  double recess_m = 0.0;  // doors only: the wall steps back by this much over the door's width
  int material = -1;      // index into World::materials
};

struct Corridor {
  std::string name;
  Eigen::Vector2d from = Eigen::Vector2d::Zero();  // centre line end points (axis-aligned)
  Eigen::Vector2d to = Eigen::Vector2d::Zero();
  double width_m = 2.0;
  double height_m = 2.8;
  int floor_material = -1, wall_material = -1, ceiling_material = -1;
  std::vector<WallFeature> features;
  // Floor area: the centre line widened by width/2 on every side (so it also reaches width/2
  // beyond each end point; segments sharing an end point join cleanly).
  Box2 rect;

  Eigen::Vector2d Axis() const { return (to - from).normalized(); }  // unit, from -> to
  double Length() const { return (to - from).norm(); }
  bool AlongX() const { return std::abs(to.y() - from.y()) < 1e-9; }
};

struct Light {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double half_x = 0.3, half_y = 0.3;  // panel half sizes in world x / y
  double z_m = 2.8;                   // the ceiling it is set in
  double intensity = 1.0;             // irradiance it gives straight below at the floor
  bool on = true;
  int corridor = -1;
};

// A standing primitive: an oriented box or a vertical cylinder spanning z0..z1. A chair is
// several primitives (legs, seat, back) sharing one `source` entry name.
struct Obstacle {
  enum class Shape { kBox, kCylinder };
  Shape shape = Shape::kBox;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0.0;                     // radians (boxes)
  double half_x = 0.2, half_y = 0.2;    // box half sizes in its own frame
  double radius = 0.2;                  // cylinders
  double z0 = 0.0, z1 = 0.5;
  int material = -1;
  std::string source;                   // e.g. "obstacles[3] (chair)" for error messages
};

// Something lying flat on the floor (paper sheet, mat): floor-labelled, never collides.
struct FlatItem {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0.0;
  double half_x = 0.1, half_y = 0.15;
  int material = -1;
  std::string source;
};

// A maximal straight piece of the boundary of the floor area, facing into free space.
struct WallSegment {
  bool along_x = true;     // true: the wall lies on y = coord; false: on x = coord
  double coord = 0.0;
  double lo = 0.0, hi = 0.0;  // extent along the wall
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();  // unit, into the free space
  int corridor = -1;       // the corridor (or recess owner) it bounds
  int material = -1;
  double height_m = 2.8;
};

// A vertical rectangle painted on a wall (doors, posters, glass, windows, mirrors).
struct Decal {
  int wall = -1;         // WallSegment index
  double lo = 0.0, hi = 0.0;  // extent along the wall
  double z0 = 0.0, z1 = 2.0;
  int material = -1;
};

struct RobotSpec {
  double radius_m = 0.25;
  double max_speed_mps = 0.6;
  double max_turn_rate_dps = 90.0;
  // The body as mirrors show it (the renderer adds it to reflected rays only): a matte vertical
  // cylinder of radius_m on the floor around the rotation centre, reaching this far above the
  // camera's optical centre, with this diffuse reflectance (0..1).
  double body_above_camera_m = 0.1;
  double body_grey = 0.35;
};

// The camera mount as a world file gives it; Model() is the pinhole camera (square pixels,
// principal point at the image centre, no distortion).
struct CameraMount {
  double height_m = 0.6;
  double pitch_deg = -5.0;
  double hfov_deg = 60.0;
  int width = 320;
  int height = 240;
  CameraModel Model() const;
};

class World {
 public:
  std::string name;
  std::string source;  // file path or "builtin:NAME"; used in error messages
  CameraMount camera;
  RobotSpec robot;
  Pose2 start;
  double ambient = 0.12;  // irradiance everywhere, in light-intensity units

  std::vector<Material> materials;
  std::vector<Corridor> corridors;
  std::vector<Light> lights;
  std::vector<Obstacle> obstacles;
  std::vector<FlatItem> flat_items;
  // Derived by Build(): the floor area's boundary and the decals on it.
  std::vector<WallSegment> walls;
  std::vector<Decal> decals;
  std::vector<Box2> recesses;  // extra floor area behind recessed doors

  // Derives walls, decals and lookup grids, and validates the whole world; throws squint::Error
  // naming `source` and the entry at fault. Loaders call it; call it again after editing.
  void Build();

  // True when p lies in the floor area (inside some corridor or recess).
  bool IsFree(const Eigen::Vector2d& p) const;
  // Distance from p to the nearest wall segment (ignores obstacles).
  double DistanceToWalls(const Eigen::Vector2d& p) const;
  // Distance from p to the nearest standing obstacle footprint (infinity when none).
  double DistanceToObstacles(const Eigen::Vector2d& p) const { return NearestObstacle(p).first; }
  // Distance to the nearest obstacle footprint and its index (-1 and infinity when none).
  std::pair<double, int> NearestObstacle(const Eigen::Vector2d& p) const;
  // First wall met by the horizontal ray p + t * dir (dir unit), t > 0: distance and wall index.
  std::optional<std::pair<double, int>> CastWalls(const Eigen::Vector2d& p, const Eigen::Vector2d& dir) const;
  // Ceiling height over p (the highest corridor containing it; 0 when outside).
  double CeilingAt(const Eigen::Vector2d& p) const;
  // Bounding box of the floor area.
  Box2 Bounds() const;
  // Total length of corridor centre lines, metres.
  double CorridorLength() const;

 private:
  // Compressed grid of the floor area: cell (i, j) spans xs_[i]..xs_[i+1], ys_[j]..ys_[j+1].
  std::vector<double> xs_, ys_;
  std::vector<unsigned char> free_;
  std::vector<int> recess_owner_;
};

// A built-in world by name (see BuiltinWorldNames()) or a YAML file path. Throws squint::Error
// for an unknown name, a missing file, or a world that fails validation.
World LoadWorld(const std::string& name_or_path);
// Parses YAML text; `source` names it in errors.
World ParseWorld(const std::string& yaml_text, const std::string& source);
std::vector<std::string> BuiltinWorldNames();
// The YAML text of a built-in world, or none.
std::optional<std::string> BuiltinWorldText(const std::string& name);

}  // namespace squint::sim
