#include "wearscar/fusion/ensemble.h"

#include <Eigen/LU>  // the 4 x 4 determinant
#include <algorithm>
#include <cmath>
#include <limits>

#include "wearscar/fusion/error.h"

namespace wearscar::fusion {

int PlateGrid::Bin(double x_mm) const {
  if (!std::isfinite(x_mm) || bins <= 0) return -1;
  const double t = (x_mm - x0_mm) / bin_mm;
  if (!(t >= 0) || t >= bins) return -1;
  return static_cast<int>(t);
}

PlateGrid PlateGrid::Covering(const force::ForceRecord& record,
                              const force::CycleSet& cycles,
                              double bin_mm,
                              int max_bins) {
  PlateGrid g;
  g.bin_mm = bin_mm;
  if (cycles.cycles.empty() || !(bin_mm > 0)) return g;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const Eigen::Index b = cycles.cycles.front().forward.begin;
  const Eigen::Index e = cycles.cycles.back().reverse.end;
  for (Eigen::Index i = b; i < e; ++i) {
    const double x = record.x_mm[i];
    if (!std::isfinite(x)) continue;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  if (!(hi >= lo)) return g;
  const double span = hi - lo;
  // Wider bins rather than an unbounded grid (a stroke of metres in
  // micrometre bins is a unit error caught elsewhere, not an allocation).
  if (span / bin_mm + 2 > max_bins) g.bin_mm = span / (max_bins - 2);
  g.x0_mm = lo - 0.5 * g.bin_mm;
  g.bins = static_cast<int>(std::floor(span / g.bin_mm)) + 2;
  return g;
}

CycleBins::CycleBins(const PlateGrid& grid,
                     int first_cycle,
                     int last_cycle,
                     bool with_x,
                     int ring_cycles)
    : grid_(grid), first_(first_cycle), last_(last_cycle) {
  if (last_ < first_ || grid_.bins <= 0) {
    last_ = first_ - 1;
    return;
  }
  const int held = last_ - first_ + 1;
  ring_ = ring_cycles > 0 && ring_cycles < held ? ring_cycles : 0;
  const std::size_t n = static_cast<std::size_t>(ring_ > 0 ? ring_ : held) * 2 *
                        static_cast<std::size_t>(grid_.bins);
  value_.assign(n, 0.0f);
  if (with_x) x_.assign(n, 0.0f);
  count_.assign(n, 0);
}

std::size_t CycleBins::Offset(int cycle, int direction) const {
  const int slot = ring_ > 0 ? (cycle - first_) % ring_ : cycle - first_;
  return (static_cast<std::size_t>(slot) * 2 + (direction > 0 ? 0 : 1)) *
         static_cast<std::size_t>(grid_.bins);
}

void CycleBins::ClearCycle(int cycle) {
  if (cycle < first_ || cycle > last_) return;
  const std::size_t o = Offset(cycle, +1),
                    n = 2 * static_cast<std::size_t>(grid_.bins);
  std::fill_n(value_.begin() + o, n, 0.0f);
  if (!x_.empty()) std::fill_n(x_.begin() + o, n, 0.0f);
  std::fill_n(count_.begin() + o, n, std::uint16_t{0});
}

void CycleBins::Add(int cycle, int direction, double x_mm, double value) {
  if (cycle < first_ || cycle > last_ || !std::isfinite(value)) return;
  const int b = grid_.Bin(x_mm);
  if (b < 0) return;
  const std::size_t o = Offset(cycle, direction) + static_cast<std::size_t>(b);
  if (count_[o] == std::numeric_limits<std::uint16_t>::max()) return;
  value_[o] += static_cast<float>(value);
  // x relative to the bin's left edge keeps float precision on any stroke.
  if (!x_.empty())
    x_[o] += static_cast<float>(x_mm - (grid_.x0_mm + b * grid_.bin_mm));
  ++count_[o];
}

void CycleBins::AddRange(int cycle,
                         int direction,
                         const double* x_mm,
                         const double* value,
                         Eigen::Index begin,
                         Eigen::Index end) {
  if (cycle < first_ || cycle > last_) return;
  const std::size_t o = Offset(cycle, direction);
  float* sum = value_.data() + o;
  float* sum_x = x_.empty() ? nullptr : x_.data() + o;
  std::uint16_t* count = count_.data() + o;
  for (Eigen::Index i = begin; i < end; ++i) {
    const double x = x_mm[i], v = value[i];
    // Bin (NaN fails both comparisons), as in PlateGrid::Bin.
    const double t = (x - grid_.x0_mm) / grid_.bin_mm;
    if (!std::isfinite(v) || !(t >= 0) || !(t < grid_.bins)) continue;
    const int b = static_cast<int>(t);
    if (count[b] == std::numeric_limits<std::uint16_t>::max()) continue;
    sum[b] += static_cast<float>(v);
    if (sum_x != nullptr)
      sum_x[b] += static_cast<float>(x - (grid_.x0_mm + b * grid_.bin_mm));
    ++count[b];
  }
}

void CycleBins::Accumulate(Sums* sums,
                           int cycle,
                           int direction,
                           int sign) const {
  if (cycle < first_ || cycle > last_) return;
  const std::size_t nb = static_cast<std::size_t>(std::max(grid_.bins, 0));
  const std::size_t o = Offset(cycle, direction);
  const float* v = value_.data() + o;
  const std::uint16_t* n = count_.data() + o;
  for (std::size_t b = 0; b < nb; ++b) {
    sums->value[b] += sign * static_cast<double>(v[b]);
    sums->count[b] += sign * static_cast<int>(n[b]);
  }
  if (x_.empty()) return;
  const float* x = x_.data() + o;
  for (std::size_t b = 0; b < nb; ++b)
    sums->x[b] += sign * static_cast<double>(x[b]);
}

CycleBins::Sums CycleBins::Window(
    int direction, int first, int last, int skip_first, int skip_last) const {
  Sums s;
  const std::size_t nb = static_cast<std::size_t>(std::max(grid_.bins, 0));
  s.value.assign(nb, 0.0);
  s.x.assign(nb, 0.0);
  s.count.assign(nb, 0);
  first = std::max(first, first_);
  last = std::min(last, last_);
  for (int c = first; c <= last; ++c) {
    if (c >= skip_first && c <= skip_last) continue;
    Accumulate(&s, c, direction, +1);
  }
  return s;
}

double PlateProfile::At(double x) const {
  const Eigen::Index n = x_mm.size();
  if (n < 2 || !(x >= x_mm[0] && x <= x_mm[n - 1])) return std::nan("");
  const double* begin = x_mm.data();
  const double* it = std::upper_bound(begin, begin + n, x);
  Eigen::Index i = std::clamp<Eigen::Index>((it - begin) - 1, 0, n - 2);
  const double t = (x - x_mm[i]) / (x_mm[i + 1] - x_mm[i]);
  return (1 - t) * k[i] + t * k[i + 1];
}

double PlateProfile::AtNear(double x, Eigen::Index* hint) const {
  const Eigen::Index n = x_mm.size();
  if (n < 2 || !(x >= x_mm[0] && x <= x_mm[n - 1])) return std::nan("");
  // The i of At: the last x_mm[i] <= x, at most n - 2.
  Eigen::Index i = std::clamp<Eigen::Index>(*hint, 0, n - 2);
  while (i > 0 && x < x_mm[i]) --i;
  while (i < n - 2 && x >= x_mm[i + 1]) ++i;
  *hint = i;
  const double t = (x - x_mm[i]) / (x_mm[i + 1] - x_mm[i]);
  return (1 - t) * k[i] + t * k[i + 1];
}

bool EnsembleSlopeOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (cycles < 1 || cycles > 10001 || cycles % 2 == 0)
    return fail("ensemble cycles must be odd, in [1, 10001]");
  if (!(bin_mm > 0 && bin_mm <= 1))
    return fail("ensemble bin must be in (0, 1] mm");
  if (!(span_mm >= 2 * bin_mm && span_mm <= 10))
    return fail("ensemble span must be in [2 bins, 10 mm]");
  if (min_bins < 3 || min_bins > 1000)
    return fail("ensemble min_bins must be in [3, 1000]");
  if (polynomial_order < 2 || polynomial_order > 3)
    return fail("ensemble polynomial order must be 2 or 3");
  return true;
}

namespace {

// The slope c1 of the weighted least-squares cubic in u = (x - xb) / scale
// through the bins [lo, hi] (mean x, count as weight, value = weight times
// the mean), by Cramer's rule on the 4 x 4 normal equations; NaN when they
// are singular.
double CubicSlope(const double* mean_x,
                  const double* weight,
                  const double* value,
                  std::size_t lo,
                  std::size_t hi,
                  double xb,
                  double scale) {
  const double inverse_scale = 1.0 / scale;
  double m[7] = {}, t[4] = {};
  for (std::size_t j = lo; j <= hi; ++j) {
    const double w = weight[j], y = value[j];
    const double u = (mean_x[j] - xb) * inverse_scale;
    const double u2 = u * u, u3 = u2 * u;
    m[0] += w;
    m[1] += w * u;
    m[2] += w * u2;
    m[3] += w * u3;
    m[4] += w * u2 * u2;
    m[5] += w * u2 * u3;
    m[6] += w * u3 * u3;
    t[0] += y;
    t[1] += y * u;
    t[2] += y * u2;
    t[3] += y * u3;
  }
  Eigen::Matrix4d normal;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) normal(r, c) = m[r + c];
  }
  const double det = normal.determinant();
  const double m0 = m[0];
  if (!(std::abs(det) > 1e-12 * m0 * m0 * m0 * m0)) return std::nan("");
  normal.col(1) << t[0], t[1], t[2], t[3];
  return normal.determinant() / det;
}

