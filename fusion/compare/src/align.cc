#include "wearscar/fusion/align.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/interpolate.h"
#include "wearscar/support/student_t.h"

namespace wearscar::fusion {
namespace {

// Linear interpolation on a uniform grid; NaN outside or next to NaN.
double Interp(const Eigen::VectorXd& v, double x0, double step, double x) {
  const double t = (x - x0) / step;
  if (!(t >= 0) || t > static_cast<double>(v.size() - 1)) return std::nan("");
  return support::InterpolateAtIndex(v, t);
}

struct Ncc {
  double r = -2;
  int n = 0;
};

// NCC of f(x_j) against h(flip x_j + shift) over the finite pairs.
Ncc Correlate(const Eigen::VectorXd& x,
              const Eigen::VectorXd& f,
              const Eigen::VectorXd& h,
              double h0,
              double step,
              int flip,
              double shift) {
  double sf = 0, sh = 0, sff = 0, shh = 0, sfh = 0;
  int n = 0;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    if (!std::isfinite(f[j])) continue;
    const double hv = Interp(h, h0, step, flip * x[j] + shift);
    if (!std::isfinite(hv)) continue;
    sf += f[j];
    sh += hv;
    sff += f[j] * f[j];
    shh += hv * hv;
    sfh += f[j] * hv;
    ++n;
  }
  Ncc out;
  out.n = n;
  if (n < 3) return out;
  const double cov = sfh - sf * sh / n, vf = sff - sf * sf / n,
               vh = shh - sh * sh / n;
  out.r = (vf > 0 && vh > 0) ? cov / std::sqrt(vf * vh) : -2;
  return out;
}

}  // namespace

bool ForceProfileOptions::IsValid(std::string* why) const {
  if (!(step_mm > 0)) {
    if (why) *why = "force profile step_mm must be > 0";
    return false;
  }
  if (cycles < 1 && first_cycle < 0) {
    if (why) *why = "force profile needs cycles >= 1 or an explicit range";
    return false;
  }
  return true;
}

bool AlignOptions::IsValid(std::string* why) const {
  if (!(step_mm > 0) || !(max_shift_mm >= 0)) {
    if (why) *why = "alignment step_mm must be > 0 and max_shift_mm >= 0";
    return false;
  }
  if (!(min_overlap_fraction > 0 && min_overlap_fraction <= 1)) {
    if (why) *why = "min_overlap_fraction must be in (0, 1]";
    return false;
  }
  if (!(waviness_window_mm > 0) ||
      !(waviness_shortest_mm >= 0 &&
        waviness_shortest_mm < waviness_window_mm)) {
    if (why)
      *why =
          "waviness_window_mm must be > 0 and waviness_shortest_mm in [0, "
          "waviness_window_mm)";
    return false;
  }
  if (ratio_blocks < 3 || ratio_blocks > 100) {
    if (why) *why = "ratio_blocks must be in [3, 100]";
    return false;
  }
  return true;
}

