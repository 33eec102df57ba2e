#pragma once

#include <functional>

namespace wearscar::support {

struct ScalarMinimum {
  double x = 0.0;
  double value = 0.0;
  int iterations = 0;
  bool converged = false;
  bool found = false;  // false when f is infinite on the whole grid
};

// Minimises f on [lo, hi]: a grid of `grid` points brackets the minimum,
// then Brent's method (golden section + parabolic steps) refines it.
ScalarMinimum MinimizeOnInterval(const std::function<double(double)>& f,
                                 double lo,
                                 double hi,
                                 int grid,
                                 double tolerance,
                                 int max_iterations);

}  // namespace wearscar::support
