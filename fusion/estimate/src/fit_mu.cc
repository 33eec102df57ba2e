#include "wearscar/fusion/fit_mu.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <vector>

#include "fit_mu_internal.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/check.h"
#include "wearscar/support/minimize.h"
#include "wearscar/support/numbers.h"

namespace wearscar::fusion {

using internal::Resolved;

namespace {

using support::kInf;

// |Qm - Qw| / |Qm| over one direction.
double DirectionCost(const SlipSamples& s, double mu) {
  // Vectorised form of |Qm - P (k + s mu) / (1 - s mu k)| / |Qm|.
  const double sm = s.direction * mu;
  const auto k = s.k.array();
  const auto denom = 1.0 - sm * k;
  if (s.k.size() == 0 || (denom <= 0.0).any()) return kInf;
  const double num =
      (s.q_n.array() - s.p_n.array() * (k + sm) / denom).square().sum();
  const double den = s.q_n.squaredNorm();
  return den > 0 ? std::sqrt(num / den) : kInf;
}

void AppendSlip(const force::ForceRecord& r,
                const force::HalfCycle& half,
                const FrictionFitOptions& o,
                const PlateProfile* profile,
                SlipSamples* out) {
  out->direction = half.direction;
  const Eigen::Index b = half.slip_begin, e = half.slip_end;
  Eigen::VectorXd k;
  if (profile == nullptr) {
    k = force::SlopeFromNormalForce(r.x_mm, r.normal_n, b, e, o.slope);
  } else {
    k.resize(e - b);
    profile->AtEach(r.x_mm.data() + b, e - b, k.data());
  }
  // Keep the samples where everything is finite.
  Eigen::Index n = 0;
  out->q_n.resize(e - b);
  out->p_n.resize(e - b);
  out->k.resize(e - b);
  out->x_mm.resize(e - b);
  for (Eigen::Index i = b; i < e; ++i) {
    const double q = r.tangential_n[i], p = r.normal_n[i], kk = k[i - b];
    if (!std::isfinite(q) || !std::isfinite(p) || !std::isfinite(kk)) continue;
    out->q_n[n] = q;
    out->p_n[n] = p;
    out->k[n] = kk;
    out->x_mm[n] = r.x_mm[i];
    ++n;
  }
  out->q_n.conservativeResize(n);
  out->p_n.conservativeResize(n);
  out->k.conservativeResize(n);
  out->x_mm.conservativeResize(n);
}

// Standard error of mu-hat (MuFit::standard_error). With r = Qm - Qw and
// g = dQw/dmu = s P (1 + k^2) / (1 - s mu k)^2 per sample, J's stationarity
// sum_d a_d r_d.g_d = 0 (a_d = 1 / (|r_d| |Qm_d|)) linearised gives
// d mu = sum_d a_d e_d.g_d / sum_d a_d |g_d|^2, whose variance is estimated
// from the scores r g summed in blocks along each direction.
double StandardError(const CycleSamples& samples, double mu, double block_mm) {
  double numerator = 0, denominator = 0;
  for (const SlipSamples* s : {&samples.forward, &samples.reverse}) {
    const Eigen::Index n = s->q_n.size();
    if (n < 2 || s->x_mm.size() != n) return std::nan("");
    const double x0 = s->x_mm[0];
    const double length = std::abs(s->x_mm[n - 1] - x0);
    if (!(length > 0)) return std::nan("");
    const int b = static_cast<int>(std::clamp(length / block_mm, 2.0, 1e5));
    const double sm = s->direction * mu;
    double rr = 0, gg = 0;
    std::vector<double> sums(static_cast<std::size_t>(b), 0.0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double k = s->k[i], d = 1.0 - sm * k;
      const double r = s->q_n[i] - s->p_n[i] * (k + sm) / d;
      const double g = s->direction * s->p_n[i] * (1.0 + k * k) / (d * d);
      rr += r * r;
      gg += g * g;
      const int j = static_cast<int>(std::abs(s->x_mm[i] - x0) / length * b);
      sums[static_cast<std::size_t>(std::clamp(j, 0, b - 1))] += r * g;
    }
    double var = 0, cross = 0;
    for (int j = 0; j < b; ++j) {
      var += sums[j] * sums[j];
      if (j > 0) cross += sums[j] * sums[j - 1];
    }
    var = std::max(var + 2.0 * cross, 0.25 * var);
    const double qq = s->q_n.squaredNorm();
    if (!(qq > 0)) return std::nan("");
    if (!(rr > 0)) return 0.0;  // an exact fit: this direction fixes mu
    const double a = 1.0 / std::sqrt(rr * qq);
    numerator += a * a * var;
    denominator += a * gg;
  }
  return denominator > 0 ? std::sqrt(numerator) / denominator : std::nan("");
}

// J = J_forward + J_reverse and its first two derivatives in mu, in one
// pass over the samples. Per direction, with r = Qm - P (k + s mu) /
// (1 - s mu k) and S = sum r^2: r' = -s P (1 + k^2) / (1 - s mu k)^2,
// r'' = 2 s k r' / (1 - s mu k), J = sqrt(S / D) with D = sum Qm^2.
// False where J is not finite (|mu k| >= 1, no samples).
struct CostDerivatives {
  double j = 0, dj = 0, d2j = 0;
};
bool CostWithDerivatives(const CycleSamples& samples,
                         double mu,
                         CostDerivatives* out) {
  *out = {};
  for (const SlipSamples* d : {&samples.forward, &samples.reverse}) {
    const double s = d->direction, sm = s * mu;
    const Eigen::Index n = d->q_n.size();
    const double *k = d->k.data(), *p = d->p_n.data(), *q = d->q_n.data();
    // Two samples at a time into two sets of sums: the adds of one sample
    // wait on the last's no more (the loop ran at the adds' latency).
    double sum[2] = {0, 0}, sum1[2] = {0, 0}, sum2[2] = {0, 0};
    bool finite = true;
    const auto add = [&](Eigen::Index i, int lane) {
      const double denom = 1.0 - sm * k[i];
      finite &= denom > 0.0;
      const double inv = 1.0 / denom;
      const double r = q[i] - p[i] * (k[i] + sm) * inv;
      const double r1 = -s * p[i] * (1.0 + k[i] * k[i]) * inv * inv;
      const double r2 = 2.0 * s * k[i] * r1 * inv;
      sum[lane] += r * r;
      sum1[lane] += r * r1;
      sum2[lane] += r1 * r1 + r * r2;
    };
    Eigen::Index i = 0;
    for (; i + 1 < n; i += 2) {
      add(i, 0);
      add(i + 1, 1);
    }
    if (i < n) add(i, 0);
    if (!finite) return false;
    const double s0 = sum[0] + sum[1], s1 = sum1[0] + sum1[1],
                 s2 = sum2[0] + sum2[1];
    const double den = d->q_n.squaredNorm();
    if (n == 0 || !(den > 0) || !(s0 > 0)) return false;
    // S' = 2 s1, S'' = 2 s2.
    const double root = std::sqrt(s0 * den);
    out->j += std::sqrt(s0 / den);
    out->dj += s1 / root;
    out->d2j += s2 / root - s1 * s1 / (s0 * root);
  }
  return std::isfinite(out->j) && std::isfinite(out->dj) &&
         std::isfinite(out->d2j);
}

// The minimum of J by Newton's method from the first-order least-squares
// mu (Qm - P k ~ s mu P (1 + k^2)), a few passes over the samples where the
// bracketing grid and Brent's method take about 25. J is a sum of squares
// of residuals that are nearly linear in mu (|mu k| << 1 on any worn
// track), so it has one minimum; a step that leaves [mu_min, mu_max], a
// negative curvature or no convergence in `kMaxSteps` steps returns false,
// and the caller falls back to the grid and Brent, which also handles a
// minimum on a bound.
bool NewtonMinimum(const CycleSamples& samples,
                   const FitMuOptions& o,
                   support::ScalarMinimum* m) {
  constexpr int kMaxSteps = 12;
  double num = 0, den = 0;
  for (const SlipSamples* d : {&samples.forward, &samples.reverse}) {
    for (Eigen::Index i = 0; i < d->q_n.size(); ++i) {
      const double k = d->k[i], p = d->p_n[i], g = p * (1 + k * k);
      num += d->direction * (d->q_n[i] - p * k) * g;
      den += g * g;
    }
  }
  if (!(den > 0)) return false;
  double mu = num / den;
  CostDerivatives c;
  for (int step = 1; step <= kMaxSteps; ++step) {
    if (!(mu > o.mu_min && mu < o.mu_max)) return false;
    if (!CostWithDerivatives(samples, mu, &c) || !(c.d2j > 0)) return false;
    const double delta = c.dj / c.d2j;
    mu -= delta;
    if (std::abs(delta) <= 0.01 * o.tolerance) {
      if (!(mu > o.mu_min && mu < o.mu_max)) return false;
      m->found = m->converged = true;
      m->x = mu;
      m->value = WearScarCost(samples, mu);
      m->iterations = step;
      return std::isfinite(m->value);
    }
  }
  return false;
}

}  // namespace

namespace internal {

// The second-order bias of mu-hat per unit variance of the noise e in k,
// d mu / var(e). With f(mu, k) = P (k + m) / (1 - m k), m = s mu,
// D = 1 - m k, the stationarity of J (weights a_d as in StandardError)
// averaged over e gives
//   mu-hat - mu = var(e) sum_d a_d sum_i T_i / sum_d a_d sum_i f_mu^2,
//   T = -f_k f_mu,k - f_kk f_mu / 2 = -s P^2 (1 + m^2) (2 (k + m) +
//       m (1 + k^2)) / D^5,
// about -3 mu for small k.
double KNoiseBiasPerVariance(const CycleSamples& samples, double mu) {
  double numerator = 0, denominator = 0;
  for (const SlipSamples* s : {&samples.forward, &samples.reverse}) {
    const double m = s->direction * mu;
    double rr = 0, tt = 0, gg = 0;
    for (Eigen::Index i = 0; i < s->q_n.size(); ++i) {
      const double p = s->p_n[i], k = s->k[i], d = 1.0 - m * k;
      const double d2 = d * d;
      const double r = s->q_n[i] - p * (k + m) / d;
      const double g = s->direction * p * (1.0 + k * k) / d2;
      tt += -s->direction * p * p * (1.0 + m * m) *
            (2.0 * (k + m) + m * (1.0 + k * k)) / (d2 * d2 * d);
      gg += g * g;
      rr += r * r;
    }
    const double qq = s->q_n.squaredNorm();
    if (!(rr > 0 && qq > 0)) return 0.0;
    const double a = 1.0 / std::sqrt(rr * qq);
    numerator += a * tt;
    denominator += a * gg;
  }
  return denominator > 0 ? numerator / denominator : 0.0;
}

FrictionFitOptions Resolved(const FrictionFitOptions& o, double rate_hz) {
  FrictionFitOptions r = o;
  r.slope = o.slope.ForSamplingRate(rate_hz);
  return r;
}

}  // namespace internal

double WearScarCost(const CycleSamples& samples, double mu) {
  return DirectionCost(samples.forward, mu) +
         DirectionCost(samples.reverse, mu);
}

bool FitMuOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (!(mu_min >= 0 && mu_max > mu_min))
    return fail("need 0 <= mu_min < mu_max");
  if (grid_points < 3) return fail("grid_points must be >= 3");
  if (!(tolerance > 0)) return fail("tolerance must be > 0");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(error_block_mm > 0)) return fail("error_block_mm must be > 0");
  return true;
}