namespace {

// The cycles compared: an explicit range, else the last N.
void ChooseCycles(int n, const ForceProfileOptions& options, ForceProfile* p) {
  if (options.first_cycle >= 0) {
    p->first_cycle = std::clamp(options.first_cycle, 0, n - 1);
    p->last_cycle =
        std::clamp(options.last_cycle >= 0 ? options.last_cycle : n - 1,
                   p->first_cycle,
                   n - 1);
  } else {
    p->last_cycle = n - 1;
    p->first_cycle = std::max(0, n - options.cycles);
  }
}

// P/S binned along x per direction over the compared cycles' gross slip:
// sums, sums of squares and counts; with `per_cycle`, each cycle's sums
// and counts too (rows: cycles), whose noise ProfilesFromBins reads.
struct DirectionBins {
  Eigen::VectorXd sum[2], sum2[2], count[2];
  Eigen::MatrixXd cycle_sum[2], cycle_count[2];
};

// `values` / `per_mm` is the height: P and S, or the depth and -1.
DirectionBins BinHeight(const force::ForceRecord& record,
                        const force::CycleSet& cycles,
                        const ForceProfile& p,
                        double lo,
                        double step,
                        const Eigen::VectorXd& values,
                        double per_mm) {
  const Eigen::Index bins = p.x_mm.size();
  const Eigen::Index n = p.last_cycle - p.first_cycle + 1;
  DirectionBins b;
  for (int d = 0; d < 2; ++d) {
    b.sum[d] = b.sum2[d] = b.count[d] = Eigen::VectorXd::Zero(bins);
    b.cycle_sum[d] = b.cycle_count[d] = Eigen::MatrixXd::Zero(n, bins);
  }
  for (int c = p.first_cycle; c <= p.last_cycle; ++c) {
    for (const force::HalfCycle* h :
         {&cycles.cycles[c].forward, &cycles.cycles[c].reverse}) {
      const int d = h->direction > 0 ? 0 : 1;
      for (Eigen::Index i = h->slip_begin; i < h->slip_end; ++i) {
        const double x = record.x_mm[i], pn = values[i];
        if (!std::isfinite(x) || !std::isfinite(pn)) continue;
        const Eigen::Index k = std::min<Eigen::Index>(
            bins - 1, static_cast<Eigen::Index>(std::floor((x - lo) / step)));
        const double f = pn / per_mm;
        b.sum[d][k] += f;
        b.sum2[d][k] += f * f;
        b.count[d][k] += 1;
        b.cycle_sum[d](c - p.first_cycle, k) += f;
        b.cycle_count[d](c - p.first_cycle, k) += 1;
      }
    }
  }
  return b;
}

// The noise variance of one bin's mean over the cycles in one direction:
// the cycles' means' second differences (the track's change over the
// cycles, linear over three, drops out; a scatter of the samples about
// their mean would hold it), var = mean(d2^2) / 6, over the cycles that
// slid through the bin; NaN with fewer than three in a row.
double BinNoise(const Eigen::MatrixXd& sum,
                const Eigen::MatrixXd& count,
                int k) {
  double s = 0;
  int triples = 0, cycles = 0;
  for (Eigen::Index c = 0; c < sum.rows(); ++c) {
    cycles += count(c, k) > 0;
    if (c < 2 || count(c, k) == 0 || count(c - 1, k) == 0 ||
        count(c - 2, k) == 0)
      continue;
    const double d2 = sum(c, k) / count(c, k) -
                      2 * sum(c - 1, k) / count(c - 1, k) +
                      sum(c - 2, k) / count(c - 2, k);
    s += d2 * d2, ++triples;
  }
  return triples > 0 ? s / triples / 6 / cycles : NAN;
}

// The profiles per direction and their mean from the bins, and the noise
// variance of the mean profile (the bins seen in both directions).
void ProfilesFromBins(const DirectionBins& b, ForceProfile* p) {
  const Eigen::Index bins = p->x_mm.size();
  p->forward_mm.resize(bins);
  p->reverse_mm.resize(bins);
  p->mean_mm.resize(bins);
  double noise = 0;
  int noise_bins = 0;
  const bool over_cycles = b.cycle_sum[0].rows() >= 3;
  for (Eigen::Index k = 0; k < bins; ++k) {
    if (b.count[0][k] > 1 && b.count[1][k] > 1) {
      double v = 0;
      for (int d = 0; d < 2; ++d) {
        const double count = b.count[d][k], mean = b.sum[d][k] / count;
        const double cycles = over_cycles ? BinNoise(b.cycle_sum[d],
                                                     b.cycle_count[d],
                                                     static_cast<int>(k))
                                          : NAN;
        v += 0.25 * (std::isfinite(cycles)
                         ? cycles
                         : std::max(0.0, b.sum2[d][k] - count * mean * mean) /
                               (count - 1) / count);
      }
      noise += v;
      ++noise_bins;
    }
    p->forward_mm[k] =
        b.count[0][k] > 0 ? b.sum[0][k] / b.count[0][k] : std::nan("");
    p->reverse_mm[k] =
        b.count[1][k] > 0 ? b.sum[1][k] / b.count[1][k] : std::nan("");
    const bool f = std::isfinite(p->forward_mm[k]),
               r = std::isfinite(p->reverse_mm[k]);
    p->mean_mm[k] = f && r ? 0.5 * (p->forward_mm[k] + p->reverse_mm[k])
                    : f    ? p->forward_mm[k]
                    : r    ? p->reverse_mm[k]
                           : std::nan("");
  }
  p->noise_variance_mm2 = noise_bins > 0 ? noise / noise_bins : 0.0;
}

}  // namespace

