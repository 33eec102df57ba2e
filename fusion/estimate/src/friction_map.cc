#include "wearscar/fusion/friction_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "wearscar/fusion/error.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/check.h"
#include "wearscar/support/numbers.h"

namespace wearscar::fusion {
namespace {

using support::kNaN;

// Sums per (cycle, direction, bin).
struct Bins {
  double lo = 0, width = 1;
  size_t count = 0;
  std::vector<double> raw, corrected;
  std::vector<int> n;
};

// Sums of the loop's Q, P and k per (cycle, direction, fine bin).
struct LoopSums {
  double lo = 0, width = 1;
  size_t count = 0;
  std::vector<double> q, p, k;
  std::vector<int> n;
};

void AccumulateLoop(const SlipSamples& s, int cycle, LoopSums* b) {
  const int d = s.direction > 0 ? 0 : 1;
  for (Eigen::Index i = 0; i < s.q_n.size(); ++i) {
    const double q = s.q_n[i], p = s.p_n[i], k = s.k[i], x = s.x_mm[i];
    if (!std::isfinite(q) || !std::isfinite(p) || !std::isfinite(k) ||
        !std::isfinite(x))
      continue;
    const auto bin = static_cast<long>(std::floor((x - b->lo) / b->width));
    if (bin < 0 || bin >= static_cast<long>(b->count)) continue;
    const size_t at = (static_cast<size_t>(cycle) * 2 + d) * b->count + bin;
    b->q[at] += q;
    b->p[at] += p;
    b->k[at] += k;
    ++b->n[at];
  }
}

void Accumulate(const SlipSamples& s, int cycle, Bins* b) {
  const int d = s.direction > 0 ? 0 : 1;
  for (Eigen::Index i = 0; i < s.q_n.size(); ++i) {
    const double q = s.q_n[i], p = s.p_n[i], k = s.k[i], x = s.x_mm[i];
    if (!std::isfinite(q) || !std::isfinite(p) || !std::isfinite(k) ||
        !std::isfinite(x) || !(p > 0))
      continue;
    const double denominator = p + k * q;
    if (!(std::abs(denominator) > 1e-9 * p)) continue;
    const auto bin = static_cast<long>(std::floor((x - b->lo) / b->width));
    if (bin < 0 || bin >= static_cast<long>(b->count)) continue;
    const size_t at = (static_cast<size_t>(cycle) * 2 + d) * b->count + bin;
    b->raw[at] += s.direction * q / p;
    b->corrected[at] += s.direction * (q - p * k) / denominator;
    ++b->n[at];
  }
}

// Blocks of steady cycles the noise floor needs (NaN with fewer).
constexpr int kFewestBlocks = 4;

// The variance of the mean of `n` block means from their summed squared
// deviations and lag-1 products. Neighbouring blocks still share the
// ensembles that straddle their boundary (a correlation of about 0.25 for
// blocks as long as the ensemble): the lag-1 covariance enters. Below
// kFewestBlocks it is not estimable (of two blocks the lag-1 covariance
// cancels their variance: a floor of exactly 0).
double VarianceOfTheMean(double var, double lag1, size_t n) {
  return static_cast<int>(n) >= kFewestBlocks
             ? (var + 2 * lag1) / static_cast<double>(n - 1) /
                   static_cast<double>(n)
             : kNaN;
}

// The along-track variation of the steady average of the map values v, and
// the noise floor of that average. Each cycle and direction is taken about
// its own mean (the drift of mu over cycles is not along-track variation).
// Successive cycles share noise (the ensemble slope spans `block` cycles):
// the floor is the standard error from the means of consecutive blocks of
// that many cycles, with their lag-1 covariance.
void SpatialVariation(const FrictionMap& m,
                      const std::vector<double>& v,
                      int first,
                      int block,
                      double* sd,
                      double* noise,
                      std::vector<double>* pattern) {
  const size_t bins = m.x_mm.size();
  const int steady = m.cycles - first;
  // centred[(c - first) * 2 * bins + d * bins + b]
  std::vector<double> centred(static_cast<size_t>(steady) * 2 * bins, kNaN);
  for (int c = first; c < m.cycles; ++c) {
    for (int d = 0; d < 2; ++d) {
      double mean = 0;
      int k = 0;
      for (size_t b = 0; b < bins; ++b) {
        const double x = v[m.Index(c, d, b)];
        if (std::isfinite(x)) mean += x, ++k;
      }
      for (size_t b = 0; k > 0 && b < bins; ++b) {
        centred[(static_cast<size_t>(c - first) * 2 + d) * bins + b] =
            v[m.Index(c, d, b)] - mean / k;
      }
    }
  }
  const int blocks = steady / std::max(1, block);
  double var_x = 0, var_noise = 0;
  int used = 0;
  pattern->assign(2 * bins, kNaN);
  std::vector<double> means(2 * bins, kNaN), se2(2 * bins, kNaN);
  for (size_t i = 0; i < 2 * bins; ++i) {
    // Block means of this cell over the steady cycles.
    std::vector<double> bm;
    for (int k = 0; k < blocks; ++k) {
      double s = 0;
      int n = 0;
      for (int c = k * block; c < (k + 1) * block; ++c) {
        const double x = centred[static_cast<size_t>(c) * 2 * bins + i];
        if (std::isfinite(x)) s += x, ++n;
      }
      if (n > 0) bm.push_back(s / n);
    }
    if (static_cast<int>(bm.size()) < std::max(2, blocks / 2)) continue;
    double mean = 0;
    for (double x : bm) mean += x;
    mean /= bm.size();
    double var = 0, lag1 = 0;
    for (size_t k = 0; k < bm.size(); ++k) {
      var += (bm[k] - mean) * (bm[k] - mean);
      if (k > 0) lag1 += (bm[k] - mean) * (bm[k - 1] - mean);
    }
    means[i] = mean;
    se2[i] = VarianceOfTheMean(var, lag1, bm.size());
  }
  for (int d = 0; d < 2; ++d) {
    double centre = 0;
    int k = 0;
    for (size_t b = 0; b < bins; ++b) {
      if (std::isfinite(means[d * bins + b]))
        centre += means[d * bins + b], ++k;
    }
    for (size_t b = 0; k > 0 && b < bins; ++b) {
      const size_t i = d * bins + b;
      if (!std::isfinite(means[i])) continue;
      (*pattern)[i] = means[i] - centre / k;
      var_x += (*pattern)[i] * (*pattern)[i];
      var_noise += se2[i];
      ++used;
    }
  }
  *sd = used > 1 ? std::sqrt(var_x / used) : kNaN;
  *noise = used > 1 && std::isfinite(var_noise)
               ? std::sqrt(std::max(0.0, var_noise) / used)
               : kNaN;
}

}  // namespace

bool FrictionMapOptions::IsValid(std::string* why) const {
  if (!(bin_mm > 0 && bin_mm < 100)) {
    if (why) *why = "friction map: bin_mm must be in (0, 100) mm";
    return false;
  }
  if (min_samples < 1) {
    if (why) *why = "friction map: min_samples must be >= 1";
    return false;
  }
  if ((loop_bins < 2 && loop_bins != 0) || loop_bins > 10000) {
    if (why) *why = "friction map: loop bins must be 0 (none) or in [2, 10000]";
    return false;
  }
  if (slope_polynomial_order != 0 &&
      (slope_polynomial_order < 2 || slope_polynomial_order > 3)) {
    if (why) *why = "friction map: slope polynomial order must be 0, 2 or 3";
    return false;
  }
  if (!(slope_span_mm >= 0 && slope_span_mm <= 10)) {
    if (why) *why = "friction map: slope span must be in [0, 10] mm";
    return false;
  }
  return true;
}

namespace {

// The sums' means where they hold samples enough (NaN elsewhere), with the
// bins' centres.
void StoreMeans(const LoopSums& loop,
                const Bins& b,
                const FrictionMapOptions& options,
                FrictionMap* map) {
  FrictionMap& m = *map;
  const size_t loop_cells = loop.n.size(), cells = b.n.size();
  for (size_t i = 0; i < loop.count; ++i)
    m.loop_x_mm.push_back(loop.lo + (i + 0.5) * loop.width);
  m.loop_q_n.resize(loop_cells);
  m.loop_p_n.resize(loop_cells);
  m.loop_k.resize(loop_cells);
  for (size_t i = 0; i < loop_cells; ++i) {
    const int n = loop.n[i];
    m.loop_q_n[i] = n > 0 ? static_cast<float>(loop.q[i] / n) : NAN;
    m.loop_p_n[i] = n > 0 ? static_cast<float>(loop.p[i] / n) : NAN;
    m.loop_k[i] = n > 0 ? static_cast<float>(loop.k[i] / n) : NAN;
  }
  for (size_t i = 0; i < b.count; ++i)
    m.x_mm.push_back(b.lo + (i + 0.5) * b.width);
  m.mu_raw.resize(cells);
  m.mu_corrected.resize(cells);
  m.samples = b.n;
  for (size_t i = 0; i < cells; ++i) {
    const bool ok = b.n[i] >= options.min_samples;
    m.mu_raw[i] = ok ? b.raw[i] / b.n[i] : kNaN;
    m.mu_corrected[i] = ok ? b.corrected[i] / b.n[i] : kNaN;
  }
}

// The map's variation along the track after running-in, raw and
// corrected, against its noise (`block` cycles share their slope).
void StoreVariation(int block, FrictionMap* map) {
  FrictionMap& m = *map;
  std::vector<double> raw_pattern;
  double raw_noise = 0;
  SpatialVariation(m,
                   m.mu_raw,
                   m.first_steady_cycle,
                   block,
                   &m.spatial_sd_raw,
                   &raw_noise,
                   &raw_pattern);
  SpatialVariation(m,
                   m.mu_corrected,
                   m.first_steady_cycle,
                   block,
                   &m.spatial_sd_corrected,
                   &m.spatial_sd_noise,
                   &m.steady_corrected);
  m.spatial_sd_excess =
      std::isfinite(m.spatial_sd_noise)
          ? std::sqrt(std::max(0.0,
                               m.spatial_sd_corrected * m.spatial_sd_corrected -
                                   m.spatial_sd_noise * m.spatial_sd_noise))
          : kNaN;
}

}  // namespace

FrictionMap ComputeFrictionMap(const force::ForceRecord& record,
                               const force::CycleSet& cycles,
                               const FrictionFitOptions& friction,
                               int first_steady,
                               const FrictionMapOptions& options) {
  WEARSCAR_CHECK(record.IsConsistent(), "ComputeFrictionMap needs one length");
  std::string why;
  if (!options.IsValid(&why)) throw FusionError(why);
  FrictionMap m;
  m.cycles = static_cast<int>(cycles.cycles.size());
  if (m.cycles == 0) return m;
  const auto [lo, hi] = force::CyclesXRange(record.x_mm, cycles);
  if (!(hi > lo)) return m;
  Bins b;
  b.width = options.bin_mm;
  b.count = static_cast<size_t>(std::ceil((hi - lo) / b.width));
  b.lo = 0.5 * (lo + hi) - 0.5 * b.count * b.width;  // centred on the stroke
  const size_t cells = static_cast<size_t>(m.cycles) * 2 * b.count;
  b.raw.assign(cells, 0);
  b.corrected.assign(cells, 0);
  b.n.assign(cells, 0);
  FrictionFitOptions map_friction = friction;
  if (options.slope_polynomial_order != 0) {
    map_friction.ensemble.polynomial_order = options.slope_polynomial_order;
  }
  if (options.slope_span_mm > 0) {
    map_friction.ensemble.span_mm =
        std::max(options.slope_span_mm, 2 * map_friction.ensemble.bin_mm);
  }
  m.slope_span_mm = map_friction.ensemble.span_mm;
  m.slope_polynomial_order = map_friction.ensemble.polynomial_order;
  LoopSums loop;
  loop.count = static_cast<size_t>(options.loop_bins);
  loop.width = loop.count > 0 ? (hi - lo) / options.loop_bins : 0.0;
  loop.lo = lo;
  const size_t loop_cells = static_cast<size_t>(m.cycles) * 2 * loop.count;
  loop.q.assign(loop_cells, 0);
  loop.p.assign(loop_cells, 0);
  loop.k.assign(loop_cells, 0);
  loop.n.assign(loop_cells, 0);
  const ForceSlopes slopes(record, cycles, map_friction);
  for (int c = 0; c < m.cycles; ++c) {
    const CycleSamples s = slopes.Gather(c);
    Accumulate(s.forward, c, &b);
    Accumulate(s.reverse, c, &b);
    if (loop.count == 0) continue;  // no loops asked for
    AccumulateLoop(s.forward, c, &loop);
    AccumulateLoop(s.reverse, c, &loop);
  }
  StoreMeans(loop, b, options, &m);
  m.first_steady_cycle = std::clamp(first_steady, 0, m.cycles - 1);
  StoreVariation(slopes.SharedCycles(), &m);
  return m;
}

double FrictionMap::LoopModelQ(int cycle,
                               int direction,
                               size_t bin,
                               double mu) const {
  const size_t at = LoopIndex(cycle, direction, bin);
  const double p = loop_p_n[at], k = loop_k[at];
  if (!std::isfinite(p) || !std::isfinite(k) || !std::isfinite(mu)) return kNaN;
  const int s = direction == 0 ? 1 : -1;
  if (!(1.0 - s * mu * k > 0)) return kNaN;
  return WearScarTangentialForce(p, k, mu, s);
}

}  // namespace wearscar::fusion