// Slope at each non-empty bin of a binned profile (mean x, mean value,
// count): weighted least-squares polynomial (quadratic by default) over the
// bins within span / 2,
// widened up to 4x until it holds min_bins non-empty bins.
PlateProfile SlopeOfBinnedProfile(const CycleBins& bins,
                                  const CycleBins::Sums& s,
                                  const EnsembleSlopeOptions& o,
                                  double spring) {
  const double bin_mm = bins.grid().bin_mm;
  const int nb = static_cast<int>(s.count.size());
  std::vector<int> used;
  used.reserve(nb);
  for (int b = 0; b < nb; ++b) {
    if (s.count[b] > 0) used.push_back(b);
  }
  // Mean x, weight and value of each non-empty bin, once.
  std::vector<double> mean_x(used.size()), weight(used.size()),
      value(used.size());
  for (std::size_t u = 0; u < used.size(); ++u) {
    mean_x[u] = bins.MeanX(s, used[u]);
    weight[u] = s.count[used[u]];
    value[u] = s.value[used[u]];
  }
  PlateProfile p;
  p.x_mm.resize(static_cast<Eigen::Index>(used.size()));
  p.k.resize(static_cast<Eigen::Index>(used.size()));
  const int half0 =
      std::max(1, static_cast<int>(std::lround(0.5 * o.span_mm / bin_mm)));
  const int needed = o.polynomial_order == 2
                         ? o.min_bins
                         : std::max(o.min_bins, o.polynomial_order + 2);
  Eigen::Index m = 0;
  for (std::size_t u = 0; u < used.size(); ++u) {
    const int b = used[u];
    const double xb = mean_x[u];
    double k = std::nan("");
    for (int half = half0; half <= 4 * half0; half *= 2) {
      // Neighbouring non-empty bins within +-half bins.
      std::size_t lo = u, hi = u;
      while (lo > 0 && used[lo - 1] >= b - half) --lo;
      while (hi + 1 < used.size() && used[hi + 1] <= b + half) ++hi;
      if (static_cast<int>(hi - lo + 1) < needed) continue;
      if (o.polynomial_order != 2) {
        const double scale = half * bin_mm;
        k = CubicSlope(
                mean_x.data(), weight.data(), value.data(), lo, hi, xb, scale) /
            scale / spring;
        break;
      }
      // Weighted normal equations of a + c1 u + c2 u^2, u = (x - xb) /
      // (half bins), solved for c1 by Cramer's rule (the 3x3 system is
      // symmetric: moments m0..m4 of u, and t0..t2 of y u^p).
      const double scale = half * bin_mm, inverse_scale = 1.0 / scale;
      double m0 = 0, m1 = 0, m2 = 0, m3 = 0, m4 = 0, t0 = 0, t1 = 0, t2 = 0;
      for (std::size_t j = lo; j <= hi; ++j) {
        const double w = weight[j];
        const double uu = (mean_x[j] - xb) * inverse_scale;
        const double y = value[j];  // = w * mean
        const double u2 = uu * uu;
        m0 += w;
        m1 += w * uu;
        m2 += w * u2;
        m3 += w * u2 * uu;
        m4 += w * u2 * u2;
        t0 += y;
        t1 += y * uu;
        t2 += y * u2;
      }
      const double det = m0 * (m2 * m4 - m3 * m3) - m1 * (m1 * m4 - m3 * m2) +
                         m2 * (m1 * m3 - m2 * m2);
      const double det1 = m0 * (t1 * m4 - m3 * t2) - t0 * (m1 * m4 - m3 * m2) +
                          m2 * (m1 * t2 - t1 * m2);
      if (std::abs(det) > 1e-12 * m0 * m0 * m0) k = det1 / det / scale / spring;
      break;
    }
    if (!std::isfinite(k)) continue;
    // Mean x of successive bins increases (bins are ordered and disjoint).
    p.x_mm[m] = xb;
    p.k[m] = k;
    ++m;
  }
  p.x_mm.conservativeResize(m);
  p.k.conservativeResize(m);
  return p;
}

}  // namespace