namespace {

// The profile's bins over the compared cycles' gross slip: [lo, lo + bins
// step); throws when there is none.
double ForceProfileGrid(const force::ForceRecord& record,
                        const force::CycleSet& cycles,
                        const ForceProfileOptions& options,
                        ForceProfile* p) {
  ChooseCycles(static_cast<int>(cycles.cycles.size()), options, p);
  double lo = INFINITY, hi = -INFINITY;
  for (int c = p->first_cycle; c <= p->last_cycle; ++c) {
    for (const force::HalfCycle* h :
         {&cycles.cycles[c].forward, &cycles.cycles[c].reverse}) {
      for (Eigen::Index i = h->slip_begin; i < h->slip_end; ++i) {
        if (!std::isfinite(record.x_mm[i])) continue;
        lo = std::min(lo, record.x_mm[i]);
        hi = std::max(hi, record.x_mm[i]);
      }
    }
  }
  if (!(hi > lo))
    throw FusionError("no gross-slip samples to build the force-side profile");
  const double step = options.step_mm;
  const Eigen::Index bins =
      static_cast<Eigen::Index>(std::floor((hi - lo) / step)) + 1;
  p->x_mm = Eigen::VectorXd::LinSpaced(
      bins, lo + 0.5 * step, lo + (bins - 0.5) * step);
  return lo;
}

}  // namespace

ForceProfile ComputeFrictionProfile(const force::ForceRecord& record,
                                    const force::CycleSet& cycles,
                                    const ForceProfileOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw FusionError(why);
  ForceProfile p;
  const double lo = ForceProfileGrid(record, cycles, options, &p);
  const double step = options.step_mm;
  const Eigen::Index bins = p.x_mm.size();
  // atan(Q/P) per direction and bin: theta + s phi on the wear-scar model.
  DirectionBins b;
  for (int d = 0; d < 2; ++d)
    b.sum[d] = b.sum2[d] = b.count[d] = Eigen::VectorXd::Zero(bins);
  for (int c = p.first_cycle; c <= p.last_cycle; ++c) {
    for (const force::HalfCycle* h :
         {&cycles.cycles[c].forward, &cycles.cycles[c].reverse}) {
      const int d = h->direction > 0 ? 0 : 1;
      for (Eigen::Index i = h->slip_begin; i < h->slip_end; ++i) {
        const double x = record.x_mm[i], q = record.tangential_n[i],
                     pn = record.normal_n[i];
        if (!std::isfinite(x) || !std::isfinite(q) || !(pn > 0)) continue;
        const Eigen::Index k = std::min<Eigen::Index>(
            bins - 1, static_cast<Eigen::Index>(std::floor((x - lo) / step)));
        const double a = std::atan(q / pn);
        b.sum[d][k] += a;
        b.sum2[d][k] += a * a;
        b.count[d][k] += 1;
      }
    }
  }
  // k = tan(theta) where both directions slid, and its noise variance.
  Eigen::VectorXd slope(bins), slope_var(bins);
  for (Eigen::Index k = 0; k < bins; ++k) {
    slope[k] = slope_var[k] = std::nan("");
    if (!(b.count[0][k] > 1 && b.count[1][k] > 1)) continue;
    double theta = 0, var = 0;
    for (int d = 0; d < 2; ++d) {
      const double n = b.count[d][k], mean = b.sum[d][k] / n;
      theta += 0.5 * mean;
      var += 0.25 * std::max(0.0, b.sum2[d][k] - n * mean * mean) / (n - 1) / n;
    }
    const double sec2 = 1 + std::tan(theta) * std::tan(theta);
    slope[k] = std::tan(theta);
    slope_var[k] = sec2 * sec2 * var;
  }
  // The height: the slope integrated along x from the first bin both
  // directions slid (trapezoids; an empty bin between takes its
  // neighbours' mean), about its mean; its noise a random walk.
  p.mean_mm = Eigen::VectorXd::Constant(bins, std::nan(""));
  Eigen::Index first = 0, last = bins - 1;
  while (first < bins && !std::isfinite(slope[first])) ++first;
  while (last > first && !std::isfinite(slope[last])) --last;
  if (last - first < 2)
    throw FusionError(
        "too few positions where both directions slid to build the profile "
        "from the friction");
  double h = 0, walk = 0, walk_sum = 0, mean = 0;
  double previous = slope[first];
  p.mean_mm[first] = 0;
  for (Eigen::Index k = first + 1; k <= last; ++k) {
    double here = slope[k];
    if (!std::isfinite(here)) {
      Eigen::Index next = k + 1;
      while (next <= last && !std::isfinite(slope[next])) ++next;
      here = 0.5 * (previous + slope[next]);
    } else {
      walk += step * step * slope_var[k];
    }
    h += 0.5 * (previous + here) * step;
    p.mean_mm[k] = h;
    previous = here;
    walk_sum += walk;
  }
  for (Eigen::Index k = first; k <= last; ++k) mean += p.mean_mm[k];
  mean /= static_cast<double>(last - first + 1);
  for (Eigen::Index k = first; k <= last; ++k) p.mean_mm[k] -= mean;
  p.forward_mm = p.reverse_mm = p.mean_mm;
  p.noise_variance_mm2 = walk_sum / static_cast<double>(last - first + 1);
  return p;
}