bool FrictionFitOptions::IsValid(std::string* why) const {
  if (threads < 1 || threads > 256) {
    if (why) *why = "threads must be in [1, 256]";
    return false;
  }
  if (k_from_depth && k_estimate != KEstimate::kEnsemble) {
    if (why) *why = "k from the depth channel needs the ensemble estimate";
    return false;
  }
  if (!std::isnan(k_noise_variance) &&
      !(k_noise_variance >= 0 && std::isfinite(k_noise_variance))) {
    if (why) *why = "the k noise variance must be >= 0 (or NaN: estimated)";
    return false;
  }
  return slope.IsValid(why) && ensemble.IsValid(why) && fit.IsValid(why) &&
         repeatability.IsValid(why);
}

std::string MuFit::BriefReport() const {
  return fmt::format("mu-hat {:.4f}, J {:.4f}, {} samples, {} iterations, {}{}",
                     mu_hat,
                     cost,
                     samples,
                     iterations,
                     message,
                     at_bound ? " (at a bound)" : "");
}

MuFit FitMu(const CycleSamples& samples, const FitMuOptions& o) {
  for (const SlipSamples* s : {&samples.forward, &samples.reverse}) {
    WEARSCAR_CHECK(s->p_n.size() == s->q_n.size() &&
                       s->k.size() == s->q_n.size() &&
                       (s->x_mm.size() == 0 || s->x_mm.size() == s->q_n.size()),
                   "FitMu needs q, p and k (and x) of one length");
  }
  MuFit fit;
  std::string why;
  if (!o.IsValid(&why)) {
    fit.message = "invalid options: " + why;
    return fit;
  }
  fit.samples =
      static_cast<int>(samples.forward.q_n.size() + samples.reverse.q_n.size());
  if (samples.forward.q_n.size() < 3 || samples.reverse.q_n.size() < 3) {
    fit.message = "too few gross-slip samples";
    return fit;
  }
  support::ScalarMinimum m;
  if (!NewtonMinimum(samples, o, &m)) {
    m = support::MinimizeOnInterval(
        [&](double mu) { return WearScarCost(samples, mu); },
        o.mu_min,
        o.mu_max,
        o.grid_points,
        o.tolerance,
        o.max_iterations);
  }
  if (!m.found) {
    fit.message = "J is infinite on the whole interval (|mu k| >= 1)";
    return fit;
  }
  const double x = m.x, fx = m.value;
  const int iter = m.iterations;
  fit.converged = m.converged;
  fit.mu_hat = x;
  fit.cost = fx;
  fit.iterations = iter;
  fit.at_bound =
      (x - o.mu_min) < 10 * o.tolerance || (o.mu_max - x) < 10 * o.tolerance;
  fit.message = fit.converged ? "converged" : "iteration limit reached";
  if (fit.converged) {
    fit.standard_error = StandardError(samples, x, o.error_block_mm);
  }
  return fit;
}

