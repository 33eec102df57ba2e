#pragma once
// Linear interpolation in a sampled series, shared by the alignment (a
// profile on a uniform grid), the diagnosis (Q between samples) and the
// simulator (its grids along the plate). What happens outside the samples
// (NaN, or clamping) stays with the caller.

#include <Eigen/Core>
#include <algorithm>

namespace wearscar::support {

// v at the fractional index `position`, between v[i] and v[i + 1]
// (i = floor(position), kept within [0, size - 2]); exactly v[i] on a
// sample, whatever its neighbour holds. Needs size >= 2.
inline double InterpolateAtIndex(const Eigen::VectorXd& v, double position) {
  const Eigen::Index i = std::clamp<Eigen::Index>(
      static_cast<Eigen::Index>(position), 0, v.size() - 2);
  const double w = position - static_cast<double>(i);
  if (w == 0) return v[i];
  if (w == 1) return v[i + 1];  // the last sample
  return (1 - w) * v[i] + w * v[i + 1];
}

}  // namespace wearscar::support
