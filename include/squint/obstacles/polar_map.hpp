// The local polar occupancy map (obstacle paper §5.3): a semicircular region of interest in
// front of the robot, split into angular sectors; a sector holding contact points is occupied.
// Also readable as a range-per-bearing array, like a laser scan ("visual sonar").
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "squint/core/camera.hpp"
#include "squint/obstacles/contacts.hpp"

namespace squint::obstacles {

struct PolarMapOptions {
  double roi_radius_m = 1.5;  // paper §6.1
  double sector_deg = 5.0;    // must divide 180 into a whole number of sectors
  // Contact points a sector needs to be occupied (the paper's histogram: "a set of" points).
  int min_contacts = 1;
  // Beyond the paper: a sector without contacts is free only when at least min_ground_features
  // ground features' floor points lie in it within the ROI (evidence of floor, not just absence
  // of outlines: a plain wall has no vertical edges and so no contacts). Without that evidence
  // it is unseen. Off by default (the paper's map).
  bool free_needs_ground = false;
  int min_ground_features = 1;
  // Only ground points at least this far count as evidence (floor seen at r is free up to r).
  double min_ground_range_m = 0.0;

  std::string Validate() const;
};

enum class SectorState { kFree, kOccupied, kUnseen };

struct PolarSector {
  double start_deg = 0.0;   // lower bearing edge (right side); sectors run right to left
  double centre_deg = 0.0;
  double end_deg = 0.0;
  bool in_view = false;     // the floor at the ROI radius is inside the image across the sector
  SectorState state = SectorState::kUnseen;
  int contacts = 0;                // contact points inside the ROI
  // Ground features' floor points inside the ROI (beyond min_ground_range_m): floor evidence. A
  // free sector with none is free only for want of contacts (unknown, honestly); with
  // free_needs_ground it is unseen instead.
  int ground = 0;
  std::optional<double> range_m;   // nearest contact inside the ROI
  std::optional<double> nearest_m; // nearest contact at any range (the "visual sonar" reading)
};

struct PolarMap {
  double roi_radius_m = 0.0;
  double sector_deg = 0.0;
  std::vector<PolarSector> sectors;  // from -90° (right) to +90° (left)
};

// Builds maps into a buffer reused from frame to frame. A sector is occupied when it holds at
// least min_contacts contact points within the ROI (whether or not it is fully in view), free
// when it is in view and holds fewer (and, with free_needs_ground, enough ground points),
// unseen otherwise.
class PolarMapper {
 public:
  PolarMapper(const CameraModel& camera, PolarMapOptions options = {});

  // `ground_floor_m`: floor points (robot frame) of the ground features, used only with
  // free_needs_ground.
  const PolarMap& Build(std::span<const ContactPoint> contacts,
                        std::span<const Eigen::Vector2d> ground_floor_m = {});

  // Index of the sector holding a bearing in [-90, 90]; none outside.
  std::optional<int> SectorOf(double bearing_deg) const;
  const PolarMapOptions& Options() const { return options_; }
  const PolarMap& Map() const { return map_; }

 private:
  PolarMapOptions options_;
  PolarMap map_;
};

// Whether the floor point at `range_m` and `bearing_deg` projects inside the camera's image.
bool FloorBearingInView(const CameraModel& camera, double range_m, double bearing_deg);

}  // namespace squint::obstacles
