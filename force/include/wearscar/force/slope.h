#pragma once

#include <Eigen/Core>
#include <string>

namespace wearscar::force {

enum class DerivativeMethod {
  // The paper: moving average of the signal, then Eq. 5's three-point
  // difference (f[i+1] - f[i-1]) / (x[i+1] - x[i-1]).
  kMovingAverageCentral,
  // Local least-squares polynomial in x (Savitzky-Golay on the actual,
  // non-uniform x samples); smoother, less biased on peaks.
  kSavitzkyGolay,
};

const char* DerivativeMethodName(DerivativeMethod method);
// Parses "central" / "moving-average" / "savgol" / "savitzky-golay".
bool ParseDerivativeMethod(const std::string& text, DerivativeMethod* method);

struct SlopeOptions {
  DerivativeMethod method = DerivativeMethod::kMovingAverageCentral;
  int window = 10;           // samples: moving average, or SG window (odd)
  int polynomial_order = 2;  // Savitzky-Golay only
  double spring_stiffness_n_per_mm = 10.19;  // S, paper Table 1
  // Near a reversal x barely moves and noise dominates a fixed stencil: the
  // difference (or SG window) widens until it spans at least this x
  // distance, mm. 0 = the paper's fixed three-point stencil.
  double min_span_mm = 0.01;
  int max_half_width = 200;  // samples; wider than this gives NaN
  // Savitzky-Golay only: where the signal ends, shift the window inward
  // (the local polynomial's slope is still taken at the sample) instead of
  // giving NaN. For a signal cut to a range whose outside must not enter.
  bool shift_window_at_ends = false;

  bool IsValid(std::string* why) const;
};

// Centred moving average over `window` samples (shrinking at the ends),
// NaN-aware.
Eigen::VectorXd MovingAverage(const Eigen::Ref<const Eigen::VectorXd>& v,
                              int window);

// d(signal)/dx over samples [begin, end) of a monotonic stretch of x. At the
// ends of `signal`, where the stencil does not fit, the result is NaN (or,
// with shift_window_at_ends, a Savitzky-Golay window shifted inward).
Eigen::VectorXd DerivativeAlongX(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm,
    const Eigen::Ref<const Eigen::VectorXd>& signal,
    Eigen::Index begin,
    Eigen::Index end,
    const SlopeOptions& options);

// Slope of the sliding path seen by the force channel, k = (1/S) dP/dx
// (paper Eqs. 4-5), over [begin, end).
Eigen::VectorXd SlopeFromNormalForce(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm,
    const Eigen::Ref<const Eigen::VectorXd>& normal_n,
    Eigen::Index begin,
    Eigen::Index end,
    const SlopeOptions& options);

}  // namespace wearscar::force