Eigen::VectorXd CostCurve(const CycleSamples& samples,
                          const Eigen::VectorXd& mu_grid) {
  Eigen::VectorXd j(mu_grid.size());
  for (Eigen::Index i = 0; i < mu_grid.size(); ++i)
    j[i] = WearScarCost(samples, mu_grid[i]);
  return j;
}

double SamplingRateOf(const force::ForceRecord& record) {
  const double stated = record.metadata.sampling_rate_hz;
  if (stated > 0 && std::isfinite(stated)) return stated;
  const Eigen::Index n = record.time_s.size();
  if (n < 2) return 0.0;
  const double span = record.time_s[n - 1] - record.time_s[0];
  return span > 0 && std::isfinite(span) ? (n - 1) / span : 0.0;
}

CycleSamples GatherCycle(const force::ForceRecord& record,
                         const force::Cycle& cycle,
                         SlopeSource source,
                         const FrictionFitOptions& options,
                         const PlateProfile* scan_slope,
                         const std::array<PlateProfile, 2>* force_slopes) {
  if (source == SlopeSource::kScan && scan_slope == nullptr) {
    throw FusionError(
        "slope from the scan requested but no scan slope profile given");
  }
  const FrictionFitOptions o =
      options.slope.window > 0 && options.slope.half_width > 0
          ? options
          : Resolved(options, SamplingRateOf(record));
  const PlateProfile* forward = nullptr;
  const PlateProfile* reverse = nullptr;
  if (source == SlopeSource::kScan) {
    forward = reverse = scan_slope;
  } else if (force_slopes != nullptr) {
    forward = &(*force_slopes)[0];
    reverse = &(*force_slopes)[1];
  }
  CycleSamples s;
  AppendSlip(record, cycle.forward, o, forward, &s.forward);
  AppendSlip(record, cycle.reverse, o, reverse, &s.reverse);
  return s;
}

