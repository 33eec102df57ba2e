#include "wearscar/force/slope.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace wearscar::force {

const char* DerivativeMethodName(DerivativeMethod method) {
  switch (method) {
    case DerivativeMethod::kMovingAverageCentral:
      return "moving-average + central difference (paper Eq. 5)";
    case DerivativeMethod::kSavitzkyGolay:
      return "Savitzky-Golay (local polynomial in x)";
  }
  return "?";
}

bool ParseDerivativeMethod(const std::string& text, DerivativeMethod* method) {
  if (text == "central" || text == "moving-average" || text == "paper") {
    *method = DerivativeMethod::kMovingAverageCentral;
    return true;
  }
  if (text == "savgol" || text == "savitzky-golay" || text == "sg") {
    *method = DerivativeMethod::kSavitzkyGolay;
    return true;
  }
  return false;
}

bool DerivativeOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (window < 0) return fail("window must be >= 0 (0 = from window_ms)");
  if (half_width < 0)
    return fail("half_width must be >= 0 (0 = from half_span_ms)");
  if (window == 0 && !(window_ms > 0 && window_ms <= 1e4))
    return fail("window_ms must be in (0, 10000]");
  if (half_width == 0 && !(half_span_ms > 0 && half_span_ms <= 1e4))
    return fail("half_span_ms must be in (0, 10000]");
  if (window > 100000 || half_width > 100000)
    return fail("window and half_width must be at most 100000 samples");
  if (method == DerivativeMethod::kSavitzkyGolay) {
    if (window != 0 && window < 3)
      return fail("Savitzky-Golay window must be >= 3");
    if (polynomial_order < 1 || (window != 0 && polynomial_order >= window)) {
      return fail("polynomial_order must be in [1, window)");
    }
  }
  if (!(min_span_mm >= 0)) return fail("min_span_mm must be >= 0");
  if (max_half_width < 1) return fail("max_half_width must be >= 1");
  return true;
}

bool SlopeOptions::IsValid(std::string* why) const {
  if (!DerivativeOptions::IsValid(why)) return false;
  if (!(spring_n_per_mm > 0)) {
    if (why) *why = "spring_n_per_mm must be > 0";
    return false;
  }
  return true;
}

SlopeOptions SlopeOptions::ForSamplingRate(double rate_hz) const {
  SlopeOptions o = *this;
  static_cast<DerivativeOptions&>(o) =
      DerivativeOptions::ForSamplingRate(rate_hz);
  return o;
}

DerivativeOptions DerivativeOptions::ForSamplingRate(double rate_hz) const {
  DerivativeOptions o = *this;
  const bool rate_known = rate_hz > 0 && std::isfinite(rate_hz);
  auto samples = [&](double ms, int paper) {
    if (!rate_known) return paper;
    const double n = std::round(ms * 1e-3 * rate_hz);
    return static_cast<int>(std::clamp(n, 1.0, 100000.0));
  };
  if (o.window == 0) o.window = samples(window_ms, 10);
  if (o.half_width == 0) o.half_width = samples(half_span_ms, 1);
  if (o.method == DerivativeMethod::kSavitzkyGolay) {
    o.window = std::max(o.window | 1, std::max(3, polynomial_order + 1) | 1);
  }
  return o;
}

std::string DerivativeOptions::Describe() const {
  if (method == DerivativeMethod::kSavitzkyGolay) {
    return fmt::format(
        "Savitzky-Golay, order {}, {} samples", polynomial_order, window);
  }
  return fmt::format(
      "moving average {} samples, central difference +-{} sample{}{}",
      window,
      half_width,
      half_width == 1 ? "" : "s",
      min_span_mm > 0 ? fmt::format(" (widened to span {} mm)", min_span_mm)
                      : std::string());
}

Eigen::VectorXd MovingAverage(const Eigen::Ref<const Eigen::VectorXd>& v,
                              int window) {
  const Eigen::Index n = v.size();
  Eigen::VectorXd out(n);
  if (window <= 1) {
    out = v;
    return out;
  }
  // Window [i - window/2, i + (window-1)/2]; for window 10: 5 before, 4 after.
  const Eigen::Index before = window / 2, after = (window - 1) / 2;
  // Running sums over finite values.
  double sum = 0;
  Eigen::Index count = 0;
  Eigen::Index lo = 0, hi = -1;  // current window [lo, hi]
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index want_lo = std::max<Eigen::Index>(0, i - before);
    const Eigen::Index want_hi = std::min<Eigen::Index>(n - 1, i + after);
    while (hi < want_hi) {
      ++hi;
      if (std::isfinite(v[hi])) {
        sum += v[hi];
        ++count;
      }
    }
    while (lo < want_lo) {
      if (std::isfinite(v[lo])) {
        sum -= v[lo];
        --count;
      }
      ++lo;
    }
    out[i] = count > 0 ? sum / static_cast<double>(count) : std::nan("");
  }
  return out;
}

