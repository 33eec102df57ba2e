#include "wearscar/force/turn_delay.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wearscar::force {
namespace {

// One turn's delay in samples: the turn at `turn` (x's extremum), its
// stick to `slip`; `pre` samples before the turn anchor the slip level F.
double HingeDelay(const ForceRecord& r,
                  Eigen::Index turn,
                  Eigen::Index slip,
                  int reach,
                  int pre) {
  const Eigen::Index begin = turn - pre, end = slip + 1;
  if (slip - turn < 3 || begin - reach < 0 || end > r.size() ||
      turn - reach < 0)
    return NAN;
  const double xr = r.x_mm[turn];
  std::vector<double> cost(2 * reach + 1, INFINITY);
  for (int d = -reach; d <= reach; ++d) {
    double sg = 0, sq = 0, sgg = 0, sgq = 0, sqq = 0;
    const double n = static_cast<double>(end - begin);
    for (Eigen::Index i = begin; i < end; ++i) {
      const Eigen::Index j = i - d;
      const double g = j >= turn && j < r.size() ? r.x_mm[j] - xr : 0.0;
      const double q = r.tangential_n[i];
      sg += g, sq += q, sgg += g * g, sgq += g * q, sqq += q * q;
    }
    const double vg = sgg - sg * sg / n, cgq = sgq - sg * sq / n;
    const double vq = sqq - sq * sq / n;
    if (vg > 0 && std::isfinite(vq)) cost[d + reach] = vq - cgq * cgq / vg;
  }
  const int best = static_cast<int>(std::min_element(cost.begin(), cost.end()) -
                                    cost.begin());
  if (best == 0 || best == 2 * reach || !std::isfinite(cost[best])) return NAN;
  const double a = cost[best - 1], b = cost[best], c = cost[best + 1];
  const double curvature = a - 2 * b + c;
  return best - reach + (curvature > 0 ? 0.5 * (a - c) / curvature : 0.0);
}

// The median of Q over [begin, end).
double MedianQ(const ForceRecord& r, Eigen::Index begin, Eigen::Index end) {
  std::vector<double> v;
  for (Eigen::Index i = std::max<Eigen::Index>(begin, 0);
       i < std::min(end, r.size());
       ++i) {
    if (std::isfinite(r.tangential_n[i])) v.push_back(r.tangential_n[i]);
  }
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Where the stick after the turn ends, as Q shows it: the first sample
// from which Q has come nine tenths of the way from its slip level before
// the turn (the end of the previous half's gross slip) to the one after
// (the start of this half's: near the turn, where friction along the
// track is what it is at the turn); -1 where it never does.
Eigen::Index StickEnd(const ForceRecord& r,
                      const HalfCycle& before,
                      const HalfCycle& h,
                      int near) {
  const double from = MedianQ(
      r, std::max(before.slip_begin, before.slip_end - near), before.slip_end);
  const double to =
      MedianQ(r, h.slip_begin, std::min(h.slip_end, h.slip_begin + near));
  if (!std::isfinite(from) || !std::isfinite(to) || from == to) return -1;
  for (Eigen::Index i = h.begin; i < h.end; ++i) {
    if ((r.tangential_n[i] - from) / (to - from) >= 0.9) return i;
  }
  return -1;
}

}  // namespace

TurnDelay MeasureTurnDelay(const ForceRecord& record,
                           const CycleSet& cycles,
                           int first,
                           int last) {
  TurnDelay t;
  const Eigen::Index n = record.size();
  if (n < 2) return t;
  const double dt =
      (record.time_s[n - 1] - record.time_s[0]) / static_cast<double>(n - 1);
  if (!(dt > 0)) return t;
  const int reach = std::clamp(static_cast<int>(0.03 / dt), 2, 400);
  const int pre = std::clamp(static_cast<int>(0.005 / dt), 3, 50);
  const int near = std::clamp(static_cast<int>(0.01 / dt), 3, 100);
  std::vector<double> delays;
  first = std::max(first, 0);
  last = std::min(last, static_cast<int>(cycles.cycles.size()) - 1);
  for (int c = first; c <= last; ++c) {
    const Cycle& cycle = cycles.cycles[c];
    // Each half with the half before it (a forward half's is the previous
    // cycle's reverse).
    const HalfCycle* before = c > 0 ? &cycles.cycles[c - 1].reverse : nullptr;
    for (const HalfCycle* h : {&cycle.forward, &cycle.reverse}) {
      if (before) {
        const Eigen::Index end = StickEnd(record, *before, *h, near);
        const double d =
            end > 0 ? HingeDelay(record, h->begin, end, reach, pre) : NAN;
        if (std::isfinite(d)) delays.push_back(d * dt);
      }
      before = h;
    }
  }
  if (delays.size() < 4) return t;
  std::sort(delays.begin(), delays.end());
  const size_t m = delays.size();
  const double median = delays[m / 2];
  // The median's standard error, 1.2533 sd / sqrt(n) for a normal
  // scatter, its sd from the median absolute deviation (a turn whose stick
  // a band's edge or a spike disturbs does not widen it).
  std::vector<double> deviation;
  for (double d : delays) deviation.push_back(std::abs(d - median));
  std::nth_element(
      deviation.begin(), deviation.begin() + m / 2, deviation.end());
  t.delay_s = median;
  t.delay_se_s =
      1.2533 * 1.4826 * deviation[m / 2] / std::sqrt(static_cast<double>(m));
  t.turns = static_cast<int>(m);
  return t;
}

}  // namespace wearscar::force
