#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/force/slope.h"
#include "wearscar/fusion/ensemble.h"
#include "wearscar/fusion/error.h"

namespace wearscar::fusion {

// Gross-slip samples of one direction: measured Q, measured P and the slope
// k of the sliding path at each sample.
struct SlipSamples {
  Eigen::VectorXd q_n;
  Eigen::VectorXd p_n;
  Eigen::VectorXd k;
  Eigen::VectorXd x_mm;
  int direction = +1;
};

struct CycleSamples {
  SlipSamples forward;
  SlipSamples reverse;
};

// Paper Eq. 6:
//   J(mu) = |Qm_f - Qw_f| / |Qm_f| + |Qm_r - Qw_r| / |Qm_r|
// with 2-norms over the gross-slip samples and Q_w the wear-scar prediction.
// Infinite where 1 - s mu k <= 0 (the hypothesis breaks down).
double WearScarCost(const CycleSamples& samples, double mu);

struct FitMuOptions {
  double mu_min = 0.0;  // search interval
  double mu_max = 1.0;
  int grid_points = 11;     // bracketing grid over the interval (step 0.1)
  double tolerance = 1e-7;  // Brent, absolute in mu
  int max_iterations = 100;
  // The standard error of mu-hat: the residuals' scores summed in blocks
  // this long along each direction's stroke, mm (MuFit::standard_error);
  // shorter than the span of the force-side slope's derivative (0.1 mm),
  // over which the misfit is correlated, since the neighbouring blocks'
  // covariance is counted. Calibrated on the simulator at its noise 1 and
  // 2: per-cycle intervals cover the truth in 98-99% of the cycles, the
  // per-test mean's in 90-97% of the tests (docs/method.md, "Error bars").
  double error_block_mm = 0.07;

  bool IsValid(std::string* why) const;
};

// Result of one fit, pessimistic by default (Ceres Solver::Summary style).
struct MuFit {
  double mu_hat = 0.0;
  double cost = 0.0;   // J at mu_hat
  int samples = 0;     // gross-slip samples used (both directions)
  int iterations = 0;  // Newton steps (or Brent's after the grid, its fallback)
  bool converged = false;
  bool at_bound = false;  // the minimum sits on mu_min or mu_max
  std::string message = "not run";
  // J split into what measurement noise explains and what repeats at the
  // same x in other cycles (SplitRepeatable on the misfit Qm - Qw), per
  // direction ([0] forward, [1] reverse), relative to |Qm|^2: J_dir^2 =
  // misfit_sq = noise part + repeat_sq. NaN when not computed.
  std::array<double, 2> misfit_sq{kNotComputed, kNotComputed};
  std::array<double, 2> repeat_sq{kNotComputed, kNotComputed};
  // The J noise alone gives (sum over directions of sqrt(misfit_sq -
  // repeat_sq)) and the J it does not explain (of sqrt(max(0, repeat_sq))):
  // cost^2 ~ floor^2 + excess^2 per direction.
  double cost_floor = kNotComputed;
  double cost_excess = kNotComputed;
  // Of repeat_sq (per direction, the two averaged), the part that changes
  // sign with the motion, as friction does (SplitRepeatable's parity): the part
  // that can bias mu-hat; the rest acts as a slope does and cancels
  // between the directions.
  double repeat_odd_sq = kNotComputed;
  // Standard error of mu-hat from the cycle's own residuals (sandwich: J's
  // first-order condition linearised about mu-hat, the scores r dQw/dmu
  // summed in blocks along the stroke with the neighbouring blocks'
  // covariance, since the misfit is correlated along x). NaN when the fit
  // did not converge.
  double standard_error = kNotComputed;

  static constexpr double kNotComputed =
      std::numeric_limits<double>::quiet_NaN();

