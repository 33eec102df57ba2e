#include "wearscar/fusion/ensemble.h"

#include <algorithm>
#include <cmath>
#include <future>
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
  const auto [lo, hi] = force::CyclesXRange(record.x_mm, cycles);
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

std::pair<const float*, const std::uint16_t*> CycleBins::Stored(
    int cycle, int direction) const {
  if (cycle < first_ || cycle > last_) return {nullptr, nullptr};
  const std::size_t o = Offset(cycle, direction);
  return {value_.data() + o, count_.data() + o};
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

namespace {

// The linear interpolation at x of `size` >= 2 points (xs increasing), its
// interval walked from *i (At's i: the last xs[i] <= x, at most size - 2);
// NaN outside, *i then left as it was.
inline double Walked(const double* xs,
                     const double* ks,
                     Eigen::Index size,
                     double x,
                     Eigen::Index* i) {
  if (!(x >= xs[0] && x <= xs[size - 1])) return std::nan("");
  Eigen::Index at = *i;
  while (at > 0 && x < xs[at]) --at;
  while (at < size - 2 && x >= xs[at + 1]) ++at;
  *i = at;
  const double t = (x - xs[at]) / (xs[at + 1] - xs[at]);
  return (1 - t) * ks[at] + t * ks[at + 1];
}

}  // namespace

double PlateProfile::AtNear(double x, Eigen::Index* hint) const {
  const Eigen::Index n = x_mm.size();
  if (n < 2) return std::nan("");
  Eigen::Index i = std::clamp<Eigen::Index>(*hint, 0, n - 2);
  const double v = Walked(x_mm.data(), k.data(), n, x, &i);
  *hint = i;  // (clamped only, where x is outside)
  return v;
}

void PlateProfile::AtEach(const double* x, Eigen::Index n, double* out) const {
  const Eigen::Index size = x_mm.size();
  if (size < 2) {
    std::fill(out, out + n, std::nan(""));
    return;
  }
  const double* const xs = x_mm.data();
  const double* const ks = k.data();
  Eigen::Index i = 0;
  for (Eigen::Index j = 0; j < n; ++j) out[j] = Walked(xs, ks, size, x[j], &i);
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

// The weighted moments of a local quadratic about a centre xb, u = (x -
// xb) / scale: m_p = sum w u^p (p = 0..4) and t_p = sum y u^p (p = 0..2),
// y = w times the bin's mean.
struct QuadraticMoments {
  double m0 = 0, m1 = 0, m2 = 0, m3 = 0, m4 = 0;
  double t0 = 0, t1 = 0, t2 = 0;

  void Add(double w, double y, double u) {
    const double w1 = w * u, w2 = w1 * u, w3 = w2 * u, w4 = w3 * u;
    const double y1 = y * u, y2 = y1 * u;
    m0 += w, m1 += w1, m2 += w2, m3 += w3, m4 += w4;
    t0 += y, t1 += y1, t2 += y2;
  }

  // The same sums about a centre `d` further along: u -> u + a, a = -d.
  void Shift(double d) {
    const double a = -d, a2 = a * a, a3 = a2 * a, a4 = a2 * a2;
    m4 += 4 * a * m3 + 6 * a2 * m2 + 4 * a3 * m1 + a4 * m0;
    m3 += 3 * a * m2 + 3 * a2 * m1 + a3 * m0;
    m2 += 2 * a * m1 + a2 * m0;
    m1 += a * m0;
    t2 += 2 * a * t1 + a2 * t0;
    t1 += a * t0;
  }

  // c1 times `factor` by Cramer's rule on the symmetric 3 x 3 normal
  // equations; NaN when they are singular.
  double Slope(double factor) const {
    const double det = m0 * (m2 * m4 - m3 * m3) - m1 * (m1 * m4 - m3 * m2) +
                       m2 * (m1 * m3 - m2 * m2);
    const double det1 = m0 * (t1 * m4 - m3 * t2) - t0 * (m1 * m4 - m3 * m2) +
                        m2 * (m1 * t2 - t1 * m2);
    if (!(std::abs(det) > 1e-12 * m0 * m0 * m0)) return std::nan("");
    return det1 * factor / det;
  }
};

// The weighted moments of a local cubic about a centre xb, u = (x - xb) /
// scale: m_p = sum w u^p (p = 0..6) and t_p = sum y u^p (p = 0..3), y = w
// times the bin's mean.
struct CubicMoments {
  double m0 = 0, m1 = 0, m2 = 0, m3 = 0, m4 = 0, m5 = 0, m6 = 0;
  double t0 = 0, t1 = 0, t2 = 0, t3 = 0;

  void Add(double w, double y, double u) {
    const double w1 = w * u, w2 = w1 * u, w3 = w2 * u, w4 = w3 * u, w5 = w4 * u,
                 w6 = w5 * u;
    const double y1 = y * u, y2 = y1 * u, y3 = y2 * u;
    m0 += w, m1 += w1, m2 += w2, m3 += w3, m4 += w4, m5 += w5, m6 += w6;
    t0 += y, t1 += y1, t2 += y2, t3 += y3;
  }

  // The same sums about a centre `d` further along: u -> u + a, a = -d,
  // sum w (u + a)^p by the binomial theorem.
  void Shift(double d) {
    const double a = -d, a2 = a * a, a3 = a2 * a, a4 = a2 * a2, a5 = a4 * a,
                 a6 = a3 * a3;
    m6 += 6 * a * m5 + 15 * a2 * m4 + 20 * a3 * m3 + 15 * a4 * m2 +
          6 * a5 * m1 + a6 * m0;
    m5 += 5 * a * m4 + 10 * a2 * m3 + 10 * a3 * m2 + 5 * a4 * m1 + a5 * m0;
    m4 += 4 * a * m3 + 6 * a2 * m2 + 4 * a3 * m1 + a4 * m0;
    m3 += 3 * a * m2 + 3 * a2 * m1 + a3 * m0;
    m2 += 2 * a * m1 + a2 * m0;
    m1 += a * m0;
    t3 += 3 * a * t2 + 3 * a2 * t1 + a3 * t0;
    t2 += 2 * a * t1 + a2 * t0;
    t1 += a * t0;
  }

  // c1 times `factor` by Cramer's rule on the 4 x 4 normal equations (by
  // the cofactors of column 1: the normal matrix's (m_{r + c})
  // determinant is sum_r m_{r + 1} C_r, that with column 1 replaced by t
  // sum_r t_r C_r; C_r from the 2 x 2 minors of columns 2 and 3); NaN
  // when they are singular.
  double Slope(double factor) const {
    const double c0[4] = {m0, m1, m2, m3};
    const double c2[4] = {m2, m3, m4, m5};
    const double c3[4] = {m3, m4, m5, m6};
    const auto minor = [&](int i, int j) {
      return c2[i] * c3[j] - c2[j] * c3[i];
    };
    const double d01 = minor(0, 1), d02 = minor(0, 2), d03 = minor(0, 3),
                 d12 = minor(1, 2), d13 = minor(1, 3), d23 = minor(2, 3);
    // Signed cofactors of column 1 (row r removed; (-1)^(r + 1)).
    const double k0 = -(c0[1] * d23 - c0[2] * d13 + c0[3] * d12);
    const double k1 = c0[0] * d23 - c0[2] * d03 + c0[3] * d02;
    const double k2 = -(c0[0] * d13 - c0[1] * d03 + c0[3] * d01);
    const double k3 = c0[0] * d12 - c0[1] * d02 + c0[2] * d01;
    const double det = m1 * k0 + m2 * k1 + m3 * k2 + m4 * k3;
    if (!(std::abs(det) > 1e-12 * m0 * m0 * m0 * m0)) return std::nan("");
    return (t0 * k0 + t1 * k1 + t2 * k2 + t3 * k3) * factor / det;
  }
};

// The moments of the bins [lo, hi] about xb.
template <typename Moments>
Moments MomentsOf(const double* mean_x,
                  const double* weight,
                  const double* value,
                  std::size_t lo,
                  std::size_t hi,
                  double xb,
                  double inverse_scale) {
  Moments c;
  for (std::size_t j = lo; j <= hi; ++j)
    c.Add(weight[j], value[j], (mean_x[j] - xb) * inverse_scale);
  return c;
}

// A window's moments slid along the bins are summed afresh after this many
// slides, so that the rounding the shifts carry along stays that of a few.
constexpr int kSlidesBeforeRefresh = 8;

// The slope k at each non-empty bin (`used`, their mean x, weight and
// value) by the local polynomial of `Moments` over the bins within
// +-half0 bins, widened to 2 and 4 half0 where fewer than `needed` are
// non-empty; into p, returning how many. The window of +-half0 bins
// slides along: its moments shifted to the next centre, less the bins
// that left, plus those that came (about a third of the arithmetic of
// summing every window afresh).
template <typename Moments>
Eigen::Index SlopesOf(const std::vector<int>& used,
                      const std::vector<double>& mean_x,
                      const std::vector<double>& weight,
                      const std::vector<double>& value,
                      double bin_mm,
                      int half0,
                      int needed,
                      double spring,
                      PlateProfile* p) {
  // Per width (+-half0, 2 half0, 4 half0 bins): 1 / its half width, and
  // what turns the slope in those units into k (one division per bin).
  double inverse_scales[3], factors[3];
  for (int level = 0; level < 3; ++level) {
    const double scale = (half0 << level) * bin_mm;
    inverse_scales[level] = 1.0 / scale;
    factors[level] = 1.0 / (scale * spring);
  }
  // The sliding window: its bins [slid_lo, slid_hi], their moments about
  // slid_centre.
  Moments slid;
  std::size_t slid_lo = 0, slid_hi = 0;
  double slid_centre = 0;
  int slides = kSlidesBeforeRefresh;  // none held yet
  Eigen::Index m = 0;
  for (std::size_t u = 0; u < used.size(); ++u) {
    const int b = used[u];
    const double xb = mean_x[u];
    double k = std::nan("");
    for (int level = 0, half = half0; level < 3; ++level, half *= 2) {
      // Neighbouring non-empty bins within +-half bins.
      std::size_t lo = u, hi = u;
      while (lo > 0 && used[lo - 1] >= b - half) --lo;
      while (hi + 1 < used.size() && used[hi + 1] <= b + half) ++hi;
      if (static_cast<int>(hi - lo + 1) < needed) continue;
      const double inverse_scale = inverse_scales[level];
      if (level > 0) {
        k = MomentsOf<Moments>(mean_x.data(),
                               weight.data(),
                               value.data(),
                               lo,
                               hi,
                               xb,
                               inverse_scale)
                .Slope(factors[level]);
        break;
      }
      if (slides >= kSlidesBeforeRefresh || lo > slid_hi) {
        slid = MomentsOf<Moments>(mean_x.data(),
                                  weight.data(),
                                  value.data(),
                                  lo,
                                  hi,
                                  xb,
                                  inverse_scale);
        slides = 0;
      } else {
        slid.Shift((xb - slid_centre) * inverse_scale);
        for (std::size_t j = slid_lo; j < lo; ++j)
          slid.Add(-weight[j], -value[j], (mean_x[j] - xb) * inverse_scale);
        for (std::size_t j = slid_hi + 1; j <= hi; ++j)
          slid.Add(weight[j], value[j], (mean_x[j] - xb) * inverse_scale);
        ++slides;
      }
      slid_lo = lo;
      slid_hi = hi;
      slid_centre = xb;
      k = slid.Slope(factors[level]);
      break;
    }
    if (!std::isfinite(k)) continue;
    // Mean x of successive bins increases (bins are ordered and disjoint).
    p->x_mm[m] = xb;
    p->k[m] = k;
    ++m;
  }
  return m;
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
  // Mean x, weight and value of each non-empty bin, once (appended: a
  // sized vector is zeroed first, thousands of times a test).
  std::vector<double> mean_x, weight, value;
  mean_x.reserve(used.size());
  weight.reserve(used.size());
  value.reserve(used.size());
  for (const int b : used) {
    mean_x.push_back(bins.MeanX(s, b));
    weight.push_back(s.count[b]);
    value.push_back(s.value[b]);
  }
  PlateProfile p;
  p.x_mm.resize(static_cast<Eigen::Index>(used.size()));
  p.k.resize(static_cast<Eigen::Index>(used.size()));
  const int half0 =
      std::max(1, static_cast<int>(std::lround(0.5 * o.span_mm / bin_mm)));
  const int needed = o.polynomial_order == 2
                         ? o.min_bins
                         : std::max(o.min_bins, o.polynomial_order + 2);
  const Eigen::Index m =
      o.polynomial_order == 2
          ? SlopesOf<QuadraticMoments>(
                used, mean_x, weight, value, bin_mm, half0, needed, spring, &p)
          : SlopesOf<CubicMoments>(
                used, mean_x, weight, value, bin_mm, half0, needed, spring, &p);
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

namespace {

// A noise split's template is summed afresh after this many slides.
constexpr int kTemplateSlides = 8;

// A template's cycles: [lo, hi] without the band (c - sep, c + sep).
struct TemplateCycles {
  int lo = 0, hi = -1, band_lo = 0, band_hi = -1;
  bool Holds(int j) const {
    return j >= lo && j <= hi && (j < band_lo || j > band_hi);
  }
};

// The template of cycle c: the t nearest cycles at distance >= sep, as
// balanced as the ends of the test allow; empty (hi < lo) when none.
TemplateCycles TemplateOf(int c, int first, int last, int sep, int t) {
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
  TemplateCycles tc;
  if (left + right == 0) return tc;
  tc.lo = std::max(first, c - sep - left + 1);
  tc.hi = std::min(last, c + sep + right - 1);
  tc.band_lo = c - sep + 1;
  tc.band_hi = c + sep - 1;
  return tc;
}

}  // namespace

// One pass of the templates: each direction's template against its
// values, and (with `parity`) against its values less the other
// direction's at the same x over the bins where both slid in the cycle,
// each bin weighted by the fewer samples of the two.
std::vector<std::array<RepeatSplit, 2>> SplitRepeatable(
    const CycleBins& bins,
    const std::vector<std::array<double, 2>>& total,
    int min_separation,
    const RepeatabilityOptions& options,
    bool two_threads,
    std::vector<std::array<RepeatSplit, 2>>* parity) {
  const int first = bins.first_cycle(), last = bins.last_cycle();
  const auto n = static_cast<std::size_t>(std::max(last - first + 1, 0));
  std::vector<std::array<RepeatSplit, 2>> same(n);
  if (parity) parity->assign(n, {});
  const int sep = std::max(1, min_separation);
  const auto split = [&](int d) {
    const int dir = d == 0 ? +1 : -1;
    // The template's sums slide along the cycles: the cycles that left it
    // taken out, those that came added (a few a cycle, not all t), summed
    // afresh now and then so that the rounding they carry stays that of a
    // few slides however long the test.
    CycleBins::Sums tpl = bins.Window(dir, 1, 0);
    TemplateCycles held;
    int slides = kTemplateSlides;
    for (int c = first; c <= last; ++c) {
      const auto i = static_cast<std::size_t>(c - first);
      RepeatSplit& r = same[i][d];
      RepeatSplit* p = parity ? &(*parity)[i][d] : nullptr;
      r.total = total[i][d];
      const TemplateCycles now =
          TemplateOf(c, first, last, sep, options.template_cycles);
      if (now.hi < now.lo) {
        r.repeat = std::nan("");
        if (p) p->repeat = std::nan("");
        continue;
      }
      if (slides >= kTemplateSlides) {
        tpl = bins.Window(dir, now.lo, now.hi, now.band_lo, now.band_hi);
        slides = 0;
      } else {
        for (int j = std::min(held.lo, now.lo); j <= std::max(held.hi, now.hi);
             ++j) {
          if (held.Holds(j) != now.Holds(j))
            bins.Accumulate(&tpl, j, dir, now.Holds(j) ? +1 : -1);
        }
        ++slides;
      }
      held = now;
      const auto [value, count] = bins.Stored(c, dir);
      const auto [other, other_count] = bins.Stored(c, -dir);
      double product = 0.0, odd = 0.0;
      int samples = 0, odd_samples = 0;
      for (std::size_t b = 0; b < tpl.count.size(); ++b) {
        if (count[b] == 0 || tpl.count[b] == 0) continue;
        const double mean = tpl.value[b] / tpl.count[b];
        product += static_cast<double>(value[b]) * mean;
        samples += count[b];
        if (!p || other_count[b] == 0) continue;
        const int w = std::min<int>(count[b], other_count[b]);
        odd += w *
               (static_cast<double>(value[b]) / count[b] -
                static_cast<double>(other[b]) / other_count[b]) *
               mean;
        odd_samples += w;
      }
      r.repeat = product, r.samples = samples;
      if (p) p->repeat = odd, p->samples = odd_samples;
    }
  };
  // (The directions share nothing but the outputs' disjoint halves.)
  std::future<void> reverse = std::async(
      two_threads ? std::launch::async : std::launch::deferred, split, 1);
  split(0);
  reverse.get();
  return same;
}

}  // namespace wearscar::fusion
