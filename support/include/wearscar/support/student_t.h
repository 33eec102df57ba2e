#pragma once

#include <algorithm>
#include <cmath>

namespace wearscar::support {

// Two-sided 95% quantile of Student's t with `df` degrees of freedom
// (t_0.975); the normal quantile beyond 30.
inline double StudentT975(int df) {
  static constexpr double kTable[] = {
      12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
      2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
      2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (df < 1) return std::nan("");
  if (df <= 30) return kTable[df - 1];
  return 1.96;
}

}  // namespace wearscar::support
