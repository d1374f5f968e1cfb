// Zone-dependent β classification with the refinement filter (eq. 4, §6.2).
#include "squint/obstacles/classifier.hpp"

#include <cmath>
#include <sstream>

namespace squint::obstacles {

std::string ClassifierOptions::Validate() const {
  std::ostringstream why;
  for (std::size_t z = 0; z < zones.size(); ++z) {
    const ZoneThreshold& t = zones[z];
    if (!(t.beta_m >= 0.0 && std::isfinite(t.beta_m))) why << "zone " << z << " beta_m must be finite and not negative; ";
    if (t.refine_high_m && !(*t.refine_high_m >= t.beta_m && std::isfinite(*t.refine_high_m)))
      why << "zone " << z << " refine_high_m must be finite and not below beta_m; ";
  }
  const std::string zoning_why = zoning.Validate();
  if (!zoning_why.empty()) why << "zoning: " << zoning_why << "; ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

std::optional<FeatureClass> ClassifyFeature(int zone, std::optional<double> discrepancy_m,
                                            const ClassifierOptions& options) {
  if (zone >= kHorizonZone) return FeatureClass::kObstacle;  // §4.1: λ < 0
  if (!discrepancy_m) return FeatureClass::kObstacle;        // no floor point: above the horizon
  const double d = *discrepancy_m;
  if (!options.zone_beta) return d > options.zones[0].beta_m ? FeatureClass::kObstacle : FeatureClass::kGround;
  const ZoneThreshold& t = options.zones[static_cast<std::size_t>(zone < 0 ? 0 : zone)];
  if (d <= t.beta_m) return FeatureClass::kGround;
  if (options.refinement && t.refine_high_m && d <= *t.refine_high_m) return std::nullopt;
  return FeatureClass::kObstacle;
}

}  // namespace squint::obstacles