ForceProfile ComputeForceProfile(const force::ForceRecord& record,
                                 const force::CycleSet& cycles,
                                 double spring_n_per_mm,
                                 const ForceProfileOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw FusionError(why);
  ForceProfile p;
  const double lo = ForceProfileGrid(record, cycles, options, &p);
  const double step = options.step_mm;
  ProfilesFromBins(
      BinHeight(record, cycles, p, lo, step, record.normal_n, spring_n_per_mm),
      &p);
  return p;
}

ForceProfile ComputeDepthProfile(const force::ForceRecord& record,
                                 const force::CycleSet& cycles,
                                 const ForceProfileOptions& options,
                                 double depth_sign) {
  std::string why;
  if (!options.IsValid(&why)) throw FusionError(why);
  if (!record.has_depth())
    throw FusionError("a depth profile, but the record has no depth channel");
  ForceProfile p;
  const double lo = ForceProfileGrid(record, cycles, options, &p);
  ProfilesFromBins(
      BinHeight(
          record, cycles, p, lo, options.step_mm, record.depth_mm, -depth_sign),
      &p);
  return p;
}

namespace {

// The scan profile resampled on the alignment grid (step_mm from s0).
struct ScanGrid {
  Eigen::VectorXd h;
  double s0 = 0, step = 0, length = 0;
  double noise_variance_mm2 = 0;  // the profile's (WearProfile's)
};

ScanGrid ResampleScan(const scan::WearProfile& sp, double step) {
  ScanGrid g;
  g.step = step;
  g.noise_variance_mm2 = sp.noise_variance_mm2;
  g.s0 = sp.s_mm[0];
  const double s1 = sp.s_mm[sp.s_mm.size() - 1];
  g.length = s1 - g.s0;
  const Eigen::Index m =
      static_cast<Eigen::Index>(std::floor((s1 - g.s0) / step)) + 1;
  g.h.resize(m);
  for (Eigen::Index i = 0; i < m; ++i)
    g.h[i] = Interp(sp.height_mm, g.s0, sp.step_mm, g.s0 + i * step);
  return g;
}

// The best whole-step shift (and flip) by normalised cross-correlation
// over an overlap of at least min_overlap_fraction of the force profile,
// refined to a sub-step shift by a parabola through the peak.
Alignment BestShift(const ForceProfile& fp,
                    const ScanGrid& g,
                    const AlignOptions& options,
                    int* best_flip) {
  const double step = g.step;
  const int valid_force = static_cast<int>(
      fp.mean_mm
          .unaryExpr([](double v) { return std::isfinite(v) ? 1.0 : 0.0; })
          .sum());
  const int min_overlap =
      static_cast<int>(std::ceil(options.min_overlap_fraction * valid_force));
  Alignment best;
  *best_flip = 1;
  const int shifts = static_cast<int>(std::floor(options.max_shift_mm / step));
  for (int flip : {1, -1}) {
    if (flip < 0 && !options.allow_flip) continue;
    for (int k = -shifts; k <= shifts; ++k) {
      const Ncc c =
          Correlate(fp.x_mm, fp.mean_mm, g.h, g.s0, step, flip, k * step);
      if (c.n < min_overlap || c.r <= best.correlation) continue;
      best.correlation = c.r;
      best.shift_mm = k * step;
      best.overlap_samples = c.n;
      *best_flip = flip;
    }
  }
  if (best.overlap_samples == 0) {
    throw FusionError(fmt::format(
        "the scan profile ({:.2f} mm) and the force-side profile "
        "({:.2f} mm) cannot overlap on {:.0f}% of the force profile within "
        "+-{} mm of shift; expected the scan to cover the stroke",
        g.length,
        fp.x_mm[fp.x_mm.size() - 1] - fp.x_mm[0],
        100 * options.min_overlap_fraction,
        options.max_shift_mm));
  }
  best.flipped = *best_flip < 0;
  const Ncc left = Correlate(
      fp.x_mm, fp.mean_mm, g.h, g.s0, step, *best_flip, best.shift_mm - step);
  const Ncc right = Correlate(
      fp.x_mm, fp.mean_mm, g.h, g.s0, step, *best_flip, best.shift_mm + step);
  if (left.r > -2 && right.r > -2) {
    const double denom = left.r - 2 * best.correlation + right.r;
    if (denom < 0) {
      const double delta = 0.5 * (left.r - right.r) / denom;
      if (std::abs(delta) < 1) best.shift_mm += delta * step;
    }
  }
  return best;
}

// Sums over the overlap of the two profiles, without [skip_begin,
// skip_end): variances, covariance and means (times the count for the
// variances).
struct Moments {
  double vf, vh, cfh, mf, mh;
};

Moments OverlapMoments(const std::vector<double>& fs,
                       const std::vector<double>& hs,
                       int skip_begin,
                       int skip_end) {
  double sf = 0, sh = 0, sff = 0, shh = 0, sfh = 0;
  int k = 0;
  for (int j = 0; j < static_cast<int>(fs.size()); ++j) {
    if (j >= skip_begin && j < skip_end) continue;
    sf += fs[j];
    sh += hs[j];
    sff += fs[j] * fs[j];
    shh += hs[j] * hs[j];
    sfh += fs[j] * hs[j];
    ++k;
  }
  return {
      sff - sf * sf / k, shh - sh * sh / k, sfh - sf * sh / k, sf / k, sh / k};
}

// v less its centred running mean over `window` points (the ends, where
// the window does not fit, dropped).
std::vector<double> HighPass(const std::vector<double>& v, int window) {
  const int n = static_cast<int>(v.size()), half = window / 2;
  std::vector<double> out;
  if (n <= 2 * half) return out;
  double sum = 0;
  for (int j = 0; j < 2 * half + 1; ++j) sum += v[j];
  for (int i = half; i + half < n; ++i) {
    if (i > half) sum += v[i + half] - v[i - half - 1];
    out.push_back(v[i] - sum / (2 * half + 1));
  }
  return out;
}

// v's centred running mean over `window` points (the ends dropped).
std::vector<double> LowPass(const std::vector<double>& v, int window) {
  const std::vector<double> high = HighPass(v, window);
  const int half = window / 2;
  std::vector<double> out(high.size());
  for (size_t i = 0; i < high.size(); ++i) out[i] = v[i + half] - high[i];
  return out;
}

// The share of white noise's variance a running mean over `smooth` points,
// less its running mean over `window`, keeps: the sum of the squared
// weights of that filter.
double BandNoiseShare(int smooth, int window) {
  const int hs = smooth / 2, hw = window / 2;
  std::vector<double> k(2 * (hs + hw) + 1, 0.0);
  for (int i = -hs; i <= hs; ++i) k[i + hs + hw] += 1.0 / (2 * hs + 1);
  for (int j = -hw; j <= hw; ++j) {
    for (int i = -hs; i <= hs; ++i)
      k[i + j + hs + hw] -= 1.0 / (2 * hs + 1) / (2 * hw + 1);
  }
  double sum = 0;
  for (double w : k) sum += w * w;
  return sum;
}

// The waviness's noise-corrected correlation and its variance over the
// noise's (Alignment::waviness_*), in the band a sphere's contact follows:
// features shorter than `smooth` points are a sensor's (a P resolution's
// pattern over the sampled positions, repeated every cycle), those longer
// than `window` the groove's envelope.
void Waviness(const std::vector<double>& fs,
              const std::vector<double>& hs,
              double noise_variance,
              double scan_noise_variance,
              int smooth,
              int window,
              Alignment* best) {
  const std::vector<double> f = HighPass(LowPass(fs, smooth), window),
                            h = HighPass(LowPass(hs, smooth), window);
  const int n = static_cast<int>(f.size());
  if (n < 4 * window) return;
  const Moments m = OverlapMoments(f, h, 0, 0);
  if (!(m.vf > 0 && m.vh > 0)) return;
  const double share = BandNoiseShare(smooth, window);
  const double noise = n * noise_variance * share;
  const double signal = std::max(0.0, m.vf - noise);
  // The scan's texture across the track (its band's halves disagree) is
  // its noise: corrected for as the force profile's is, so a faint
  // waviness under a rough surface is not taken for another track's.
  const double scan_signal =
      std::max(0.0, m.vh - n * scan_noise_variance * share);
  best->waviness_to_noise = noise > 0 ? signal / noise : INFINITY;
  const double r = m.cfh / std::sqrt(m.vf * m.vh);
  best->waviness_correlation =
      signal > 0 && scan_signal > 0
          ? std::min(1.0, r * std::sqrt(m.vf / signal * m.vh / scan_signal))
          : NAN;
}

// The waviness's correlation (not corrected for noise) with the scan
// shifted to `shift`, over the bins both directions slid.
double WavinessAt(const ForceProfile& fp,
                  const ScanGrid& g,
                  int flip,
                  double shift,
                  int smooth,
                  int window) {
  std::vector<double> fs, hs;
  for (Eigen::Index j = 0; j < fp.x_mm.size(); ++j) {
    const double hv = Interp(g.h, g.s0, g.step, flip * fp.x_mm[j] + shift);
    if (!std::isfinite(fp.forward_mm[j]) || !std::isfinite(fp.reverse_mm[j]) ||
        !std::isfinite(fp.mean_mm[j]) || !std::isfinite(hv))
      continue;
    fs.push_back(fp.mean_mm[j]);
    hs.push_back(hv);
  }
  const std::vector<double> f = HighPass(LowPass(fs, smooth), window),
                            h = HighPass(LowPass(hs, smooth), window);
  if (static_cast<int>(f.size()) < 4 * window) return NAN;
  const Moments m = OverlapMoments(f, h, 0, 0);
  return m.vf > 0 && m.vh > 0 ? m.cfh / std::sqrt(m.vf * m.vh) : NAN;
}

// Alignment::waviness_runner_up: the best waviness correlation more than
// a window away from the best shift, corrected by the best's own factor
// (the texture a twin would not share lowers it; its rings would not).
void WavinessRunnerUp(const ForceProfile& fp,
                      const ScanGrid& g,
                      int flip,
                      const AlignOptions& options,
                      int smooth,
                      int window,
                      Alignment* best) {
  const double at_best =
      WavinessAt(fp, g, flip, best->shift_mm, smooth, window);
  if (!(at_best > 0) || !std::isfinite(best->waviness_correlation)) return;
  // As far as the profiles still overlap on min_overlap_fraction of the
  // force profile: a ring period may exceed the alignment's search.
  const double length = fp.x_mm[fp.x_mm.size() - 1] - fp.x_mm[0];
  const double reach = std::max(options.max_shift_mm,
                                (1 - options.min_overlap_fraction) * length);
  // Every other step: a ring's peak spans a contact's width, tenths of a
  // millimetre.
  const double step = 2 * g.step;
  const int shifts = static_cast<int>(std::floor(reach / step));
  double top = -INFINITY, where = NAN;
  for (int k = -shifts; k <= shifts; ++k) {
    const double shift = best->shift_mm + k * step;
    if (std::abs(shift - best->shift_mm) <= options.waviness_window_mm)
      continue;
    const double r = WavinessAt(fp, g, flip, shift, smooth, window);
    if (r > top) top = r, where = shift;
  }
  if (!std::isfinite(top)) return;
  best->waviness_runner_up =
      std::min(1.0, top * best->waviness_correlation / at_best);
  best->waviness_runner_up_shift_mm = where;
}

// Least-squares scale and offset, the amplitude ratio std(f) / std(h) with
// f's variance less its noise, the noise-corrected correlation, and the
// ratio's 95% interval by a delete-a-block jackknife over contiguous
// stretches of the overlap (neighbouring points are correlated; each block
// holds several features of the track).
void ScaleAndRatio(const ForceProfile& fp,
                   const ScanGrid& g,
                   int flip,
                   const AlignOptions& options,
                   Alignment* best) {
  const int blocks = options.ratio_blocks;
  // (The waviness over the bins both directions slid: where one alone
  // did, near the ends, its mean holds P's drift over the half cycle, a
  // spring's preload relaxing as the groove deepens, which no scan shows.)
  std::vector<double> fs, hs, fs_both, hs_both;
  for (Eigen::Index j = 0; j < fp.x_mm.size(); ++j) {
    const double f = fp.mean_mm[j];
    const double hv =
        Interp(g.h, g.s0, g.step, flip * fp.x_mm[j] + best->shift_mm);
    if (!std::isfinite(f) || !std::isfinite(hv)) continue;
    fs.push_back(f);
    hs.push_back(hv);
    if (std::isfinite(fp.forward_mm[j]) && std::isfinite(fp.reverse_mm[j]))
      fs_both.push_back(f), hs_both.push_back(hv);
  }
  const int n = static_cast<int>(fs.size());
  auto ratio = [&](double vf, double vh, int points) {
    const double signal = std::max(0.0, vf - points * fp.noise_variance_mm2);
    return vh > 0 ? std::sqrt(signal / vh) : 0.0;
  };
  const Moments all = OverlapMoments(fs, hs, 0, 0);
  best->scale = all.vh > 0 ? all.cfh / all.vh : 0.0;
  best->offset_mm = all.mf - best->scale * all.mh;
  best->amplitude_ratio = ratio(all.vf, all.vh, n);
  const double noise_share =
      all.vf > 0 ? n * fp.noise_variance_mm2 / all.vf : 0.0;
  best->correlation_noise_corrected =
      noise_share < 0.99
          ? std::min(1.0, best->correlation / std::sqrt(1.0 - noise_share))
          : best->correlation;
  best->overlap_samples = n;
  const Eigen::Index bins = fp.x_mm.size();
  const double bin_mm = (fp.x_mm[bins - 1] - fp.x_mm[0]) / (bins - 1);
  auto points = [bin_mm](double mm) {
    return std::max(1, static_cast<int>(std::lround(mm / bin_mm)) | 1);
  };
  Waviness(fs_both,
           hs_both,
           fp.noise_variance_mm2,
           g.noise_variance_mm2,
           points(options.waviness_shortest_mm),
           std::max(3, points(options.waviness_window_mm)),
           best);
  if (n < 4 * blocks || !(all.vh > 0)) return;
  std::vector<double> r(blocks);
  double mean = 0;
  for (int b = 0; b < blocks; ++b) {
    const int skip = (b + 1) * n / blocks - b * n / blocks;
    const Moments part =
        OverlapMoments(fs, hs, b * n / blocks, (b + 1) * n / blocks);
    r[b] =
        part.vh > 0 ? ratio(part.vf, part.vh, n - skip) : best->amplitude_ratio;
    mean += r[b] / blocks;
  }
  double ss = 0;
  for (double v : r) ss += (v - mean) * (v - mean);
  const double se = std::sqrt((blocks - 1.0) / blocks * ss);
  const double t = support::StudentT975(blocks - 1);
  best->amplitude_ratio_low = best->amplitude_ratio - t * se;
  best->amplitude_ratio_high = best->amplitude_ratio + t * se;
}

}  // namespace

