#include "wearscar/force/cof.h"

#include <algorithm>
#include <cmath>

#include "wearscar/support/numbers.h"

namespace wearscar::force {
namespace {

using support::Finite;
using support::kNaN;

// x where Q crosses zero in the stick transition after the reversal (the
// loop opening at Q = 0); NaN when Q does not change sign there (a wavy track
// can keep Q on one side through the reversal; crossings later in gross slip
// are not the opening).
double ZeroCrossing(const ForceRecord& r, const HalfCycle& half) {
  const auto& q = r.tangential_n;
  const auto& x = r.x_mm;
  const Eigen::Index limit = half.slip_begin > half.begin
                                 ? std::min(half.end, half.slip_begin + 1)
                                 : half.end;
  for (Eigen::Index i = half.begin; i + 1 < limit; ++i) {
    const double a = half.direction * q[i], b = half.direction * q[i + 1];
    if (a < 0 && b >= 0) {
      const double t = a / (a - b);
      return x[i] + t * (x[i + 1] - x[i]);
    }
  }
  return std::nan("");
}

// Correlation of |Q| with P over a half's gross-slip samples; NaN when
// either is constant or fewer than 3 samples are finite.
double QpCorrelation(const ForceRecord& r, const HalfCycle& h) {
  double sq = 0, sp = 0, sqq = 0, spp = 0, sqp = 0;
  long n = 0;
  for (Eigen::Index i = h.slip_begin; i < h.slip_end; ++i) {
    const double q = std::abs(r.tangential_n[i]), p = r.normal_n[i];
    const bool both = Finite(q) & Finite(p);
    sq += both ? q : -0.0;
    sp += both ? p : -0.0;
    sqq += both ? q * q : -0.0;
    spp += both ? p * p : -0.0;
    sqp += both ? q * p : -0.0;
    n += both;
  }
  if (n < 3) return std::nan("");
  const double cov = sqp - sq * sp / n;
  const double vq = sqq - sq * sq / n, vp = spp - sp * sp / n;
  return vq > 0 && vp > 0 ? cov / std::sqrt(vq * vp) : std::nan("");
}

}  // namespace

std::vector<CycleCof> ComputeClassicCof(const ForceRecord& record,
                                        const CycleSet& cycles) {
  std::vector<CycleCof> out;
  out.reserve(cycles.cycles.size());
  const auto& x = record.x_mm;
  const auto& q = record.tangential_n;
  const auto& p = record.normal_n;
  for (const Cycle& c : cycles.cycles) {
    CycleCof r;
    r.cycle = c.index;
    double sum_q = 0, sum_p = 0;
    long n = 0;
    for (const HalfCycle* h : {&c.forward, &c.reverse}) {
      for (Eigen::Index i = h->slip_begin; i < h->slip_end; ++i) {
        const bool both = Finite(q[i]) & Finite(p[i]);
        sum_q += both ? std::abs(q[i]) : -0.0;
        sum_p += both ? p[i] : -0.0;
        n += both;
      }
    }
    r.mean_normal_n = n > 0 ? sum_p / n : std::nan("");
    r.mu_mean = n > 0 ? sum_q / sum_p : std::nan("");
    // Loop area, trapezoids over the whole cycle: forward (dx > 0, Q > 0) and
    // reverse (dx < 0, Q < 0) both add positive work.
    double area = 0, xmin = INFINITY, xmax = -INFINITY;
    r.q_max_n = -INFINITY;
    r.q_min_n = INFINITY;
    r.p_max_n = -INFINITY;
    r.p_min_n = INFINITY;
    // (Without branches: NaN in place of a value that is not finite is
    // passed over by min and max, -0.0 adds nothing to a sum, not even to
    // a -0.0.)
    const Eigen::Index end = c.reverse.end, last = record.size() - 1;
    for (Eigen::Index i = c.forward.begin; i < end; ++i) {
      const double term =
          0.5 * (q[i] + q[i + (i < last)]) * (x[i + (i < last)] - x[i]);
      area +=
          (i < last) & Finite(q[i]) & Finite(q[i + (i < last)]) ? term : -0.0;
      const double xi = Finite(x[i]) ? x[i] : kNaN;
      const double qi = Finite(q[i]) ? q[i] : kNaN;
      const double pi = Finite(p[i]) ? p[i] : kNaN;
      xmin = std::min(xmin, xi);
      xmax = std::max(xmax, xi);
      r.q_max_n = std::max(r.q_max_n, qi);
      r.q_min_n = std::min(r.q_min_n, qi);
      r.p_max_n = std::max(r.p_max_n, pi);
      r.p_min_n = std::min(r.p_min_n, pi);
    }
    r.p_range_n = r.p_max_n - r.p_min_n;
    {
      const double f = QpCorrelation(record, c.forward);
      const double b = QpCorrelation(record, c.reverse);
      r.qp_correlation = std::isfinite(f) && std::isfinite(b) ? 0.5 * (f + b)
                         : std::isfinite(f)                   ? f
                                                              : b;
    }
    r.dissipated_energy_nmm = area;
    r.delta_max_mm = 0.5 * (xmax - xmin);
    const double xf = ZeroCrossing(record, c.forward);
    const double xr = ZeroCrossing(record, c.reverse);
    if (std::isfinite(xf) && std::isfinite(xr)) {
      r.delta_g_mm = 0.5 * (xr - xf);
    } else {
      // No sign change at a reversal: for a Coulomb loop the crossing sits
      // half-way through the stick travel, so delta_g = delta_max - half the
      // mean stick travel.
      const double stick =
          0.5 * (std::abs(x[c.forward.slip_begin] - x[c.forward.begin]) +
                 std::abs(x[c.reverse.slip_begin] - x[c.reverse.begin]));
      r.delta_g_mm = r.delta_max_mm - 0.5 * stick;
    }
    r.mu_energy_max = area / (4 * r.mean_normal_n * r.delta_max_mm);
    r.mu_energy_g = area / (4 * r.mean_normal_n * r.delta_g_mm);
    out.push_back(r);
  }
  return out;
}

}  // namespace wearscar::force
