#pragma once

// Order statistics shared by the libraries. Private to wearscar's
// libraries (header-only, never installed).

#include <algorithm>
#include <cmath>
#include <vector>

namespace wearscar::support {

// The q-quantile (0..1) of v by selection (the element at floor(q (n-1))),
// 0 for an empty v; v is taken by value and reordered.
inline double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = static_cast<size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace wearscar::support