std::pair<int, int> EnsembleWindow(const CycleBins& normal_bins,
                                   int cycle,
                                   const EnsembleSlopeOptions& o) {
  const int half = o.cycles / 2;
  return {std::max(cycle - half, normal_bins.first_cycle()),
          std::min(cycle + half, normal_bins.last_cycle())};
}

std::array<PlateProfile, 2> EnsembleSlopeFromSums(
    const CycleBins& normal_bins,
    const std::array<CycleBins::Sums, 2>& sums,
    double spring,
    const EnsembleSlopeOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw FusionError("ensemble slope options: " + why);
  return {SlopeOfBinnedProfile(normal_bins, sums[0], o, spring),
          SlopeOfBinnedProfile(normal_bins, sums[1], o, spring)};
}

PlateProfile EnsembleSlopeOfSums(const CycleBins& normal_bins,
                                 const CycleBins::Sums& sums,
                                 double spring,
                                 const EnsembleSlopeOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw FusionError("ensemble slope options: " + why);
  return SlopeOfBinnedProfile(normal_bins, sums, o, spring);
}

std::array<PlateProfile, 2> EnsembleSlopeAt(const CycleBins& normal_bins,
                                            int cycle,
                                            double spring,
                                            const EnsembleSlopeOptions& o) {
  const auto [first, last] = EnsembleWindow(normal_bins, cycle, o);
  return EnsembleSlopeFromSums(normal_bins,
                               {normal_bins.Window(+1, first, last),
                                normal_bins.Window(-1, first, last)},
                               spring,
                               o);
}

