#include "wearscar/fusion/analysis.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/check.h"
#include "wearscar/support/student_t.h"

namespace wearscar::fusion {

bool AnalysisOptions::IsValid(std::string* why) const {
  if (!segment.IsValid(why) || !slip.IsValid(why) || !friction.IsValid(why))
    return false;
  if (running_in_cycles < -1) {
    if (why) *why = "running_in_cycles must be >= 0, or -1 to detect";
    return false;
  }
  if (!(running_in_tolerance > 0)) {
    if (why) *why = "running_in_tolerance must be > 0";
    return false;
  }
  return true;
}

Statistic Summarise(const std::vector<double>& values, int first) {
  Statistic s;
  double sum = 0, sum2 = 0;
  for (size_t i = static_cast<size_t>(std::max(0, first)); i < values.size();
       ++i) {
    if (!std::isfinite(values[i])) continue;
    sum += values[i];
    sum2 += values[i] * values[i];
    ++s.count;
  }
  if (s.count > 0) {
    s.mean = sum / s.count;
    s.sd = s.count > 1 ? std::sqrt(std::max(
                             0.0, (sum2 - sum * sum / s.count) / (s.count - 1)))
                       : 0.0;
  }
  return s;
}

Interval MeanInterval(const std::vector<double>& values,
                      int first,
                      int last,
                      int batches) {
  Interval r;
  std::vector<double> v;
  first = std::max(first, 0);
  last = std::min(last, static_cast<int>(values.size()) - 1);
  for (int i = first; i <= last; ++i) {
    if (std::isfinite(values[i])) v.push_back(values[i]);
  }
  r.count = static_cast<int>(v.size());
  if (v.empty()) return r;
  double sum = 0;
  for (double x : v) sum += x;
  r.mean = r.low = r.high = sum / r.count;
  const int b = std::min(batches, r.count / 2);
  if (b < 3) return r;
  std::vector<double> means(b, 0.0);
  for (int j = 0; j < b; ++j) {
    const int lo = j * r.count / b, hi = (j + 1) * r.count / b;
    for (int i = lo; i < hi; ++i) means[j] += v[i];
    means[j] /= hi - lo;
  }
  double ss = 0;
  for (double m : means) ss += (m - r.mean) * (m - r.mean);
  const double se = std::sqrt(ss / (b - 1) / b);
  const double t = support::StudentT975(b - 1);
  r.low = r.mean - t * se;
  r.high = r.mean + t * se;
  r.batches = b;
  return r;
}

Statistic SummariseWithErrors(const std::vector<double>& values,
                              const std::vector<double>& standard_errors,
                              int first,
                              int last,
                              int correlated_cycles) {
  WEARSCAR_CHECK(values.size() == standard_errors.size(),
                 "SummariseWithErrors needs one error per value");
  WEARSCAR_CHECK(correlated_cycles >= 1,
                 "SummariseWithErrors needs correlated_cycles >= 1");
  first = std::max(first, 0);
  last = std::min(last, static_cast<int>(values.size()) - 1);
  std::vector<int> cycle;
  std::vector<double> v, se;
  bool all_errors = true;
  for (int c = first; c <= last; ++c) {
    if (!std::isfinite(values[c])) continue;
    all_errors = all_errors && std::isfinite(standard_errors[c]);
    cycle.push_back(c);
    v.push_back(values[c]);
    se.push_back(standard_errors[c]);
  }
  Statistic s = Summarise(v, 0);
  const int n = static_cast<int>(v.size());
  if (n == 0 || !all_errors) return s;  // no interval
  // sum over pairs closer than the correlation length, by their cycle
  // numbers (cycles left out leave gaps).
  double var = 0, se2 = 0;
  for (int i = 0; i < n; ++i) {
    se2 += se[i] * se[i];
    for (int j = i; j < n && cycle[j] - cycle[i] < correlated_cycles; ++j) {
      const double rho =
          1.0 - static_cast<double>(cycle[j] - cycle[i]) / correlated_cycles;
      var += (i == j ? 1.0 : 2.0) * rho * se[i] * se[j];
    }
  }
  const double half = 1.96 * std::sqrt(var) / n;
  s.low = s.mean - half;
  s.high = s.mean + half;
  s.effective_count = var > 0 ? static_cast<double>(n) * se2 / var : n;
  return s;
}

Statistic SummariseSeries(const std::vector<double>& values,
                          int first,
                          int last) {
  first = std::max(first, 0);
  last = std::min(last, static_cast<int>(values.size()) - 1);
  std::vector<double> t, v;
  for (int c = first; c <= last; ++c) {
    if (!std::isfinite(values[c])) continue;
    t.push_back(c);
    v.push_back(values[c]);
  }
  Statistic s = Summarise(v, 0);
  const int n = static_cast<int>(v.size());
  if (n < 4) return s;
  // Residuals about the least-squares line.
  double tm = 0;
  for (double x : t) tm += x;
  tm /= n;
  double sxy = 0, sxx = 0;
  for (int i = 0; i < n; ++i) {
    sxy += (t[i] - tm) * (v[i] - s.mean);
    sxx += (t[i] - tm) * (t[i] - tm);
  }
  const double slope = sxx > 0 ? sxy / sxx : 0.0;
  std::vector<double> r(static_cast<std::size_t>(n));
  double rr = 0, lag1 = 0;
  for (int i = 0; i < n; ++i) {
    r[i] = v[i] - s.mean - slope * (t[i] - tm);
    rr += r[i] * r[i];
    if (i > 0) lag1 += r[i] * r[i - 1];
  }
  const double rho = rr > 0 ? std::clamp(lag1 / rr, 0.0, 0.99) : 0.0;
  const double n_eff =
      std::clamp(n * (1.0 - rho) / (1.0 + rho), 2.0, static_cast<double>(n));
  const double sd = std::sqrt(rr / (n - 2));
  const double half =
      support::StudentT975(static_cast<int>(n_eff) - 1) * sd / std::sqrt(n_eff);
  s.low = s.mean - half;
  s.high = s.mean + half;
  s.effective_count = n_eff;
  return s;
}

CostSplit SplitCost(const std::vector<MuFit>& fits, int first, int last) {
  CostSplit s;
  std::vector<double> j, noise[2], repeat[2], odd;
  for (const MuFit& f : fits) {
    const bool ok = f.converged;
    j.push_back(ok ? f.cost : std::nan(""));
    odd.push_back(ok ? f.repeat_odd_sq : std::nan(""));
    for (int d = 0; d < 2; ++d) {
      repeat[d].push_back(ok ? f.repeat_sq[d] : std::nan(""));
      noise[d].push_back(ok ? f.misfit_sq[d] - f.repeat_sq[d] : std::nan(""));
    }
  }
  const Interval cost = MeanInterval(j, first, last);
  s.cost = cost.mean;
  s.cycles = cost.count;
  if (cost.count == 0) return s;
  s.floor = s.excess = s.excess_low = s.excess_high = 0.0;
  for (int d = 0; d < 2; ++d) {
    const Interval rep = MeanInterval(repeat[d], first, last);
    const Interval noi = MeanInterval(noise[d], first, last);
    auto root = [](double v) {
      return std::isfinite(v) ? std::sqrt(std::max(0.0, v)) : std::nan("");
    };
    s.floor += root(noi.mean);
    s.excess += root(rep.mean);
    s.excess_low += root(rep.low);
    s.excess_high += root(rep.high);
  }
  const Interval o = MeanInterval(odd, first, last);
  if (o.count > 0) {
    auto twice_root = [](double v) {
      return std::isfinite(v) ? 2 * std::sqrt(std::max(0.0, v)) : std::nan("");
    };
    s.odd_excess = twice_root(o.mean);
    s.odd_excess_low = twice_root(o.low);
    s.odd_excess_high = twice_root(o.high);
  }
  return s;
}

RunningIn DetectRunningIn(const std::vector<double>& v, double tolerance) {
  RunningIn r;
  const int n = static_cast<int>(v.size());
  if (n < 6) {
    r.rule = fmt::format(
        "running-in: 0 cycles ({} cycles are too few to detect it)", n);
    return r;
  }
  r.detected = true;
  // Steady trend: least-squares line over the finite values of the second
  // half.
  const int half = n / 2;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (int c = half; c < n; ++c) {
    if (!std::isfinite(v[c])) continue;
    sx += c;
    sy += v[c];
    sxx += static_cast<double>(c) * c;
    sxy += c * v[c];
    ++m;
  }
  if (m < 3) {
    r.detected = false;
    r.rule = "running-in: 0 cycles (too few finite cycles to detect it)";
    return r;
  }
  const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  const double icpt = (sy - slope * sx) / m;
  std::vector<double> res;
  for (int c = half; c < n; ++c) {
    if (std::isfinite(v[c])) res.push_back(std::abs(v[c] - icpt - slope * c));
  }
  std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
  const double mad = res[res.size() / 2];
  r.tolerance = std::max(tolerance, 3 * 1.4826 * mad);
  r.steady_slope = slope;
  // Running median of 3, then the last cycle outside the band + 1.
  int end = 0;
  for (int c = 0; c < n; ++c) {
    double w[3];
    int k = 0;
    for (int j = std::max(0, c - 1); j <= std::min(n - 1, c + 1); ++j) {
      if (std::isfinite(v[j])) w[k++] = v[j];
    }
    if (k == 0) continue;
    // Median of up to three values.
    const double med = k == 1 ? w[0]
                       : k == 2
                           ? 0.5 * (w[0] + w[1])
                           : std::max(std::min(w[0], w[1]),
                                      std::min(std::max(w[0], w[1]), w[2]));
    if (std::abs(med - icpt - slope * c) > r.tolerance) end = c + 1;
  }
  r.cycles = std::min(end, half);
  r.rule = fmt::format(
      "running-in: {} cycles (friction within {:.4f} of the steady trend "
      "{:+.2e}/cycle from cycle {} on)",
      r.cycles,
      r.tolerance,
      slope,
      r.cycles + 1);
  return r;
}

ForceAnalysis SegmentCycles(const force::ForceRecord& record,
                            const AnalysisOptions& options) {
  WEARSCAR_CHECK(record.IsConsistent(),
                 "SegmentCycles needs channels of one length");
  std::string why;
  if (!options.IsValid(&why)) throw FusionError("analysis options: " + why);
  ForceAnalysis a;
  a.cycles = force::SegmentCycles(
      record.x_mm, options.segment, record.metadata.source);
  force::FindGrossSlip(record, &a.cycles, options.slip);
  for (const auto& c : a.cycles.cycles) {
    a.slip_fallbacks += c.forward.slip_fallback + c.reverse.slip_fallback;
  }
  return a;
}

void FindRunningIn(const force::ForceRecord& record,
                   const AnalysisOptions& options,
                   const ClassicCofs& cofs,
                   ForceAnalysis* a) {
  // Running-in never swallows the whole test: keep at least the last half.
  const int n = static_cast<int>(a->cycles.cycles.size());
  if (options.running_in_cycles >= 0) {
    if (options.running_in_cycles > n / 2) {
      throw FusionError(fmt::format(
          "{}: a running-in of {} cycles was given (--running-in); the test "
          "has {} complete cycles, and the running-in may take at most half "
          "of them ({})",
          record.metadata.source,
          options.running_in_cycles,
          n,
          n / 2));
    }
    a->running_in.cycles = options.running_in_cycles;
    a->running_in.rule =
        fmt::format("running-in: {} cycles (given)", a->running_in.cycles);
  } else {
    std::vector<double> friction;
    for (const auto& c : cofs.cycles) friction.push_back(c.mu_mean);
    a->running_in = DetectRunningIn(friction, options.running_in_tolerance);
  }
}

ForceAnalysis SegmentForce(const force::ForceRecord& record,
                           const AnalysisOptions& options) {
  ForceAnalysis a = SegmentCycles(record, options);
  FindRunningIn(record,
                options,
                ClassicCofs{force::ComputeClassicCof(record, a.cycles)},
                &a);
  return a;
}

SlopeFits FitForceSide(const force::ForceRecord& record,
                       const AnalysisOptions& options,
                       const ForceAnalysis& segmented) {
  SlopeFits a;
  if (options.fit_force_slope) {
    FrictionFits fits = FitFriction(
        record, segmented.cycles, SlopeSource::kForce, options.friction);
    a.cycles = std::move(fits.cycles);
    a.slope_estimate = std::move(fits.slope);
    a.k_signal_rms = fits.k_signal_rms;
    a.k_noise_rms = fits.k_noise_rms;
    a.k_ensemble_noise_rms = fits.k_ensemble_noise_rms;
    a.k_noise_correction = fits.k_noise_correction;
    a.correlated_cycles = fits.correlated_cycles;
  } else {
    a.cycles.assign(segmented.cycles.cycles.size(), MuFit{});
    for (auto& f : a.cycles) f.message = "not fitted (scan slope only)";
  }
  const int n = static_cast<int>(segmented.cycles.cycles.size());
  const int first = segmented.running_in.cycles;
  std::vector<double> mu, se, j;
  for (int i = 0; i < n; ++i) {
    const bool ok = a.cycles[i].converged;
    mu.push_back(ok ? a.cycles[i].mu_hat : std::nan(""));
    se.push_back(ok ? a.cycles[i].standard_error : std::nan(""));
    j.push_back(ok ? a.cycles[i].cost : std::nan(""));
  }
  a.mu_hat = SummariseWithErrors(mu, se, first, n - 1, a.correlated_cycles);
  a.cost = Summarise(j, first);
  return a;
}

ForceFitted AnalyzeForce(const force::ForceRecord& record,
                         const AnalysisOptions& options) {
  ForceFitted a;
  static_cast<ForceAnalysis&>(a) = SegmentForce(record, options);
  a.fits = FitForceSide(record, options, a);
  return a;
}

}  // namespace wearscar::fusion
