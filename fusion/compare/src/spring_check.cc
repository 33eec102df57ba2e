#include "wearscar/fusion/spring_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "wearscar/support/student_t.h"

namespace wearscar::fusion {

bool SpringCheckOptions::IsValid(std::string* why) const {
  if (!(max_stiffness_ratio > 1) ||
      !(min_elastic_share > 0 && min_elastic_share < 1) ||
      !(max_split_width > 0 && max_split_width < 1) ||
      !(min_growth_to_noise > 1) || !(max_q_delay_s > 0)) {
    if (why) {
      *why =
          "spring check: max_stiffness_ratio must be > 1, min_elastic_share "
          "and max_split_width in (0, 1), min_growth_to_noise > 1, "
          "max_q_delay_s > 0";
    }
    return false;
  }
  return true;
}

bool SpringCheck::SplitsTheStiffness() const {
  return changing_groove.Held() && elastic_share_low > 0;
}
double SpringCheck::StiffnessRatio() const {
  return SplitsTheStiffness()     ? stiffness_ratio
         : changing_groove.Held() ? end_ratio
                                  : path_ratio;
}
double SpringCheck::ImpliedStiffness() const {
  return used_n_per_mm * StiffnessRatio();
}
double SpringCheck::ImpliedLow() const {
  return used_n_per_mm * (SplitsTheStiffness()     ? stiffness_ratio_low
                          : changing_groove.Held() ? end_ratio_low
                                                   : path_ratio_low);
}
double SpringCheck::ImpliedHigh() const {
  return used_n_per_mm * (SplitsTheStiffness()     ? stiffness_ratio_high
                          : changing_groove.Held() ? end_ratio_high
                                                   : path_ratio_high);
}

std::string SpringCheck::Describe(const std::string& how) const {
  // What the path ratio says of the stiffness, then how it was decided: a
  // bound where the groove did not change, else the growth's split.
  const std::string tail =
      UpperBoundOnly()
          ? fmt::format(
                "; cannot tell a spring of {:.3g} N/mm from a softer one "
                "beside an elastic part (the sphere sinking further into "
                "softer wood adds to P/S in the worn track's shape), and the "
                "groove did not change during the record to split them; give "
                "--spring, or record from the first contact",
                ImpliedStiffness())
      : SplitsTheStiffness()
          ? fmt::format(
                " as the groove grew, beside an elastic part that "
                "does not follow the growth ({:.0f}% of the worn "
                "track's profile); give --spring if the rig's is "
                "known",
                100 * elastic_share)
          : fmt::format(
                " at the end of the record; the groove's growth "
                "shows no elastic part beside it ({:.0f}%, 95% "
                "{:.0f} to {:.0f}%); give --spring if the rig's is "
                "known",
                100 * elastic_share,
                100 * elastic_share_low,
                100 * elastic_share_high);
  return fmt::format(
      "the spring's stiffness appears to be {}{:.3g} N/mm (95%: "
      "{:.3g}-{:.3g}), not the {:g} N/mm {}: P/S is the path the friction "
      "shows times {:.2f}{}",
      UpperBoundOnly() ? "at most " : "",
      ImpliedStiffness(),
      ImpliedLow(),
      ImpliedHigh(),
      used_n_per_mm,
      how,
      StiffnessRatio(),
      tail);
}

std::string SpringCheck::DescribeUndecided(const std::string& how) const {
  return fmt::format(
      "cannot tell a spring of {:.3g} N/mm from an elastic part: P/S is the "
      "path the friction shows times {:.2f} (95%: {:.2f}-{:.2f}), which "
      "either a spring of that stiffness (not the {:g} N/mm {}) or an "
      "elastic part of {:.0f}% of the worn track's profile (the sphere "
      "sinking further into softer wood) explains, and the groove did not "
      "change during the record to split them ({}); give --spring, or "
      "record from the first contact",
      ImpliedStiffness(),
      path_ratio,
      path_ratio_low,
      path_ratio_high,
      used_n_per_mm,
      how,
      100 * (path_ratio - 1),
      changing_groove.evidence);
}

std::string SpringCheck::DescribeElastic(
    const std::string& profile_name) const {
  return fmt::format(
      "{} carries an elastic part: {:.0f}% of the worn track's profile at "
      "the end (95% interval {:.0f}-{:.0f}%), which does not follow the "
      "path's growth that the friction shows (it was there without wear)",
      profile_name,
      100 * elastic_share,
      100 * elastic_share_low,
      100 * elastic_share_high);
}

namespace {

// One cycle's P/S profile, the two directions averaged per bin (NaN where
// neither has one).
std::vector<double> SpringRow(const TrackHistory& h, int cycle) {
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

std::vector<double> FrictionRow(const TrackHistory& h, int cycle) {
  const auto from = h.friction_height_mm.begin() +
                    static_cast<std::ptrdiff_t>(h.FrictionIndex(cycle, 0));
  return std::vector<double>(from,
                             from + static_cast<std::ptrdiff_t>(h.x_mm.size()));
}

// The mean of rows [first, last] per bin, where every row has the bin.
template <typename Row>
std::vector<double> MeanRow(const TrackHistory& h,
                            int first,
                            int last,
                            Row row) {
  std::vector<double> mean(h.x_mm.size(), 0.0);
  for (int c = first; c <= last; ++c) {
    const std::vector<double> r = row(h, c);
    for (size_t b = 0; b < r.size(); ++b) mean[b] += r[b];
  }
  for (double& m : mean) m /= (last - first + 1);
  return mean;
}

// v less its least-squares line in x over the bins in `use`.
std::vector<double> Detrended(const std::vector<double>& v,
                              const std::vector<double>& x,
                              const std::vector<size_t>& use) {
  double mx = 0, mv = 0;
  for (size_t b : use) mx += x[b], mv += v[b];
  mx /= use.size(), mv /= use.size();
  double sxx = 0, sxv = 0;
  for (size_t b : use) {
    sxx += (x[b] - mx) * (x[b] - mx);
    sxv += (x[b] - mx) * (v[b] - mv);
  }
  const double slope = sxx > 0 ? sxv / sxx : 0;
  std::vector<double> d(use.size());
  for (size_t i = 0; i < use.size(); ++i)
    d[i] = v[use[i]] - mv - slope * (x[use[i]] - mx);
  return d;
}

// How much of the shape `w` the row `v` carries over the bins in `use`
// (each less its line in x: an offset in Q, integrated, is a line in the
// friction's path): sum v w / sum w w.
double Projection(const std::vector<double>& v,
                  const std::vector<double>& w,
                  const std::vector<double>& x,
                  const std::vector<size_t>& use) {
  const std::vector<double> dv = Detrended(v, x, use),
                            dw = Detrended(w, x, use);
  double vw = 0, ww = 0;
  for (size_t i = 0; i < dv.size(); ++i)
    vw += dv[i] * dw[i], ww += dw[i] * dw[i];
  return ww > 0 ? vw / ww : NAN;
}

// The projections p_c (P/S) and f_c (the friction's path) of the cycles
// that hold at least 80% of the bins both hold over the compared cycles.
struct Projections {
  std::vector<int> cycle;
  std::vector<double> p, f;
  double shape_correlation = NAN;  // P/S's and the friction's compared shapes
};

Projections Project(const TrackHistory& h,
                    int steady_from,
                    int first,
                    int last) {
  Projections out;
  const std::vector<double> w = MeanRow(h, first, last, SpringRow);
  const std::vector<double> fw = MeanRow(h, first, last, FrictionRow);
  std::vector<size_t> common;
  for (size_t b = 0; b < w.size(); ++b) {
    if (std::isfinite(w[b]) && std::isfinite(fw[b])) common.push_back(b);
  }
  if (common.size() < 8) return out;
  const std::vector<double> dw = Detrended(w, h.x_mm, common),
                            df = Detrended(fw, h.x_mm, common);
  double wf = 0, ww = 0, ff = 0;
  for (size_t i = 0; i < dw.size(); ++i)
    wf += dw[i] * df[i], ww += dw[i] * dw[i], ff += df[i] * df[i];
  out.shape_correlation = ww > 0 && ff > 0 ? wf / std::sqrt(ww * ff) : NAN;
  for (int c = steady_from; c < h.cycles; ++c) {
    const std::vector<double> p = SpringRow(h, c), f = FrictionRow(h, c);
    std::vector<size_t> use;
    for (size_t b : common) {
      if (std::isfinite(p[b]) && std::isfinite(f[b])) use.push_back(b);
    }
    if (use.size() < 0.8 * common.size()) continue;
    const double pc = Projection(p, w, h.x_mm, use);
    const double fc = Projection(f, w, h.x_mm, use);
    if (!std::isfinite(pc) || !std::isfinite(fc)) continue;
    out.cycle.push_back(c), out.p.push_back(pc), out.f.push_back(fc);
  }
  return out;
}

double Mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / v.size();
}

// The white noise of a slowly changing per-cycle series: its second
// differences over successive cycles, var = mean(d2^2) / 6.
double NoiseVariance(const std::vector<int>& cycle,
                     const std::vector<double>& v) {
  double sum = 0;
  int n = 0;
  for (size_t i = 1; i + 1 < v.size(); ++i) {
    if (cycle[i] - cycle[i - 1] != 1 || cycle[i + 1] - cycle[i] != 1) continue;
    const double d2 = v[i + 1] - 2 * v[i] + v[i - 1];
    sum += d2 * d2, ++n;
  }
  return n > 0 ? sum / n / 6 : NAN;
}

// Successive residuals' lag-1 correlation counted as AR(1): the effective
// number of independent cycles, at least 3.
double EffectiveCount(const std::vector<double>& r) {
  const double n = static_cast<double>(r.size());
  double r0 = 0, r1 = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    r0 += r[i] * r[i];
    if (i > 0) r1 += r[i] * r[i - 1];
  }
  const double rho = r0 > 0 ? std::clamp(r1 / r0, 0.0, 0.95) : 0.0;
  return std::max(3.0, n * (1 - rho) / (1 + rho));
}

double T975(double effective) {
  return support::StudentT975(std::max(1, static_cast<int>(effective) - 2));
}

// The mean of `v` over the cycles [first, last] and its 95% half-width.
std::pair<double, double> MeanWithin(const Projections& s,
                                     const std::vector<double>& v,
                                     int first,
                                     int last) {
  std::vector<double> in;
  for (size_t i = 0; i < v.size(); ++i) {
    if (s.cycle[i] >= first && s.cycle[i] <= last) in.push_back(v[i]);
  }
  const double m = Mean(in);
  if (in.size() < 3) return {m, NAN};
  std::vector<double> r;
  double ss = 0;
  for (double x : in) r.push_back(x - m), ss += (x - m) * (x - m);
  const double n_eff = EffectiveCount(r);
  return {m, T975(n_eff) * std::sqrt(ss / (in.size() - 1) / n_eff)};
}

// The split p_c = r f_c + e over every cycle, f_c's noise removed from its
// variance (errors in variables), with the premise's check.
void Split(const Projections& s, const SpringCheckOptions& o, SpringCheck* c) {
  const double n = static_cast<double>(s.p.size());
  const double mp = Mean(s.p), mf = Mean(s.f);
  double vf = 0, cov = 0;
  for (size_t i = 0; i < s.p.size(); ++i) {
    vf += (s.f[i] - mf) * (s.f[i] - mf) / (n - 1);
    cov += (s.p[i] - mp) * (s.f[i] - mf) / (n - 1);
  }
  const double noise = NoiseVariance(s.cycle, s.f);
  c->growth_to_noise = noise > 0 ? vf / noise : INFINITY;
  Premise& premise = c->changing_groove;
  const double signal = vf - (std::isfinite(noise) ? noise : 0.0);
  double beta = NAN, half = INFINITY, se_beta = NAN, se_resid = NAN;
  double n_eff = 0;
  if (signal > 0) {
    beta = cov / signal;
    std::vector<double> r;
    double ss = 0;
    for (size_t i = 0; i < s.p.size(); ++i) {
      r.push_back(s.p[i] - mp - beta * (s.f[i] - mf));
      ss += r.back() * r.back();
    }
    n_eff = EffectiveCount(r);
    se_resid = std::sqrt(ss / (n - 2) / n_eff);
    se_beta = std::sqrt(ss / (n - 2) / (n_eff * signal));
    half = T975(n_eff) * se_beta;
  }
  const bool decides = c->growth_to_noise >= o.min_growth_to_noise &&
                       std::abs(half / beta) < o.max_split_width;
  premise.state = decides ? Premise::State::kHeld : Premise::State::kFailed;
  premise.evidence = fmt::format(
      "the friction's path changed over the cycles {:.1f}x its noise in "
      "variance (at least {:g}){}",
      c->growth_to_noise,
      o.min_growth_to_noise,
      std::isfinite(beta) && beta != 0
          ? fmt::format(", deciding the stiffness ratio to +-{:.0f}% (at most "
                        "{:.0f}%)",
                        100 * std::abs(half / beta),
                        100 * o.max_split_width)
          : "");
  if (!decides) return;
  c->stiffness_ratio = beta;
  c->stiffness_ratio_low = beta - half;
  c->stiffness_ratio_high = beta + half;
  // The intercept at f = 0 is the elastic part's projection; its share of
  // the worn track at the end (the last tenth of the cycles' path, what
  // the scan shows), r f_end: the elastic part against the waviness it
  // would tilt the contact by, whatever the compared cycles' growth.
  const int n_cycles = s.cycle.back() + 1;
  const double f_end =
      MeanWithin(s, s.f, n_cycles - std::max(3, n_cycles / 10), n_cycles - 1)
          .first;
  const double a = mp - beta * mf;
  const double se_a = std::hypot(se_resid, mf * se_beta);
  const double worn = beta * f_end;
  c->elastic_share = a / worn;
  const double se_share =
      std::hypot(se_a / worn, c->elastic_share * se_beta / beta);
  c->elastic_share_low = c->elastic_share - T975(n_eff) * se_share;
  c->elastic_share_high = c->elastic_share + T975(n_eff) * se_share;
  // The path ratio the fitted line gives at the end, where the groove is
  // the deepest (an elastic part weighs least there).
  const double p_end = mp + beta * (f_end - mf);
  const double se_end = std::hypot(se_resid, (f_end - mf) * se_beta) / f_end;
  c->end_ratio = p_end / f_end;
  c->end_ratio_low = c->end_ratio - T975(n_eff) * se_end;
  c->end_ratio_high = c->end_ratio + T975(n_eff) * se_end;
}

// The premise that Q is in time with x: false (and the premise failed)
// where Q turns at the reversals later than the options allow.
bool QInTime(const force::TurnDelay& turn,
             const SpringCheckOptions& o,
             Premise* in_time) {
  in_time->rule = "spring check";
  in_time->statement =
      "Q is in time with x and P (the friction's path averages the two "
      "directions at the same x)";
  in_time->otherwise =
      "the spring and an elastic part are not judged: a lag of the Q channel "
      "shifts the two directions' friction apart; `wearscar diagnose` "
      "measures it";
  if (!std::isfinite(turn.delay_s)) return true;
  in_time->evidence = fmt::format(
      "Q turns at the reversals {:.2f} ms (+-{:.2f}) behind x, the median "
      "over {} turns (at most {:g} ms)",
      1e3 * turn.delay_s,
      1e3 * turn.delay_se_s,
      turn.turns,
      1e3 * o.max_q_delay_s);
  const bool late =
      std::abs(turn.delay_s) - 2 * turn.delay_se_s > o.max_q_delay_s;
  in_time->state = late ? Premise::State::kFailed : Premise::State::kHeld;
  return !late;
}

}  // namespace