  std::string BriefReport() const;
};

// mu-hat = argmin J: grid bracketing, then Brent's method in the bracket.
// Requires q, p and k (and x when given) of one length per direction.
MuFit FitMu(const CycleSamples& samples, const FitMuOptions& options = {});

// J on a grid of mu (paper Fig. 11).
Eigen::VectorXd CostCurve(const CycleSamples& samples,
                          const Eigen::VectorXd& mu_grid);

enum class SlopeSource { kForce, kScan };

struct FrictionFitOptions {
  // Derivative and S for the force-side slope of one cycle (kCycle).
  force::SlopeOptions slope;
  // k from each cycle's own P (the paper) or from the ensemble of its
  // neighbouring cycles (a fraction of the noise).
  KEstimate k_estimate = KEstimate::kEnsemble;
  EnsembleSlopeOptions ensemble;
  FitMuOptions fit;
  // The noise split of J (MuFit::cost_floor, cost_excess).
  RepeatabilityOptions repeatability;
  // Errors in variables: noise e in the ensemble's k biases mu-hat at
  // second order, by about -3 mu var(e) (the model is curved in k). With
  // this on, each cycle's mu-hat has that bias removed, var(e) being the
  // k noise the split estimates (FrictionFits::k_ensemble_noise_rms). Ensemble
  // only: the paper's k per cycle is left as the paper has it.
  bool correct_k_noise_bias = true;
  // Threads FitFriction fits the cycles on: 2 fit the second half of the
  // cycles beside the first, and split k's noise beside the misfit's
  // (`wearscar fuse`); the fits are the same with any number.
  int threads = 1;
  // When not empty, only the cycles c with fit_cycle[c] set are fitted
  // (the others' MuFit "not run"): a live window fits its new cycles.
  std::vector<char> fit_cycle;
  // A record of few cycles narrows the ensemble to a third of them (odd),
  // leaving the noise split a template of cycles whose k shares no sample
  // with the cycle judged. false keeps the ensemble's width: a live
  // window, whose noise split takes its template from earlier windows.
  bool narrow_ensemble_to_record = true;
  // The ensemble k's noise variance per sample when it is known (a live
  // window reuses an earlier window's); NaN: estimated from the cycles
  // fitted (ForceSlopes::EnsembleNoiseVariance).
  double k_noise_variance = std::numeric_limits<double>::quiet_NaN();
  // FrictionFits::samples keeps each fitted cycle's gross-slip samples
  // with its k (a live window's loop and misfit).
  bool keep_samples = false;
  // The noise split of J and of k over the cycles given (MuFit::cost_floor
  // and cost_excess, FrictionFits::k_signal_rms and k_noise_rms); false
  // leaves them NaN: a live window splits each new cycle's J against a
  // template of earlier windows' cycles, not against its own few.
  bool split_noise = true;
  // k from the record's depth channel (the ball's vertical position,
  // penetration positive: k = -d depth/dx) instead of P/S; the ensemble
  // estimate only.
  bool k_from_depth = false;
  // +1: the depth channel grows into the specimen (as the reader makes
  // it); -1: it runs the other way (turned over where its profile runs
  // against the friction's, DepthSign).
  double depth_sign = 1.0;
  bool IsValid(std::string* why) const;
};

// Gathers the gross-slip samples of a cycle with k from the force channel,
// k = (1/S) dP/dx of this cycle's own P (options.slope, spans resolved for
// the record's sampling rate), from a scan slope profile, or (source kForce
// with force_slopes) from given force-side profiles per direction.
CycleSamples GatherCycle(
    const force::ForceRecord& record,
    const force::Cycle& cycle,
    SlopeSource source,
    const FrictionFitOptions& options,
    const PlateProfile* scan_slope = nullptr,
    const std::array<PlateProfile, 2>* force_slopes = nullptr);

// The sampling rate of a record: the stated one, else from its clock
// (0 when neither is known).
double SamplingRateOf(const force::ForceRecord& record);

// The force side's k for the cycles [first, last] of a test, estimated as
// options.k_estimate says: each cycle from its own P, or each from the
// ensemble of its neighbours (P binned per cycle once, here; cycles asked
// for in order slide the ensemble's sums instead of summing them anew, so
// one ForceSlopes is not for concurrent use).
class ForceSlopes {
 public:
  ForceSlopes(const force::ForceRecord& record,
              const force::CycleSet& cycles,
              const FrictionFitOptions& options,
              int first = 0,
              int last = -1);
  // Gross-slip samples of cycle c (in [first, last]) with the force's k.
  CycleSamples Gather(int c) const;
  // One line: which estimate, with its spans.
  std::string Describe() const;
  // Cycles whose k shares P samples with cycle c's: |c' - c| < this.
  int SharedCycles() const;
  // The variance of the ensemble's k noise per sample, from `probes`
  // cycles spread over [first, last]: each ensemble split into its odd and
  // even cycles, the variance of the two halves' difference over the
  // central 80% of the stroke scaled by n_odd n_even / n^2. The track's
  // change over cycles cancels between the interleaved halves. NaN for k
  // per cycle or when nothing could be compared.
  double EnsembleNoiseVariance(int first, int last, int probes = 24) const;

