// The feature classifier (eq. 4 with a zone-dependent β, §6.2) and its refinement filter: in the
// zones that have one, features whose D lies in (β, refine_high] are left unclassified.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "squint/obstacles/feature.hpp"
#include "squint/obstacles/zones.hpp"

namespace squint::obstacles {

struct ZoneThreshold {
  // Largest D (metres) of a ground point in this zone.
  double beta_m = 0.021;
  // Refinement: features with beta_m < D <= refine_high_m are not classified. None = no filter.
  std::optional<double> refine_high_m;
};

struct ClassifierOptions {
  // β of zones 0, 1, 2 (zone 3, above the horizon, needs none). Defaults from the paper: 21 mm in
  // zone 0, 20–30 mm in zone 1 with the 20–85 mm refinement band, 30–150 mm in zone 2.
  std::array<ZoneThreshold, 3> zones = {ZoneThreshold{0.021, std::nullopt}, ZoneThreshold{0.025, 0.085},
                                        ZoneThreshold{0.090, std::nullopt}};
  // When false, one β (zones[0].beta_m) for every zone and no refinement (the paper's baseline).
  bool zone_beta = true;
  bool refinement = true;
  ZoneOptions zoning;

  std::string Validate() const;
};

// A classification, or none when the refinement filter leaves the feature unclassified.
// `discrepancy_m` is ignored (may be none) in zone 3.
std::optional<FeatureClass> ClassifyFeature(int zone, std::optional<double> discrepancy_m,
                                            const ClassifierOptions& options);

}  // namespace squint::obstacles
