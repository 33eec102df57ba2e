#include "wearscar/fusion/track_history.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "wearscar/fusion/error.h"
#include "wearscar/support/check.h"

namespace wearscar::fusion {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

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
  if (k < 2) return kNan;
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
  h->final_waviness_sd_mm = m > 0 ? last / m : kNan;
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
  h.height_mm.assign(static_cast<size_t>(h.cycles) * 2 * bins, kNan);
  h.waviness_sd_mm.assign(h.cycles, kNan);
  std::vector<double> sum(bins), sum2(bins), count(bins);
  // Per cycle, the noise-corrected variance of h summed over directions.
  std::vector<double> variance(static_cast<size_t>(h.cycles), 0.0);
  std::vector<int> variances(static_cast<size_t>(h.cycles), 0);
  for (int c = 0; c < h.cycles; ++c) {
    for (const force::HalfCycle* half :
         {&cycles.cycles[c].forward, &cycles.cycles[c].reverse}) {
      const int d = half->direction > 0 ? 0 : 1;
      std::fill(sum.begin(), sum.end(), 0.0);
      std::fill(sum2.begin(), sum2.end(), 0.0);
      std::fill(count.begin(), count.end(), 0.0);
      for (Eigen::Index i = half->begin; i < half->end; ++i) {
        const double x = record.x_mm[i], p = record.normal_n[i];
        if (!std::isfinite(x) || !std::isfinite(p)) continue;
        const auto b =
            static_cast<long>(std::floor((x - start) / options.bin_mm));
        if (b < 0 || b >= static_cast<long>(bins)) continue;
        sum[b] += p;
        sum2[b] += p * p;
        count[b] += 1;
      }
      // Bin means of P/S about their mean over the bins (uniform in x).
      double mean = 0;
      int k = 0;
      for (size_t b = 0; b < bins; ++b) {
        if (count[b] > 0) mean += sum[b] / count[b], ++k;
      }
      if (k < 2) continue;
      mean /= k;
      for (size_t b = 0; b < bins; ++b) {
        if (count[b] > 0)
          h.height_mm[h.Index(c, d, b)] =
              (sum[b] / count[b] - mean) / spring_n_per_mm;
      }
      // The sensor noise left in the bin means (their variance, from the
      // scatter within each bin) is taken out of the waviness.
      double noise = 0;
      int noisy = 0;
      for (size_t b = 0; b < bins; ++b) {
        if (count[b] < 2) continue;
        const double m = sum[b] / count[b];
        noise += std::max(0.0, (sum2[b] / count[b] - m * m)) / (count[b] - 1) /
                 (spring_n_per_mm * spring_n_per_mm);
        ++noisy;
      }
      const double s = SdOf(h.height_mm, h.Index(c, d, 0), bins);
      if (!std::isfinite(s)) continue;
      variance[c] += s * s - (noisy > 0 ? noise / noisy : 0);
      ++variances[c];
    }
  }
  // Pooled over the cycles about each: centred, shifted inwards at the
  // ends of the test so that every cycle pools as many.
  const int pool = std::min(options.pool_cycles, h.cycles);
  for (int c = 0; c < h.cycles; ++c) {
    const int from = std::clamp(c - pool / 2, 0, h.cycles - pool);
    double v = 0;
    int n = 0;
    for (int j = from; j < from + pool; ++j)
      v += variance[j], n += variances[j];
    if (variances[c] > 0 && n > 0)
      h.waviness_sd_mm[c] = std::sqrt(std::max(0.0, v / n));
  }
  FindSteady(&h, options.steady_tolerance);
  return h;
}

}  // namespace wearscar::fusion
