// Image zones for the zone-dependent threshold β (paper §4.2, §6.2): the D(u, v) map of the
// configured camera and motion by the paper's simulation (eq. 11–15), and the rows that split it.
#pragma once

#include <string>
#include <vector>

#include "squint/core/camera.hpp"

namespace squint::obstacles {

// Zone 3: above the horizon (obstacle without D). Zone 2: below the horizon while the simulated D is
// high (its peak). Zone 1: D falls gradually. Zone 0: the bottom rows, where the DST sphere lies
// under the floor and the simulated D vanishes (points there are floor points at close range).
inline constexpr int kZoneCount = 4;
inline constexpr int kHorizonZone = 3;

struct ZoneOptions {
  // Camera-to-point distance DST of the simulation (eq. 12), the radius of the region of interest.
  double dst_m = 1.5;
  // Forward motion between the two simulated frames (the paper: 31 mm).
  double step_m = 0.031;
  // Zone 2 (going down from the horizon) ends at the first row whose simulated D (the largest over
  // the row) falls below this level. D grows without bound towards the horizon, so a fraction of
  // the peak would leave zone 2 a few rows wide; the paper's zone 2 holds D of 30–150 mm.
  double zone2_min_d_m = 0.08;
  // Zone 0 starts at the first row whose simulated D is at most this level (the DST sphere lies
  // under the floor there: close floor points).
  double zone0_max_d_m = 0.001;

  std::string Validate() const;
};

// D for every pixel (row-major, height × width, metres) for a scene point at distance DST along each
// pixel's ray, seen again after the camera moved `step_m` forward (§4.2 steps I–III). Points that
// the sphere puts under the floor are taken on the floor (D = 0), as in the paper's figure 5.
std::vector<double> SimulateDiscrepancyMap(const CameraModel& camera, const ZoneOptions& options);

// The zone rows of one camera.
struct ZoneLayout {
  double horizon_row = 0.0;  // rows v < horizon_row are zone 3
  double zone2_end_row = 0.0;  // zone 2: [horizon_row, zone2_end_row)
  double zone1_end_row = 0.0;  // zone 1: [zone2_end_row, zone1_end_row); zone 0 below

  int ZoneOfRow(double v) const {
    if (v < horizon_row) return 3;
    if (v < zone2_end_row) return 2;
    if (v < zone1_end_row) return 1;
    return 0;
  }
};

// Derives the zone rows from the simulated map (the per-row maximum of D over the columns).
ZoneLayout ComputeZoneLayout(const CameraModel& camera, const ZoneOptions& options);

}  // namespace squint::obstacles
