#include "minimize.h"

#include <cmath>
#include <limits>

namespace wearscar::fusion::internal {

ScalarMinimum MinimizeOnInterval(const std::function<double(double)>& f,
                                 double lo,
                                 double hi,
                                 int grid,
                                 double tolerance,
                                 int max_iterations) {
  ScalarMinimum m;
  const double h = (hi - lo) / (grid - 1);
  int best = -1;
  double best_f = std::numeric_limits<double>::infinity();
  for (int i = 0; i < grid; ++i) {
    const double v = f(lo + i * h);
    if (v < best_f) {
      best_f = v;
      best = i;
    }
  }
  if (best < 0) return m;
  m.found = true;
  double a = lo + std::max(0, best - 1) * h;
  double b = lo + std::min(grid - 1, best + 1) * h;
  constexpr double kGolden = 0.3819660112501051;
  double x = lo + best * h, w = x, v = x;
  double fx = best_f, fw = fx, fv = fx;
  double d = 0, e = 0;
  int iter = 0;
  for (; iter < max_iterations; ++iter) {
    const double mid = 0.5 * (a + b);
    const double tol1 = tolerance + 1e-10 * std::abs(x), tol2 = 2 * tol1;
    if (std::abs(x - mid) <= tol2 - 0.5 * (b - a)) {
      m.converged = true;
      break;
    }
    bool golden = true;
    if (std::abs(e) > tol1) {
      const double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2 * (q - r);
      if (q > 0) p = -p;
      q = std::abs(q);
      const double etemp = e;
      e = d;
      if (std::abs(p) < std::abs(0.5 * q * etemp) && p > q * (a - x) &&
          p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = x < mid ? tol1 : -tol1;
        golden = false;
      }
    }
    if (golden) {
      e = (x >= mid ? a : b) - x;
      d = kGolden * e;
    }
    const double u = std::abs(d) >= tol1 ? x + d : x + (d > 0 ? tol1 : -tol1);
    const double fu = f(u);
    if (fu <= fx) {
      (u >= x ? a : b) = x;
      v = w;
      fv = fw;
      w = x;
      fw = fx;
      x = u;
      fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w;
        fv = fw;
        w = u;
        fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u;
        fv = fu;
      }
    }
  }
  m.x = x;
  m.value = fx;
  m.iterations = iter;
  return m;
}

}  // namespace wearscar::fusion::internal
