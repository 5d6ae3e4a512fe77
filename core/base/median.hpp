#pragma once
// The median of a sample, shared by the trackers and the loop's analyses.
#include <algorithm>
#include <limits>
#include <vector>

namespace sb {

// The middle value; for an even count the mean of the two middle ones; NaN for none. Takes a copy to reorder.
inline double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  if (v.size() % 2) return v[mid];
  const double hi = v[mid];
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
}

}  // namespace sb
