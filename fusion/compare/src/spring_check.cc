#include "wearscar/fusion/spring_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "wearscar/support/student_t.h"

namespace wearscar::fusion {

bool SpringCheckOptions::IsValid(std::string* why) const {
  if (early_cycles < 3 || !(max_stiffness_ratio > 1) ||
      !(min_elastic_share > 0 && min_elastic_share < 1)) {
    if (why) {
      *why =
          "spring check: early_cycles must be >= 3, max_stiffness_ratio > 1 "
          "and min_elastic_share in (0, 1)";
    }
    return false;
  }
  return true;
}

std::string SpringCheck::Describe(const std::string& how) const {
  return fmt::format(
      "the spring's stiffness appears to be {:.3g} N/mm (95%: {:.3g}-{:.3g}), "
      "not the {:g} N/mm {}: P/S is the scanned track times {:.2f} after its "
      "growth, and it grew from nothing (an elastic part would be there "
      "from the first cycle: {:.0f}% of the profile is); mu-hat is quoted "
      "with k from the scan, which needs no spring; give --spring if the "
      "rig's is known",
      ImpliedStiffness(),
      ImpliedLow(),
      ImpliedHigh(),
      used_n_per_mm,
      how,
      stiffness_ratio,
      100 * std::max(0.0, elastic_share));
}

namespace {

// One cycle's profile: the two directions' heights averaged per bin (NaN
// where neither has one).
std::vector<double> CycleProfile(const TrackHistory& h, int cycle) {
  const size_t bins = h.x_mm.size();
  std::vector<double> p(bins, NAN);
  for (size_t b = 0; b < bins; ++b) {
    double sum = 0;
    int n = 0;
    for (int d = 0; d < 2; ++d) {
      const double v = h.height_mm[h.Index(cycle, d, b)];
      if (std::isfinite(v)) sum += v, ++n;
    }
    if (n > 0) p[b] = sum / n;
  }
  return p;
}

// The mean profile of cycles [first, last].
std::vector<double> MeanProfile(const TrackHistory& h, int first, int last) {
  const size_t bins = h.x_mm.size();
  std::vector<double> sum(bins, 0.0), mean(bins, NAN);
  std::vector<int> n(bins, 0);
  for (int c = first; c <= last; ++c) {
    const std::vector<double> p = CycleProfile(h, c);
    for (size_t b = 0; b < bins; ++b) {
      if (std::isfinite(p[b])) sum[b] += p[b], ++n[b];
    }
  }
  for (size_t b = 0; b < bins; ++b) {
    if (n[b] > 0) mean[b] = sum[b] / n[b];
  }
  return mean;
}

// The projection of p on `late` (both less their means over the bins both
// hold): how much of late's shape p carries. NaN when late is flat.
double Projection(const std::vector<double>& p,
                  const std::vector<double>& late) {
  double sp = 0, sl = 0;
  int n = 0;
  for (size_t b = 0; b < p.size(); ++b) {
    if (std::isfinite(p[b]) && std::isfinite(late[b])) {
      sp += p[b], sl += late[b], ++n;
    }
  }
  if (n < 3) return NAN;
  sp /= n, sl /= n;
  double pl = 0, ll = 0;
  for (size_t b = 0; b < p.size(); ++b) {
    if (std::isfinite(p[b]) && std::isfinite(late[b])) {
      pl += (p[b] - sp) * (late[b] - sl);
      ll += (late[b] - sl) * (late[b] - sl);
    }
  }
  return ll > 0 ? pl / ll : NAN;
}

// How far the compared cycles' track had grown towards the final one the
// scan shows: their mean profile projected on the last cycles' (the last
// tenth, at least 3), which the scan's track is closest to.
double Growth(const TrackHistory& h, int first, int last) {
  const int n = h.cycles;
  const int tail = std::min(n, std::max(3, n / 10));
  const double g =
      Projection(MeanProfile(h, first, last), MeanProfile(h, n - tail, n - 1));
  return std::isfinite(g) && g > 0 ? g : 1.0;
}

}  // namespace

void EstimateElasticShare(const TrackHistory& history,
                          int first,
                          int last,
                          const SpringCheckOptions& o,
                          SpringCheck* check) {
  const int m = o.early_cycles;
  if (history.cycles < m || history.x_mm.empty() || first < 0 ||
      last >= history.cycles || last < first)
    return;
  const std::vector<double> late = MeanProfile(history, first, last);
  // Least squares p = a + b t over t = 1..m (the cycle's number): a is
  // the projection before the first cycle.
  std::vector<double> t, p;
  for (int c = 0; c < m; ++c) {
    const double v = Projection(CycleProfile(history, c), late);
    if (std::isfinite(v)) t.push_back(c + 1.0), p.push_back(v);
  }
  const int n = static_cast<int>(t.size());
  if (n < 3) return;
  double mt = 0, mp = 0;
  for (int i = 0; i < n; ++i) mt += t[i] / n, mp += p[i] / n;
  double stt = 0, stp = 0;
  for (int i = 0; i < n; ++i) {
    stt += (t[i] - mt) * (t[i] - mt);
    stp += (t[i] - mt) * (p[i] - mp);
  }
  const double b = stp / stt, a = mp - b * mt;
  double ss = 0;
  for (int i = 0; i < n; ++i) ss += std::pow(p[i] - a - b * t[i], 2);
  const double se = std::sqrt(ss / (n - 2) * (1.0 / n + mt * mt / stt));
  const double half = support::StudentT975(n - 2) * se;
  check->judged = true;
  check->elastic_share = a;
  check->elastic_share_low = a - half;
  check->elastic_share_high = a + half;
  check->elastic = a - half > o.min_elastic_share;
}

SpringCheck CheckSpring(const TrackHistory& history,
                        const Alignment* alignment,
                        int first,
                        int last,
                        double spring_n_per_mm,
                        const SpringCheckOptions& o) {
  SpringCheck c;
  c.used_n_per_mm = spring_n_per_mm;
  EstimateElasticShare(history, first, last, o, &c);
  if (!c.judged || alignment == nullptr ||
      !std::isfinite(alignment->amplitude_ratio_low) ||
      !std::isfinite(alignment->amplitude_ratio_high))
    return c;
  // The worn part's share of P/S, within [0, 1], its interval's ends
  // taken where they widen the ratio's; all of it where no elastic part
  // stands out of the share's noise (a noisy share would only bias it).
  auto worn = [&](double share) {
    return c.elastic ? std::clamp(1.0 - share, 0.0, 1.0) : 1.0;
  };
  c.growth = Growth(history, first, last);
  c.stiffness_ratio =
      alignment->amplitude_ratio * worn(c.elastic_share) / c.growth;
  c.stiffness_ratio_low =
      alignment->amplitude_ratio_low * worn(c.elastic_share_high) / c.growth;
  c.stiffness_ratio_high =
      alignment->amplitude_ratio_high * worn(c.elastic_share_low) / c.growth;
  c.contradicted = c.stiffness_ratio_low > o.max_stiffness_ratio ||
                   c.stiffness_ratio_high < 1.0 / o.max_stiffness_ratio;
  return c;
}

}  // namespace wearscar::fusion