void FindWavinessRunnerUp(const ForceProfile& fp,
                          const scan::WearProfile& sp,
                          const AlignOptions& options,
                          Alignment* a) {
  if (sp.s_mm.size() < 3 || fp.x_mm.size() < 3) return;
  const ScanGrid g = ResampleScan(sp, options.step_mm);
  const Eigen::Index bins = fp.x_mm.size();
  const double bin_mm = (fp.x_mm[bins - 1] - fp.x_mm[0]) / (bins - 1);
  auto points = [bin_mm](double mm) {
    return std::max(1, static_cast<int>(std::lround(mm / bin_mm)) | 1);
  };
  WavinessRunnerUp(fp,
                   g,
                   a->flipped ? -1 : 1,
                   options,
                   points(options.waviness_shortest_mm),
                   std::max(3, points(options.waviness_window_mm)),
                   a);
}

Alignment AlignProfiles(const ForceProfile& fp,
                        const scan::WearProfile& sp,
                        const AlignOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw FusionError(why);
  if (sp.s_mm.size() < 3 || fp.x_mm.size() < 3) {
    throw FusionError("alignment needs at least 3 points in each profile");
  }
  const ScanGrid g = ResampleScan(sp, options.step_mm);
  int flip = 1;
  Alignment best = BestShift(fp, g, options, &flip);
  const double shift = best.shift_mm;
  best.correlation =
      Correlate(fp.x_mm, fp.mean_mm, g.h, g.s0, g.step, flip, shift).r;
  best.correlation_forward =
      Correlate(fp.x_mm, fp.forward_mm, g.h, g.s0, g.step, flip, shift).r;
  best.correlation_reverse =
      Correlate(fp.x_mm, fp.reverse_mm, g.h, g.s0, g.step, flip, shift).r;
  ScaleAndRatio(fp, g, flip, options, &best);
  best.message =
      fmt::format("shift {:.3f} mm{}, r = {:.3f}, scale {:.2f}, {} points",
                  best.shift_mm,
                  best.flipped ? " (flipped)" : "",
                  best.correlation,
                  best.scale,
                  best.overlap_samples);
  return best;
}