namespace {

// The paper's derivative: a moving average of the signal, then the central
// difference over +-half_width samples, widened (up to max_half_width)
// until it spans min_span_mm of x when that is set.
void CentralDifference(const Eigen::Ref<const Eigen::VectorXd>& x_mm,
                       const Eigen::Ref<const Eigen::VectorXd>& signal,
                       Eigen::Index begin,
                       Eigen::Index end,
                       const DerivativeOptions& options,
                       Eigen::VectorXd* d) {
  const Eigen::Index h0 = std::max(1, options.half_width);
  const int window = options.window > 0 ? options.window : 10;
  // Smooth a padded stretch so the ends see the same filter as the middle.
  const bool widen = options.min_span_mm > 0;
  const Eigen::Index wide = std::max<Eigen::Index>(options.max_half_width, h0);
  const Eigen::Index pad = widen ? wide : window + h0;
  const Eigen::Index base = std::max<Eigen::Index>(0, begin - pad - 1);
  const Eigen::Index top = std::min<Eigen::Index>(signal.size(), end + pad + 1);
  const Eigen::VectorXd sm =
      MovingAverage(signal.segment(base, top - base), window);
  for (Eigen::Index i = begin; i < end; ++i) {
    Eigen::Index m = h0;
    if (widen) {
      while (i - m >= base && i + m < top &&
             !(std::abs(x_mm[i + m] - x_mm[i - m]) >= options.min_span_mm) &&
             m < wide) {
        ++m;
      }
    }
    if (i - m < base || i + m >= base + sm.size()) continue;
    const double dx = x_mm[i + m] - x_mm[i - m];
    if (dx == 0 || !std::isfinite(dx) ||
        (widen && std::abs(dx) < options.min_span_mm)) {
      continue;
    }
    (*d)[i - begin] = (sm[i + m - base] - sm[i - m - base]) / dx;
  }
}

// Savitzky-Golay on the actual x: a polynomial of the given order in
// (x - x_i) fitted over the window, its linear coefficient.
void SavitzkyGolay(const Eigen::Ref<const Eigen::VectorXd>& x_mm,
                   const Eigen::Ref<const Eigen::VectorXd>& signal,
                   Eigen::Index begin,
                   Eigen::Index end,
                   const DerivativeOptions& options,
                   Eigen::VectorXd* d) {
  const int window = options.window > 0 ? options.window : 10;
  const Eigen::Index h = std::max(window, options.polynomial_order + 1) / 2;
  const int p = options.polynomial_order;
  Eigen::MatrixXd a(2 * h + 1, p + 1);
  Eigen::VectorXd b(2 * h + 1);
  if (signal.size() < 2 * h + 1) return;
  for (Eigen::Index i = begin; i < end; ++i) {
    // The window is centred on i; where the signal ends it is NaN, or shifted
    // inward on request (the polynomial's slope is still taken at x_i).
    if (!options.shift_window_at_ends && (i - h < 0 || i + h >= signal.size()))
      continue;
    const Eigen::Index lo =
        std::clamp<Eigen::Index>(i - h, 0, signal.size() - 1 - 2 * h);
    const Eigen::Index hi = lo + 2 * h;
    // Scale x for conditioning; too little x spread means noise only.
    const double scale = std::abs(x_mm[hi] - x_mm[lo]);
    if (!(scale > 0) || scale < options.min_span_mm) continue;
    Eigen::Index rows = 0;
    for (Eigen::Index j = lo; j <= hi; ++j) {
      if (!std::isfinite(signal[j]) || !std::isfinite(x_mm[j])) continue;
      const double u = (x_mm[j] - x_mm[i]) / scale;
      double pw = 1.0;
      for (int c = 0; c <= p; ++c) {
        a(rows, c) = pw;
        pw *= u;
      }
      b[rows] = signal[j];
      ++rows;
    }
    // Too many gaps in the window: the fit would extrapolate.
    if (rows <= p || rows < h + 1) continue;
    const Eigen::VectorXd coef =
        a.topRows(rows).colPivHouseholderQr().solve(b.head(rows));
    (*d)[i - begin] = coef[1] / scale;
  }
}

}  // namespace

Eigen::VectorXd DerivativeAlongX(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm,
    const Eigen::Ref<const Eigen::VectorXd>& signal,
    Eigen::Index begin,
    Eigen::Index end,
    const DerivativeOptions& options) {
  const Eigen::Index n = end - begin;
  Eigen::VectorXd d =
      Eigen::VectorXd::Constant(std::max<Eigen::Index>(n, 0), std::nan(""));
  if (n <= 0) return d;
  if (options.method == DerivativeMethod::kMovingAverageCentral) {
    CentralDifference(x_mm, signal, begin, end, options, &d);
  } else {
    SavitzkyGolay(x_mm, signal, begin, end, options, &d);
  }
  return d;
}

Eigen::VectorXd SlopeFromNormalForce(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm,
    const Eigen::Ref<const Eigen::VectorXd>& normal_n,
    Eigen::Index begin,
    Eigen::Index end,
    const SlopeOptions& options) {
  // k = df/dx with f = P / S (paper Eqs. 4-5).
  return DerivativeAlongX(x_mm, normal_n, begin, end, options) /
         options.spring_n_per_mm;
}

}  // namespace wearscar::force