ForceSlopes::ForceSlopes(const force::ForceRecord& record,
                         const force::CycleSet& cycles,
                         const FrictionFitOptions& options,
                         int first,
                         int last)
    : record_(record),
      cycles_(cycles),
      options_(Resolved(options, SamplingRateOf(record))),
      profile_(options.k_from_depth ? record.depth_mm : record.normal_n),
      profile_per_mm_(options.k_from_depth ? -options.depth_sign
                                           : options.slope.spring_n_per_mm) {
  if (options.k_from_depth && !record.has_depth())
    throw FusionError("k from the depth channel, but the record has none");
  const int n = static_cast<int>(cycles.cycles.size());
  if (last < 0 || last >= n) last = n - 1;
  first = std::clamp(first, 0, std::max(0, n - 1));
  if (options_.k_estimate != KEstimate::kEnsemble || n == 0) return;
  // A short test keeps room for the noise split's template (cycles whose
  // ensembles share no sample): at most a third of the cycles, odd.
  int& window = options_.ensemble.cycles;
  if (options.narrow_ensemble_to_record)
    window = std::max(1, std::min(window, ((n / 3) - 1) | 1));
  // Sparse sampling (tens of samples per stroke): the local fit must reach
  // its neighbouring samples, 2.5 steps of x, with 3 of them enough. At the
  // paper's 2 kHz the step is 0.01 mm and the span stays as given. The
  // steps of up to 21 cycles (those fitted when only some are) are
  // gathered for their 99th percentile only where it could widen the
  // span: never when even the largest does not (every densely sampled
  // test).
  const std::vector<char>& fit = options.fit_cycle;
  std::vector<double> steps;
  for (const bool gather : {false, true}) {
    double largest = 0;
    for (int c = first; c <= last; c += std::max(1, (last - first) / 20)) {
      if (!fit.empty() && (c >= static_cast<int>(fit.size()) ||
                           !fit[static_cast<std::size_t>(c)]))
        continue;
      for (const force::HalfCycle* h :
           {&cycles.cycles[c].forward, &cycles.cycles[c].reverse}) {
        for (Eigen::Index i = h->slip_begin + 1; i < h->slip_end; ++i) {
          const double dx = std::abs(record.x_mm[i] - record.x_mm[i - 1]);
          if (!std::isfinite(dx)) continue;
          if (gather) steps.push_back(dx);
          largest = std::max(largest, dx);
        }
      }
    }
    if (!(2.5 * largest > options_.ensemble.span_mm)) break;
  }
  if (!steps.empty()) {
    const std::size_t k = steps.size() * 99 / 100;
    std::nth_element(steps.begin(), steps.begin() + k, steps.end());
    const double needed = 2.5 * steps[k];
    if (needed > options_.ensemble.span_mm) {
      options_.ensemble.span_mm = std::min(needed, 10.0);
      options_.ensemble.min_bins = 3;
    }
  }
  // P of the cycles any ensemble in [first, last] reaches, binned along x.
  const int half = options_.ensemble.cycles / 2;
  const int lo = std::max(0, first - half), hi = std::min(n - 1, last + half);
  // One ensemble's cycles at a time; each is binned when a window first
  // needs it (Gather slides the window along the cycles).
  const int ring = options_.ensemble.cycles;
  normal_bins_.emplace(
      PlateGrid::Covering(record, cycles, options_.ensemble.bin_mm),
      lo,
      hi,
      /*with_x=*/true,
      ring);
  binned_cycle_.assign(static_cast<std::size_t>(std::min(ring, hi - lo + 1)),
                       -1);
}

