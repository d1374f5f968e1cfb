// A tracked image feature after inverse-perspective classification: the hand-over between
// obstacle detection (IPT) and the outline / contact-point / polar-map stages.
#pragma once

#include <Eigen/Core>
#include <optional>

namespace squint::obstacles {

enum class FeatureClass { kGround, kObstacle };

struct ClassifiedFeature {
  Eigen::Vector2d pixel;               // (u, v) in the later frame of the pair, as in the image
  Eigen::Vector2d previous_pixel;      // its match in the earlier frame
  std::optional<double> discrepancy_m; // D (paper eq. 4); none when classified above the horizon
  FeatureClass cls = FeatureClass::kGround;
};

}  // namespace squint::obstacles