const char* KEstimateName(KEstimate estimate) {
  return estimate == KEstimate::kEnsemble ? "ensemble" : "cycle";
}

bool ParseKEstimate(const std::string& text, KEstimate* estimate) {
  if (text == "ensemble") {
    *estimate = KEstimate::kEnsemble;
  } else if (text == "cycle" || text == "paper") {
    *estimate = KEstimate::kCycle;
  } else {
    return false;
  }
  return true;
}

bool RepeatabilityOptions::IsValid(std::string* why) const {
  if (!(bin_mm > 0 && bin_mm <= 1) || template_cycles < 2 ||
      template_cycles > 10000) {
    if (why)
      *why = "repeatability: bin in (0, 1] mm, template cycles in [2, 10000]";
    return false;
  }
  return true;
}

std::vector<std::array<RepeatSplit, 2>> SplitRepeatable(
    const CycleBins& bins,
    const std::vector<std::array<double, 2>>& total,
    int min_separation,
    const RepeatabilityOptions& options) {
  const int first = bins.first_cycle(), last = bins.last_cycle();
  const int n = last - first + 1;
  std::vector<std::array<RepeatSplit, 2>> out(
      static_cast<std::size_t>(std::max(n, 0)));
  const int sep = std::max(1, min_separation);
  const int t = options.template_cycles;
  for (int c = first; c <= last; ++c) {
    // The template: the t nearest cycles at distance >= sep, as balanced as
    // the ends of the test allow: [lo, hi] without (c - sep, c + sep).
    int left = t / 2, right = t - t / 2;
    const int room_left = std::max(0, c - sep - first + 1);
    const int room_right = std::max(0, last - (c + sep) + 1);
    if (left > room_left) {
      right += left - room_left;
      left = room_left;
    }
    if (right > room_right) {
      left = std::min(room_left, left + right - room_right);
      right = room_right;
    }
    const int lo = c - sep - left + 1, hi = c + sep + right - 1;
    for (int d = 0; d < 2; ++d) {
      const int dir = d == 0 ? +1 : -1;
      RepeatSplit& r = out[static_cast<std::size_t>(c - first)][d];
      r.total = total[static_cast<std::size_t>(c - first)][d];
      if (left + right == 0) {
        r.repeat = std::nan("");
        continue;
      }
      const CycleBins::Sums own = bins.Cycle(c, dir);
      const CycleBins::Sums tpl =
          bins.Window(dir, lo, hi, c - sep + 1, c + sep - 1);
      double cross = 0.0;
      int samples = 0;
      for (std::size_t b = 0; b < own.count.size(); ++b) {
        if (own.count[b] == 0 || tpl.count[b] == 0) continue;
        cross += own.value[b] * (tpl.value[b] / tpl.count[b]);
        samples += own.count[b];
      }
      r.repeat = cross;
      r.samples = samples;
    }
  }
  return out;
}

}  // namespace wearscar::fusion
