#pragma once

#include <limits>
#include <string>
#include <vector>

#include "wearscar/force/cof.h"
#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/fusion/fit_mu.h"

namespace wearscar::fusion {

struct AnalysisOptions {
  force::SegmentOptions segment;
  force::GrossSlipOptions slip;
  FrictionFitOptions friction;
  // Cycles treated as running-in: excluded from the after-running-in
  // statistics and the verdict. -1 = detect them (DetectRunningIn).
  int running_in_cycles = -1;
  // Detection: the per-cycle friction has settled when it stays within this
  // much (or 3 robust sd of its scatter, if larger) of the steady trend.
  double running_in_tolerance = 0.005;
  // Fit mu-hat with the force-side slope (false: only with the scan's).
  bool fit_force_slope = true;

  bool IsValid(std::string* why) const;
};

// Mean and standard deviation over the cycles after running-in, and the
// mean's 95% interval where one was estimated (NaN otherwise) with the
// effective number of independent cycles behind it.
struct Statistic {
  double mean = 0.0;
  double sd = 0.0;
  int count = 0;
  double low = std::numeric_limits<double>::quiet_NaN();
  double high = std::numeric_limits<double>::quiet_NaN();
  double effective_count = std::numeric_limits<double>::quiet_NaN();
};

// A mean over cycles with its 95% interval, from the means of consecutive
// batches of cycles (successive cycles are correlated: the track, the
// template of the noise split and the ensemble slope span several).
struct Interval {
  double mean = std::numeric_limits<double>::quiet_NaN();
  double low = std::numeric_limits<double>::quiet_NaN();
  double high = std::numeric_limits<double>::quiet_NaN();
  int count = 0;    // finite values
  int batches = 0;  // 0: too few values for an interval (low = high = mean)
};

// Mean of the finite values[first..last] and its interval from `batches`
// consecutive batches (Student's t on the batch means; fewer than 2 values
// per batch: fewer batches; fewer than 3 batches: no interval).
Interval MeanInterval(const std::vector<double>& values,
                      int first,
                      int last,
                      int batches = 10);

// The mean of per-cycle estimates values[first..last] whose errors have
// the standard errors given (MuFit::standard_error) and are correlated over
// `correlated_cycles` successive cycles: the force side's ensemble slope
// shares P samples between cycles fewer than that apart (triangular
// correlation 1 - |c - c'| / correlated_cycles); a slope common to all
// cycles (the scan's) makes them all one (pass the number of cycles). The
// 95% interval is mean +- 1.96 sqrt(sum_cc' rho se_c se_c') / n;
// effective_count = n^2 mean(se^2) / sum_cc' rho se_c se_c'. Cycles whose
// value is not finite are left out; when a finite value has no finite
// error there is no interval (low, high NaN).
Statistic SummariseWithErrors(const std::vector<double>& values,
                              const std::vector<double>& standard_errors,
                              int first,
                              int last,
                              int correlated_cycles);

// The mean of a per-cycle series values[first..last] whose scatter about
// its straight-line trend is the uncertainty (the classic COFs: no
// per-cycle error is known): the trend's residuals' lag-1 autocorrelation
// r gives the effective number of cycles n (1 - r) / (1 + r) (AR(1), at
// most n, at least 2), and the interval is mean +- t_0.975 sd_residual /
// sqrt(n_eff). The slow drift itself is not counted as uncertainty.
Statistic SummariseSeries(const std::vector<double>& values,
                          int first,
                          int last);

// J over a range of cycles split into the part measurement noise explains
// (its floor) and the excess it does not, per direction in quadrature:
// J_dir^2 = floor_dir^2 + excess_dir^2 (MuFit::misfit_sq, repeat_sq).
struct CostSplit {
  double cost = std::numeric_limits<double>::quiet_NaN();  // mean J (Eq. 6)
  double floor = std::numeric_limits<double>::quiet_NaN();
  double excess = std::numeric_limits<double>::quiet_NaN();
  // 95% interval of the excess (batch means of the per-direction repeat
  // parts); equal to excess when there are too few cycles for it.
  double excess_low = std::numeric_limits<double>::quiet_NaN();
  double excess_high = std::numeric_limits<double>::quiet_NaN();
  // The excess's part that changes sign with the motion, as friction does
  // (MuFit::repeat_odd_sq, both directions), with its 95% interval: what
  // can bias mu-hat. NaN where not split.
  double odd_excess = std::numeric_limits<double>::quiet_NaN();
  double odd_excess_low = std::numeric_limits<double>::quiet_NaN();
  double odd_excess_high = std::numeric_limits<double>::quiet_NaN();
  int cycles = 0;
};
CostSplit SplitCost(const std::vector<MuFit>& fits, int first, int last);

// Everything the force side of one test yields.
// Where running-in ends, and how that was decided.
struct RunningIn {
  int cycles = 0;             // cycles [0, cycles) are running-in
  bool detected = false;      // false: given by the user (or too few cycles)
  double steady_slope = 0.0;  // trend after running-in, per cycle
  double tolerance = 0.0;     // band actually used
  std::string rule;           // one line for reports
};

// Running-in from the per-cycle friction coefficient (mu_mean): a straight
// line is fitted to the second half of the test (the steady trend, slow drift
// allowed); running-in ends at the first cycle from which the 3-cycle
// running median stays within the tolerance band around that line
// extrapolated backwards. The band is max(tolerance, 3 x 1.4826 MAD of the
// residuals on the second half). Never more than half the cycles; fewer than
// 6 cycles give 0.
RunningIn DetectRunningIn(const std::vector<double>& friction_per_cycle,
                          double tolerance);

// The classic COFs per cycle (force::ComputeClassicCof): the result of the
// analysis unit "classic_cofs", from whose mean method the running-in is
// detected (FindRunningIn) and from which the comparison takes the classic
// methods' difference to mu-hat.
struct ClassicCofs {
  std::vector<force::CycleCof> cycles;
};

// The force side's record segmented: its cycles with their gross slip and
// the running-in.
struct ForceAnalysis {
  force::CycleSet cycles;
  RunningIn running_in;
  int slip_fallbacks = 0;  // half cycles where the central fallback was used
};

// mu-hat per cycle with one slope source of the force side, and its
// figures after running-in: the results of the analysis units
// "mu_fit_spring" (k from P/S, SpringFits) and "mu_fit_depth" (k from the
// depth channel, DepthFits), TestResult::ForceFits the one the profile's
// decision took.
struct SlopeFits {
  std::vector<MuFit> cycles;  // one per cycle ("not fitted" where not)
  Statistic mu_hat, cost;     // after running-in
  // Successive cycles whose mu-hat errors are correlated through the
  // force-side slope (ForceSlopes::SharedCycles).
  int correlated_cycles = 1;
  // How k was estimated (FrictionFits::slope) and the root mean square of
  // its repeatable part and of its noise.
  std::string slope_estimate;
  double k_signal_rms = MuFit::kNotComputed;
  double k_noise_rms = MuFit::kNotComputed;
  // The ensemble k's noise from its odd and even halves
  // (FrictionFits::k_ensemble_noise_rms), and what
  // FrictionFitOptions::correct_k_noise_bias added to mu-hat, mean over the
  // converged cycles.
  double k_ensemble_noise_rms = MuFit::kNotComputed;
  double k_noise_correction = 0.0;
};
struct SpringFits : SlopeFits {};
struct DepthFits : SlopeFits {};

// The force side's stages that need no slope nor the classic COFs: cycles
// and gross slip; the running-in is not set. Throws force::ForceError for
// records that cannot be segmented. Requires record.IsConsistent().
ForceAnalysis SegmentCycles(const force::ForceRecord& record,
                            const AnalysisOptions& options);

// The running-in of a segmented record: given (options.running_in_cycles;
// FusionError when longer than half the test) or detected on the classic
// COFs' mean method (DetectRunningIn).
void FindRunningIn(const force::ForceRecord& record,
                   const AnalysisOptions& options,
                   const ClassicCofs& cofs,
                   ForceAnalysis* analysis);

// SegmentCycles, the classic COFs and FindRunningIn, for a caller that runs
// no analysis units (the pipeline runs the COFs' unit between the two).
ForceAnalysis SegmentForce(const force::ForceRecord& record,
                           const AnalysisOptions& options);

// mu-hat per cycle with the force side's slope (options.friction: P/S or
// the depth channel) on a segmented record, and its statistics after
// running-in ("not fitted" where options.fit_force_slope is off).
SlopeFits FitForceSide(const force::ForceRecord& record,
                       const AnalysisOptions& options,
                       const ForceAnalysis& segmented);

// A record segmented and fitted with the force side's slope.
struct ForceFitted : ForceAnalysis {
  SlopeFits fits;
};

// SegmentForce, then FitForceSide, for a caller that runs no analysis
// units: segments, finds gross slip and the running-in, and fits mu-hat per
// cycle with the force-side slope. Throws force::ForceError for records
// that cannot be segmented. Requires record.IsConsistent().
ForceFitted AnalyzeForce(const force::ForceRecord& record,
                         const AnalysisOptions& options);

// Mean and sd of values[i] over i >= first where finite.
Statistic Summarise(const std::vector<double>& values, int first);

}  // namespace wearscar::fusion