void ForceSlopes::BinCycle(int c) const {
  const int lo = normal_bins_->first_cycle();
  if (c < lo || c > normal_bins_->last_cycle()) return;
  int& held =
      binned_cycle_[static_cast<std::size_t>(c - lo) % binned_cycle_.size()];
  if (held == c) return;
  normal_bins_->ClearCycle(c);
  for (const force::HalfCycle* h :
       {&cycles_.cycles[c].forward, &cycles_.cycles[c].reverse}) {
    normal_bins_->AddRange(c,
                           h->direction,
                           record_.x_mm.data(),
                           profile_.data(),
                           h->begin,
                           h->end);
  }
  held = c;
}

CycleSamples ForceSlopes::Gather(int c) const {
  const force::Cycle& cycle = cycles_.cycles.at(static_cast<std::size_t>(c));
  if (!normal_bins_) {
    return GatherCycle(record_, cycle, SlopeSource::kForce, options_);
  }
  const auto [first, last] =
      EnsembleWindow(*normal_bins_, c, options_.ensemble);
  const bool overlaps = window_last_ >= window_first_ &&
                        first <= window_last_ && last >= window_first_;
  if (overlaps) {
    // Slide: remove the cycles that left the window (still in their ring
    // slots), then bin and add those that came.
    for (int d = 0; d < 2; ++d) {
      const int direction = d == 0 ? +1 : -1;
      CycleBins::Sums& s = window_sums_[d];
      for (int j = window_first_; j < first; ++j)
        normal_bins_->Accumulate(&s, j, direction, -1);
      for (int j = last + 1; j <= window_last_; ++j)
        normal_bins_->Accumulate(&s, j, direction, -1);
    }
    for (int j = first; j <= last; ++j) {
      if (j >= window_first_ && j <= window_last_) continue;
      BinCycle(j);
      for (int d = 0; d < 2; ++d)
        normal_bins_->Accumulate(&window_sums_[d], j, d == 0 ? +1 : -1, +1);
    }
  } else {
    for (int j = first; j <= last; ++j) BinCycle(j);
    for (int d = 0; d < 2; ++d)
      window_sums_[d] = normal_bins_->Window(d == 0 ? +1 : -1, first, last);
  }
  window_first_ = first;
  window_last_ = last;
  const std::array<PlateProfile, 2> k = EnsembleSlopeFromSums(
      *normal_bins_, window_sums_, profile_per_mm_, options_.ensemble);
  return GatherCycle(
      record_, cycle, SlopeSource::kForce, options_, nullptr, &k);
}