double SpringOverFrictionPath(const TrackHistory& h, int first, int last) {
  if (h.x_mm.empty() || h.friction_height_mm.empty() || first < 0 ||
      last >= h.cycles || last - first < 2)
    return NAN;
  const std::vector<double> w = MeanRow(h, first, last, SpringRow);
  const std::vector<double> f = MeanRow(h, first, last, FrictionRow);
  std::vector<size_t> use;
  for (size_t b = 0; b < w.size(); ++b) {
    if (std::isfinite(w[b]) && std::isfinite(f[b])) use.push_back(b);
  }
  if (use.size() < 8) return NAN;
  // The mean path's noise: each bin's scatter over the cycles.
  const int n = last - first + 1;
  double noise = 0;
  for (size_t b : use) {
    double sum = 0, sum2 = 0;
    for (int c = first; c <= last; ++c) {
      const double v = h.friction_height_mm[h.FrictionIndex(c, b)];
      sum += v, sum2 += v * v;
    }
    noise += std::max(0.0, sum2 / n - sum * sum / n / n) / (n - 1);
  }
  noise /= use.size();
  const std::vector<double> df = Detrended(f, h.x_mm, use);
  double ff = 0;
  for (double v : df) ff += v * v;
  if (!(ff / use.size() > 4 * noise)) return NAN;
  return Projection(w, f, h.x_mm, use);
}

