// Private helper: the extremum of a per-column score curve, its prominence and sub-pixel place.
#pragma once

#include <array>

#include "squint/corridor/glance.hpp"
#include "squint/corridor/measure.hpp"

namespace squint::corridor::detail {

struct Peak {
  double column = 0.0;
  double prominence = 0.0;  // (peak − median) / (max − min) over the scored columns
  Reason reason = Reason::kNone;
};

// The maximum of curve[first..last] (inclusive). kFlatCurve when max == min or the prominence is
// below min_prominence; kPeakAtBorder when the argmax is the first or last scored column or lies
// within border_px of the glance edge.
// The column is refined by a parabola through the argmax and its neighbours.
Peak FindPeak(const std::array<float, kGlanceWidth>& curve, int first, int last, int border_px,
              double min_prominence);

}  // namespace squint::corridor::detail
