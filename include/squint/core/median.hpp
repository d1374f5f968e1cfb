// The median of a set of values, taken in place (no allocation): the middle value, or the mean of
// the two middle values for an even count; 0 for none. Reorders `values`.
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>

namespace squint {

inline double MedianInPlace(std::span<double> values) {
  if (values.empty()) return 0.0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  double m = values[mid];
  if (values.size() % 2 == 0) m = 0.5 * (m + *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid)));
  return m;
}

}  // namespace squint
