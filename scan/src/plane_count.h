// RANSAC's inner loop for a plane: how many points lie within a distance
// of it, with the arithmetic of PCL's portable count (its points one by
// one through an index list) but over coordinates held column by column,
// which the compiler runs several points at a time.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace wearscar::scan {

// The smallest float t with t >= threshold (as doubles): for any float a,
// a < threshold exactly when a < t.
inline float FloatBelowWhich(double threshold) {
  float t = static_cast<float>(threshold);
  if (static_cast<double>(t) < threshold) t = std::nextafter(t, INFINITY);
  return t;
}

// Points i < n with |a x + b y + c z + d| < threshold, the plane (a, b, c,
// d) in float. Each distance is PCL's to the bit: its Eigen dot product of
// (a, b, c, d) with (x, y, z, 1) sums the products pairwise, (a x + c z) +
// (b y + d), in float, and compares its magnitude with the threshold in
// double.
inline std::size_t CountWithinPlane(const float* x,
                                    const float* y,
                                    const float* z,
                                    std::size_t n,
                                    const float plane[4],
                                    double threshold) {
  const float a = plane[0], b = plane[1], c = plane[2], d = plane[3];
  const float t = FloatBelowWhich(threshold);
  std::uint32_t inside = 0;
  std::size_t total = 0;
  // Blocks short enough for a 32-bit count (several points a step).
  constexpr std::size_t kBlock = std::size_t{1} << 30;
  for (std::size_t start = 0; start < n; start += kBlock) {
    const std::size_t end = n - start > kBlock ? start + kBlock : n;
    inside = 0;
    for (std::size_t i = start; i < end; ++i) {
      const float s = (a * x[i] + c * z[i]) + (b * y[i] + d);
      inside += std::abs(s) < t ? 1u : 0u;
    }
    total += inside;
  }
  return total;
}

}  // namespace wearscar::scan
