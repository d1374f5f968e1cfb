// The extremum of a per-column score curve (shared by the heading measures).
#include "curve_peak.hpp"

#include <algorithm>

namespace squint::corridor::detail {

Peak FindPeak(const std::array<float, kGlanceWidth>& curve, int first, int last, int border_px,
              double min_prominence) {
  Peak peak;
  if (last < first) {
    peak.reason = Reason::kFlatCurve;
    return peak;
  }
  int best = first;
  float lo = curve[first], hi = curve[first];
  std::array<float, kGlanceWidth> sorted{};
  int n = 0;
  for (int x = first; x <= last; ++x) {
    if (curve[x] > curve[best]) best = x;
    lo = std::min(lo, curve[x]);
    hi = std::max(hi, curve[x]);
    sorted[n++] = curve[x];
  }
  if (!(hi > lo)) {
    peak.reason = Reason::kFlatCurve;
    return peak;
  }
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.begin() + n);
  const double median = sorted[n / 2];
  peak.prominence = (hi - median) / (hi - lo);
  double column = best;
  if (best > first && best < last) {
    const double a = curve[best - 1], b = curve[best], c = curve[best + 1];
    const double denom = a - 2.0 * b + c;
    if (denom < 0.0) column += std::clamp(0.5 * (a - c) / denom, -0.5, 0.5);
  }
  peak.column = column;
  // An argmax on the first or last scored column may be a slope running out of the view, not a
  // peak; so is one within border_px of the glance edge.
  if (best == first || best == last || best < border_px || best > kGlanceWidth - 1 - border_px) {
    peak.reason = Reason::kPeakAtBorder;
  } else if (peak.prominence < min_prominence) {
    peak.reason = Reason::kFlatCurve;
  }
  return peak;
}

}  // namespace squint::corridor::detail
