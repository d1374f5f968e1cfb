// Per-frame ground truth as SEQUENCE_FORMAT.md defines it; each value is optional.
#pragma once

#include <optional>

namespace squint {

struct GroundTruth {
  std::optional<double> heading_deg;  // robot yaw relative to the corridor axis, left positive
  std::optional<double> lateral_m;    // offset from the corridor centre line, left positive
  std::optional<double> dist_end_m;   // along the axis, camera to the corridor's end wall
};

}  // namespace squint
