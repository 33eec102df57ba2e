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

// How a derivative along x is taken, for any signal sampled along x (P
// along the stroke, a scan's centreline).
struct DerivativeOptions {
  DerivativeMethod method = DerivativeMethod::kMovingAverageCentral;
  // Smoothing span in samples: moving average, or SG window (odd). 0 = from
  // window_ms and the record's sampling rate (ForSamplingRate).
  int window = 0;
  // Smoothing span in time, ms, used when window is 0: 5 ms is the paper's
  // 10 samples at 2 kHz. In time, not samples, so that a record sampled at
  // another rate is smoothed over the same stretch of the stroke.
  double window_ms = 5.0;
  // Central difference f[i+h] - f[i-h] over x[i+h] - x[i-h]: h in samples;
  // 0 = from half_span_ms (0.5 ms: the paper's Eq. 5, h = 1, at 2 kHz).
  int half_width = 0;
  double half_span_ms = 0.5;
  int polynomial_order = 2;  // Savitzky-Golay only
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
  // The spans in samples for a record sampled at rate_hz (> 0): window and
  // half_width kept when given, else from window_ms and half_span_ms, at
  // least 1 sample (3, odd, for Savitzky-Golay).
  DerivativeOptions ForSamplingRate(double rate_hz) const;
  // "moving average 10 samples (5.0 ms), central difference +-1 sample".
  std::string Describe() const;
};

// The slope of the sliding path seen by the force channel: the derivative
// of P along x, divided by the loading spring's stiffness S.
struct SlopeOptions : DerivativeOptions {
  double spring_n_per_mm = 10.19;  // S, paper Table 1

  bool IsValid(std::string* why) const;
  SlopeOptions ForSamplingRate(double rate_hz) const;
};

// Centred moving average over `window` samples (shrinking at the ends),
// NaN-aware.
Eigen::VectorXd MovingAverage(const Eigen::Ref<const Eigen::VectorXd>& v,
                              int window);

// d(signal)/dx over samples [begin, end) of a monotonic stretch of x, with
// the spans in samples (options.window and half_width >= 1: see
// ForSamplingRate; 0 is taken as the paper's 10 and 1). At the
// ends of `signal`, where the stencil does not fit, the result is NaN (or,
// with shift_window_at_ends, a Savitzky-Golay window shifted inward).
Eigen::VectorXd DerivativeAlongX(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm,
    const Eigen::Ref<const Eigen::VectorXd>& signal,
    Eigen::Index begin,
    Eigen::Index end,
    const DerivativeOptions& options);

// Slope of the sliding path seen by the force channel, k = (1/S) dP/dx
// (paper Eqs. 4-5), over [begin, end).
Eigen::VectorXd SlopeFromNormalForce(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm,
    const Eigen::Ref<const Eigen::VectorXd>& normal_n,
    Eigen::Index begin,
    Eigen::Index end,
    const SlopeOptions& options);

}  // namespace wearscar::force