Eigen::VectorXd ScanHeightAtPlate(
    const scan::WearProfile& sp,
    const Alignment& a,
    const Eigen::Ref<const Eigen::VectorXd>& x_mm) {
  Eigen::VectorXd out(x_mm.size());
  for (Eigen::Index i = 0; i < x_mm.size(); ++i) {
    out[i] =
        Interp(sp.height_mm, sp.s_mm[0], sp.step_mm, a.ScanFromPlate(x_mm[i]));
  }
  return out;
}

PlateProfile ScanSlopeInPlate(const scan::WearProfile& sp,
                              const Alignment& a,
                              const force::DerivativeOptions& derivative,
                              double stroke_min_mm,
                              double stroke_max_mm) {
  force::DerivativeOptions d = derivative;
  d.min_span_mm = 0;              // s is uniform: no widening needed
  d.shift_window_at_ends = true;  // only the path's own samples enter
  // x = flip (s - shift); dh/dx = flip dh/ds.
  auto plate_x = [&](double s) {
    return a.flipped ? -(s - a.shift_mm) : s - a.shift_mm;
  };
  // Samples on the sliding path; s increases, so they are a run.
  const Eigen::Index m = sp.s_mm.size();
  auto on_path = [&](Eigen::Index i) {
    const double x = plate_x(sp.s_mm[i]);
    return x >= stroke_min_mm && x <= stroke_max_mm;
  };
  Eigen::Index lo = 0, hi = m;
  while (lo < m && !on_path(lo)) ++lo;
  while (hi > lo && !on_path(hi - 1)) --hi;
  if (hi - lo < 2) return {};
  const Eigen::Index n = hi - lo;
  const Eigen::VectorXd dhds = force::DerivativeAlongX(
      sp.s_mm.segment(lo, n), sp.height_mm.segment(lo, n), 0, n, d);
  // In s order: the neighbour beyond each end of the path (when the scan
  // has one) carries the end's slope, so every x of the stroke lies between
  // two slopes; then order by increasing x.
  std::vector<double> xs, ks;
  xs.reserve(n + 2);
  ks.reserve(n + 2);
  auto add = [&](Eigen::Index i, double dh) {
    xs.push_back(plate_x(sp.s_mm[i]));
    ks.push_back(a.flipped ? -dh : dh);
  };
  if (lo > 0) add(lo - 1, dhds[0]);
  for (Eigen::Index i = 0; i < n; ++i) add(lo + i, dhds[i]);
  if (hi < m) add(hi, dhds[n - 1]);
  if (a.flipped) {
    std::reverse(xs.begin(), xs.end());
    std::reverse(ks.begin(), ks.end());
  }
  PlateProfile k;
  k.x_mm = Eigen::Map<const Eigen::VectorXd>(
      xs.data(), static_cast<Eigen::Index>(xs.size()));
  k.k = Eigen::Map<const Eigen::VectorXd>(ks.data(),
                                          static_cast<Eigen::Index>(ks.size()));
  return k;
}

}  // namespace wearscar::fusion