double ForceSlopes::EnsembleNoiseVariance(int first,
                                          int last,
                                          int probes) const {
  if (!normal_bins_ || probes < 1) return std::nan("");
  first = std::max(first, normal_bins_->first_cycle());
  last = std::min(last, normal_bins_->last_cycle());
  if (last < first) return std::nan("");
  const PlateGrid& grid = normal_bins_->grid();
  const double centre = grid.x0_mm + 0.5 * grid.bins * grid.bin_mm;
  const double half_range = 0.4 * grid.bins * grid.bin_mm;
  const double spring = profile_per_mm_;
  double sum = 0;
  long n = 0;
  const int step = std::max(1, (last - first + 1) / probes);
  for (int c = first; c <= last; c += step) {
    const auto [lo, hi] = EnsembleWindow(*normal_bins_, c, options_.ensemble);
    if (hi - lo < 2) continue;
    const int odd = (hi - lo + 1) / 2, even = hi - lo + 1 - odd;
    const double scale = static_cast<double>(odd) * even /
                         ((odd + even) * static_cast<double>(odd + even));
    std::array<CycleBins::Sums, 2> halves;
    for (int j = lo; j <= hi; ++j) BinCycle(j);
    for (int d = 0; d < 2; ++d) {
      const int direction = d == 0 ? +1 : -1;
      halves[0] = normal_bins_->Window(direction, 1, 0);  // empty sums
      halves[1] = halves[0];
      for (int j = lo; j <= hi; ++j) {
        normal_bins_->Accumulate(&halves[(j - lo) % 2], j, direction, +1);
      }
      const PlateProfile pa = EnsembleSlopeOfSums(
          *normal_bins_, halves[0], spring, options_.ensemble);
      const PlateProfile pb = EnsembleSlopeOfSums(
          *normal_bins_, halves[1], spring, options_.ensemble);
      Eigen::Index hint = 0;  // pa's x rise: pb is walked, not searched
      for (Eigen::Index i = 0; i < pa.x_mm.size(); ++i) {
        if (std::abs(pa.x_mm[i] - centre) > half_range) continue;
        const double diff = pa.k[i] - pb.AtNear(pa.x_mm[i], &hint);
        if (!std::isfinite(diff)) continue;
        sum += scale * diff * diff;
        ++n;
      }
    }
  }
  // The probes took ring slots the last window's sums counted on.
  window_last_ = window_first_ - 1;
  return n > 0 ? sum / n : std::nan("");
}

std::string ForceSlopes::Describe() const {
  const double s = options_.slope.spring_n_per_mm;
  if (options_.k_from_depth) {
    return fmt::format(
        "k = -d(depth)/dx from the depth channel averaged over {} "
        "neighbouring cycles per direction in {} mm bins, local quadratic "
        "over {:.3g} mm (ensemble)",
        options_.ensemble.cycles,
        options_.ensemble.bin_mm,
        options_.ensemble.span_mm);
  }
  if (normal_bins_) {
    return fmt::format(
        "k = (1/S) dP/dx, S = {} N/mm, from P(x) averaged over {} "
        "neighbouring cycles per direction in {} mm bins, local quadratic "
        "over {:.3g} mm (ensemble)",
        s,
        options_.ensemble.cycles,
        options_.ensemble.bin_mm,
        options_.ensemble.span_mm);
  }
  return fmt::format(
      "k = (1/S) dP/dx, S = {} N/mm, from each cycle's own P: {} "
      "(cycle)",
      s,
      options_.slope.Describe());
}

int ForceSlopes::SharedCycles() const {
  return normal_bins_ ? options_.ensemble.cycles : 1;
}

}  // namespace wearscar::fusion