SpringCheck CheckSpring(const TrackHistory& h,
                        int steady_from,
                        int first,
                        int last,
                        double spring_n_per_mm,
                        const SpringCheckOptions& o) {
  SpringCheck c;
  c.used_n_per_mm = spring_n_per_mm;
  Premise& premise = c.changing_groove;
  premise.rule = "spring check";
  premise.statement = "the groove changes during the record";
  premise.otherwise =
      "the stiffness and an elastic part are not split: P/S against the "
      "path is judged alone; recording from the first contact splits them";
  if (h.cycles < 6 || h.x_mm.empty() || h.friction_height_mm.empty() ||
      first < 0 || last >= h.cycles || last - first < 2)
    return c;
  if (!QInTime(h.q_turn, o, &c.q_in_time)) return c;
  const Projections s =
      Project(h, std::clamp(steady_from, 0, first), first, last);
  if (s.p.size() < 6 || !(s.shape_correlation > 0.5)) {
    premise.evidence = fmt::format(
        "not judged: P/S and the path the friction shows share no shape "
        "(r = {:.2f})",
        s.shape_correlation);
    return c;
  }
  c.judged = true;
  std::vector<double> ratio(s.p.size());
  for (size_t i = 0; i < s.p.size(); ++i) ratio[i] = s.p[i] / s.f[i];
  const auto [rho, rho_half] = MeanWithin(s, ratio, first, last);
  c.path_ratio = rho;
  c.path_ratio_low = rho - rho_half;
  c.path_ratio_high = rho + rho_half;
  const int tail_first = std::max(0, h.cycles - std::max(3, h.cycles / 10));
  c.growth = MeanWithin(s, s.f, first, last).first /
             MeanWithin(s, s.f, tail_first, h.cycles - 1).first;
  Split(s, o, &c);
  const double limit = o.max_stiffness_ratio;
  if (premise.Held()) {
    // The stiffness is contradicted when the split's ratio and the path
    // ratio both lie beyond the limit: an elastic part below the verdict's
    // limit raises the path ratio, not the split's.
    c.elastic = c.elastic_share_low > o.min_elastic_share;
    auto beyond = [limit](double low, double high) {
      return low > limit || high < 1.0 / limit;
    };
    c.contradicted = beyond(c.stiffness_ratio_low, c.stiffness_ratio_high) &&
                     beyond(c.end_ratio_low, c.end_ratio_high);
  } else {
    c.contradicted = c.path_ratio_high < 1.0 / limit;
    c.undecided = c.path_ratio_low > limit;
  }
  return c;
}

}  // namespace wearscar::fusion