 private:
  const force::ForceRecord& record_;
  const force::CycleSet& cycles_;
  FrictionFitOptions options_;  // the derivative's spans resolved
  // The channel whose variation along x is the path's height, and its
  // height's scale: height = profile / profile_per_mm (P and S, or the
  // depth and -1).
  const Eigen::VectorXd& profile_;
  double profile_per_mm_;
  // P binned along x, for one ensemble's cycles at a time (a ring): a
  // cycle is binned when a window reaches it.
  mutable std::optional<CycleBins> normal_bins_;
  mutable std::vector<int> binned_cycle_;  // per ring slot, -1 empty
  // Bins cycle c into its ring slot unless it is there already.
  void BinCycle(int c) const;
  // The ensemble sums of the last window asked for, per direction.
  mutable std::array<CycleBins::Sums, 2> window_sums_;
  mutable int window_first_ = 0, window_last_ = -1;
};

// A fit's J split into the noise floor and the excess that repeats at the
// same x (J^2 = floor^2 + excess^2 per direction), from the split of its
// misfit (SplitRepeatable) and its sum of Q^2, per direction [0] forward,
// [1] reverse: MuFit's misfit_sq, repeat_sq, cost_floor and cost_excess.
void ApplyRepeatSplit(const std::array<RepeatSplit, 2>& split,
                      const std::array<double, 2>& q_total,
                      MuFit* f);

// Everything the per-cycle fits of one test give.
struct FrictionFits {
  std::vector<MuFit> cycles;  // mu-hat per cycle
  // With FrictionFitOptions::keep_samples, per cycle the samples fitted
  // (empty for a cycle not fitted); else empty.
  std::vector<CycleSamples> samples;
  std::string slope;  // how k was obtained (ForceSlopes::Describe)
  // Successive cycles whose errors are correlated through a shared slope
  // (SummariseWithErrors): ForceSlopes::SharedCycles for the force side,
  // every cycle for the scan's one slope.
  int correlated_cycles = 1;
  // k over the gross-slip samples of all cycles: root mean square of its
  // part that repeats at the same x in other cycles, and of the rest
  // (noise). Force side only; NaN for the scan's.
  double k_signal_rms = MuFit::kNotComputed;
  double k_noise_rms = MuFit::kNotComputed;
  // The ensemble k's noise (rms per sample) from its odd and even halves
  // (ForceSlopes::EnsembleNoiseVariance): the noise alone, where the split's
  // k_noise_rms also holds the track's change between a cycle and its
  // template. correct_k_noise_bias uses this one. NaN for k per cycle.
  double k_ensemble_noise_rms = MuFit::kNotComputed;
  // The mean over converged cycles of what correct_k_noise_bias added to
  // mu-hat (0 when it is off or does not apply).
  double k_noise_correction = 0.0;
};

// mu-hat for every cycle (Eq. 6), slope from the chosen source, with the
// noise split of every cycle's J. With the scan's slope, `slope_scale`
// (one factor per cycle, or null) multiplies the slope of each cycle: the
// scan shows the track's final state, the factor its state in that cycle
// (FuseOptions::scan_slope_history).
// Requires record.IsConsistent() and, when given, one scale per cycle.
FrictionFits FitFriction(const force::ForceRecord& record,
                         const force::CycleSet& cycles,
                         SlopeSource source,
                         const FrictionFitOptions& options = {},
                         const PlateProfile* scan_slope = nullptr,
                         const std::vector<double>* slope_scale = nullptr);

// FitFriction's per-cycle fits.
std::vector<MuFit> FitFrictionPerCycle(
    const force::ForceRecord& record,
    const force::CycleSet& cycles,
    SlopeSource source,
    const FrictionFitOptions& options = {},
    const PlateProfile* scan_slope = nullptr,
    const std::vector<double>* slope_scale = nullptr);

}  // namespace wearscar::fusion
