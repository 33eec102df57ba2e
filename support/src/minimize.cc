#include "wearscar/support/minimize.h"

#include <cmath>
#include <limits>

namespace wearscar::support {
namespace {

// Brent's bracket: the abscissae a < b, the best point x, the second best
// w and the previous w, v, their values, and the last two steps d, e.
struct Bracket {
  double a, b, x, w, v, fx, fw, fv, d = 0, e = 0;
};

// Brent's step from x: the parabola through x, w, v where it falls inside
// the bracket and shrinks fast enough, else a golden-section step into the
// larger part.
double BrentStep(Bracket* k, double mid, double tol1, double tol2) {
  constexpr double kGolden = 0.3819660112501051;
  Bracket& b = *k;
  if (std::abs(b.e) > tol1) {
    const double r = (b.x - b.w) * (b.fx - b.fv);
    double q = (b.x - b.v) * (b.fx - b.fw);
    double p = (b.x - b.v) * q - (b.x - b.w) * r;
    q = 2 * (q - r);
    if (q > 0) p = -p;
    q = std::abs(q);
    const double etemp = b.e;
    b.e = b.d;
    if (std::abs(p) < std::abs(0.5 * q * etemp) && p > q * (b.a - b.x) &&
        p < q * (b.b - b.x)) {
      b.d = p / q;
      const double u = b.x + b.d;
      if (u - b.a < tol2 || b.b - u < tol2) b.d = b.x < mid ? tol1 : -tol1;
      return b.d;
    }
  }
  b.e = (b.x >= mid ? b.a : b.b) - b.x;
  b.d = kGolden * b.e;
  return b.d;
}

// The bracket after f(u) = fu.
void Update(double u, double fu, Bracket* k) {
  Bracket& b = *k;
  if (fu <= b.fx) {
    (u >= b.x ? b.a : b.b) = b.x;
    b.v = b.w;
    b.fv = b.fw;
    b.w = b.x;
    b.fw = b.fx;
    b.x = u;
    b.fx = fu;
    return;
  }
  (u < b.x ? b.a : b.b) = u;
  if (fu <= b.fw || b.w == b.x) {
    b.v = b.w;
    b.fv = b.fw;
    b.w = u;
    b.fw = fu;
  } else if (fu <= b.fv || b.v == b.x || b.v == b.w) {
    b.v = u;
    b.fv = fu;
  }
}

}  // namespace

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
  Bracket k;
  k.a = lo + std::max(0, best - 1) * h;
  k.b = lo + std::min(grid - 1, best + 1) * h;
  k.x = k.w = k.v = lo + best * h;
  k.fx = k.fw = k.fv = best_f;
  int iter = 0;
  for (; iter < max_iterations; ++iter) {
    const double mid = 0.5 * (k.a + k.b);
    const double tol1 = tolerance + 1e-10 * std::abs(k.x), tol2 = 2 * tol1;
    if (std::abs(k.x - mid) <= tol2 - 0.5 * (k.b - k.a)) {
      m.converged = true;
      break;
    }
    const double d = BrentStep(&k, mid, tol1, tol2);
    const double u =
        std::abs(d) >= tol1 ? k.x + d : k.x + (d > 0 ? tol1 : -tol1);
    Update(u, f(u), &k);
  }
  m.x = k.x;
  m.value = k.fx;
  m.iterations = iter;
  return m;
}

}  // namespace wearscar::support
