#pragma once

// Order statistics shared by the libraries.

#include <algorithm>
#include <cmath>
#include <utility>
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

// The q_low- and q_high-quantiles (q_low <= q_high) of v, as two calls of
// Percentile would give them, from one copy: the second selection looks
// only above the first.
inline std::pair<double, double> Percentiles(std::vector<double> v,
                                             double q_low,
                                             double q_high) {
  if (v.empty()) return {0.0, 0.0};
  const auto rank = [&v](double q) {
    return static_cast<long>(q * static_cast<double>(v.size() - 1));
  };
  const long lo = rank(q_low), hi = std::max(lo, rank(q_high));
  std::nth_element(v.begin(), v.begin() + lo, v.end());
  if (hi > lo) std::nth_element(v.begin() + lo + 1, v.begin() + hi, v.end());
  return {v[lo], v[hi]};
}

}  // namespace wearscar::support
