#include "wearscar/fusion/track_history.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "wearscar/fusion/error.h"
#include "wearscar/support/check.h"
#include "wearscar/support/numbers.h"

namespace wearscar::fusion {
namespace {

using support::kNaN;

// The sd over the finite values of v[from, from + n).
double SdOf(const std::vector<double>& v, size_t from, size_t n) {
  double sum = 0, sum2 = 0;
  int k = 0;
  for (size_t i = from; i < from + n; ++i) {
    if (!std::isfinite(v[i])) continue;
    sum += v[i];
    sum2 += v[i] * v[i];
    ++k;
  }
  if (k < 2) return kNaN;
  const double mean = sum / k;
  return std::sqrt(std::max(0.0, sum2 / k - mean * mean));
}

// From which cycle the waviness stays within `tolerance` of the line
// fitted over the second half, and that line's slope.
void FindSteady(TrackHistory* h, double tolerance) {
  const int n = h->cycles;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int k = 0;
  for (int c = n / 2; c < n; ++c) {
    const double y = h->waviness_sd_mm[c];
    if (!std::isfinite(y)) continue;
    sx += c, sy += y, sxx += 1.0 * c * c, sxy += c * y, ++k;
  }
  if (k < 2) return;
  const double slope = (k * sxy - sx * sy) / (k * sxx - sx * sx);
  const double icpt = (sy - slope * sx) / k;
  h->growth_per_cycle_mm = slope;
  h->steady_cycle = 0;
  for (int c = 0; c < n; ++c) {
    const double trend = icpt + slope * c, y = h->waviness_sd_mm[c];
    if (std::isfinite(y) && std::abs(y - trend) > tolerance * std::abs(trend))
      h->steady_cycle = c + 1;
  }
  h->steady_cycle = std::min(h->steady_cycle, n - 1);
  double last = 0;
  int m = 0;
  for (int c = n - std::max(1, n / 10); c < n; ++c) {
    if (std::isfinite(h->waviness_sd_mm[c])) last += h->waviness_sd_mm[c], ++m;
  }
  h->final_waviness_sd_mm = m > 0 ? last / m : kNaN;
}

}  // namespace

bool TrackHistoryOptions::IsValid(std::string* why) const {
  if (!(bin_mm > 0 && bin_mm < 100)) {
    if (why) *why = "track history: bin_mm must be in (0, 100) mm";
    return false;
  }
  if (!(steady_tolerance > 0 && steady_tolerance < 1)) {
    if (why) *why = "track history: steady_tolerance must be in (0, 1)";
    return false;
  }
  if (pool_cycles < 1 || pool_cycles % 2 == 0) {
    if (why) *why = "track history: pool_cycles must be odd and >= 1";
    return false;
  }
  return true;
}

namespace {

// P binned along x over one half cycle: sums, sums of squares, counts.
struct HalfBins {
  std::vector<double> sum, sum2, count;
};

void BinHalf(const force::ForceRecord& record,
             const force::HalfCycle& half,
             double start,
             double bin_mm,
             HalfBins* b) {
  const size_t bins = b->sum.size();
  std::fill(b->sum.begin(), b->sum.end(), 0.0);
  std::fill(b->sum2.begin(), b->sum2.end(), 0.0);
  std::fill(b->count.begin(), b->count.end(), 0.0);
  for (Eigen::Index i = half.begin; i < half.end; ++i) {
    const double x = record.x_mm[i], p = record.normal_n[i];
    if (!std::isfinite(x) || !std::isfinite(p)) continue;
    const auto k = static_cast<long>(std::floor((x - start) / bin_mm));
    if (k < 0 || k >= static_cast<long>(bins)) continue;
    b->sum[k] += p;
    b->sum2[k] += p * p;
    b->count[k] += 1;
  }
}

// The bin means of P/S about their mean over the bins (uniform in x) into
// h's row (c, d); returns the sensor noise left in the bin means (their
// variance, from the scatter within each bin), or NaN for fewer than two
// bins.
double HeightRow(
    const HalfBins& b, double spring_n_per_mm, int c, int d, TrackHistory* h) {
  const size_t bins = b.sum.size();
  double mean = 0;
  int k = 0;
  for (size_t i = 0; i < bins; ++i) {
    if (b.count[i] > 0) mean += b.sum[i] / b.count[i], ++k;
  }
  if (k < 2) return kNaN;
  mean /= k;
  for (size_t i = 0; i < bins; ++i) {
    if (b.count[i] > 0)
      h->height_mm[h->Index(c, d, i)] =
          (b.sum[i] / b.count[i] - mean) / spring_n_per_mm;
  }
  double noise = 0;
  int noisy = 0;
  for (size_t i = 0; i < bins; ++i) {
    if (b.count[i] < 2) continue;
    const double m = b.sum[i] / b.count[i];
    noise += std::max(0.0, (b.sum2[i] / b.count[i] - m * m)) /
             (b.count[i] - 1) / (spring_n_per_mm * spring_n_per_mm);
    ++noisy;
  }
  return noisy > 0 ? noise / noisy : 0;
}

// One cycle's atan(Q/P) over each direction's gross slip per bin, and the
// samples' times: sums and counts, [0] forward, [1] reverse.
struct FrictionBins {
  std::vector<double> angle[2], time[2];
  std::vector<int> count[2];
  // The friction's angle atan(mu) over the cycle (half the two directions'
  // difference, over the bins both slid) and the cycle's mean time.
  double friction = kNaN, time_s = kNaN;
};

FrictionBins BinFriction(const force::ForceRecord& record,
                         const force::Cycle& cycle,
                         double start,
                         double bin_mm,
                         size_t bins) {
  FrictionBins f;
  for (int d = 0; d < 2; ++d) {
    f.angle[d].assign(bins, 0.0), f.time[d].assign(bins, 0.0);
    f.count[d].assign(bins, 0);
  }
  for (const force::HalfCycle* half : {&cycle.forward, &cycle.reverse}) {
    const int d = half->direction > 0 ? 0 : 1;
    for (Eigen::Index i = half->slip_begin; i < half->slip_end; ++i) {
      const double x = record.x_mm[i], q = record.tangential_n[i],
                   p = record.normal_n[i];
      if (!std::isfinite(x) || !std::isfinite(q) || !(p > 0)) continue;
      const auto k = static_cast<long>(std::floor((x - start) / bin_mm));
      if (k < 0 || k >= static_cast<long>(bins)) continue;
      f.angle[d][k] += std::atan(q / p);
      f.time[d][k] += record.time_s[i];
      ++f.count[d][k];
    }
  }
  double friction = 0, time = 0;
  int both = 0;
  for (size_t k = 0; k < bins; ++k) {
    if (f.count[0][k] == 0 || f.count[1][k] == 0) continue;
    friction +=
        0.5 * (f.angle[0][k] / f.count[0][k] - f.angle[1][k] / f.count[1][k]);
    time += 0.5 * (f.time[0][k] / f.count[0][k] + f.time[1][k] / f.count[1][k]);
    ++both;
  }
  if (both > 0) f.friction = friction / both, f.time_s = time / both;
  return f;
}

// One cycle's height from the friction (TrackHistory::friction_height_mm)
// into h: the two directions' mean atan(Q/P) per bin where both slid,
// less what the friction's drift between the two passes over the bin
// adds (rate: `drift` per s, from the neighbouring cycles; a running-in
// otherwise tilts the path by half the change between the passes), tan of
// it integrated along x by trapezoids (a bin between two that slid takes
// their mean), about its mean.
void FrictionRow(const FrictionBins& f,
                 double drift,
                 int c,
                 double bin_mm,
                 TrackHistory* h) {
  const size_t bins = h->x_mm.size();
  std::vector<double> slope(bins, kNaN);
  for (size_t k = 0; k < bins; ++k) {
    if (f.count[0][k] == 0 || f.count[1][k] == 0) continue;
    const double between =
        f.time[0][k] / f.count[0][k] - f.time[1][k] / f.count[1][k];
    slope[k] = std::tan(
        0.5 * (f.angle[0][k] / f.count[0][k] + f.angle[1][k] / f.count[1][k]) -
        0.5 * drift * between);
  }
  size_t first = 0, last = bins;
  while (first < bins && !std::isfinite(slope[first])) ++first;
  while (last > first && !std::isfinite(slope[last - 1])) --last;
  if (last - first < 3) return;
  double height = 0, previous = slope[first], mean = 0;
  std::vector<double> row(bins, kNaN);
  row[first] = 0;
  for (size_t k = first + 1; k < last; ++k) {
    double here = slope[k];
    if (!std::isfinite(here)) {
      size_t next = k + 1;
      while (!std::isfinite(slope[next])) ++next;  // slope[last - 1] is
      here = 0.5 * (previous + slope[next]);
    }
    height += 0.5 * (previous + here) * bin_mm;
    row[k] = height;
    previous = here;
  }
  for (size_t k = first; k < last; ++k) mean += row[k];
  mean /= static_cast<double>(last - first);
  for (size_t k = first; k < last; ++k)
    h->friction_height_mm[h->FrictionIndex(c, k)] = row[k] - mean;
}

// Every cycle's friction row, the drift of cycle c from cycles c - 1 and
// c + 1 (one-sided at the test's ends).
void FrictionRows(const std::vector<FrictionBins>& f,
                  double bin_mm,
                  TrackHistory* h) {
  const int n = static_cast<int>(f.size());
  for (int c = 0; c < n; ++c) {
    const int a = std::max(0, c - 1), b = std::min(n - 1, c + 1);
    double drift = 0;
    if (b > a && std::isfinite(f[a].friction) && std::isfinite(f[b].friction) &&
        f[b].time_s > f[a].time_s)
      drift = (f[b].friction - f[a].friction) / (f[b].time_s - f[a].time_s);
    FrictionRow(f[c], drift, c, bin_mm, h);
  }
}

// The waviness per cycle: the noise-corrected variances pooled over the
// cycles about each, centred, shifted inwards at the ends of the test so
// that every cycle pools as many.
void PoolWaviness(const std::vector<double>& variance,
                  const std::vector<int>& variances,
                  int pool_cycles,
                  TrackHistory* h) {
  const int pool = std::min(pool_cycles, h->cycles);
  for (int c = 0; c < h->cycles; ++c) {
    const int from = std::clamp(c - pool / 2, 0, h->cycles - pool);
    double v = 0;
    int n = 0;
    for (int j = from; j < from + pool; ++j)
      v += variance[j], n += variances[j];
    if (variances[c] > 0 && n > 0)
      h->waviness_sd_mm[c] = std::sqrt(std::max(0.0, v / n));
  }
}

}  // namespace

TrackHistory ComputeTrackHistory(const force::ForceRecord& record,
                                 const force::CycleSet& cycles,
                                 double spring_n_per_mm,
                                 const TrackHistoryOptions& options) {
  WEARSCAR_CHECK(record.IsConsistent(), "ComputeTrackHistory needs one length");
  std::string why;
  if (!options.IsValid(&why)) throw FusionError(why);
  if (!(spring_n_per_mm > 0))
    throw FusionError("track history: the spring stiffness must be > 0");
  TrackHistory h;
  h.cycles = static_cast<int>(cycles.cycles.size());
  const auto [lo, hi] = force::CyclesXRange(record.x_mm, cycles);
  if (h.cycles == 0 || !(hi > lo)) return h;
  const auto bins = static_cast<size_t>(std::ceil((hi - lo) / options.bin_mm));
  const double start = 0.5 * (lo + hi) - 0.5 * bins * options.bin_mm;
  for (size_t b = 0; b < bins; ++b)
    h.x_mm.push_back(start + (b + 0.5) * options.bin_mm);
  h.height_mm.assign(static_cast<size_t>(h.cycles) * 2 * bins, kNaN);
  h.waviness_sd_mm.assign(h.cycles, kNaN);
  h.friction_height_mm.assign(static_cast<size_t>(h.cycles) * bins, kNaN);
  HalfBins b{std::vector<double>(bins),
             std::vector<double>(bins),
             std::vector<double>(bins)};
  // Per cycle, the noise-corrected variance of h summed over directions.
  std::vector<double> variance(static_cast<size_t>(h.cycles), 0.0);
  std::vector<int> variances(static_cast<size_t>(h.cycles), 0);
  std::vector<FrictionBins> friction;
  for (int c = 0; c < h.cycles; ++c) {
    friction.push_back(
        BinFriction(record, cycles.cycles[c], start, options.bin_mm, bins));
    for (const force::HalfCycle* half :
         {&cycles.cycles[c].forward, &cycles.cycles[c].reverse}) {
      const int d = half->direction > 0 ? 0 : 1;
      BinHalf(record, *half, start, options.bin_mm, &b);
      const double noise = HeightRow(b, spring_n_per_mm, c, d, &h);
      if (std::isnan(noise)) continue;
      const double s = SdOf(h.height_mm, h.Index(c, d, 0), bins);
      if (!std::isfinite(s)) continue;
      variance[c] += s * s - noise;
      ++variances[c];
    }
  }
  FrictionRows(friction, options.bin_mm, &h);
  h.q_turn = force::MeasureTurnDelay(record, cycles, 0, h.cycles - 1);
  PoolWaviness(variance, variances, options.pool_cycles, &h);
  FindSteady(&h, options.steady_tolerance);
  return h;
}

}  // namespace wearscar::fusion
