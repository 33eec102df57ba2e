#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/force/slope.h"
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

  bool IsValid(std::string* why) const;
};

// Result of one fit, pessimistic by default (Ceres Solver::Summary style).
struct MuFit {
  double mu_hat = 0.0;
  double cost = 0.0;   // J at mu_hat
  int samples = 0;     // gross-slip samples used (both directions)
  int iterations = 0;  // Brent iterations after the grid
  bool converged = false;
  bool at_bound = false;  // the minimum sits on mu_min or mu_max
  std::string message = "not run";

  std::string BriefReport() const;
};

// mu-hat = argmin J: grid bracketing, then Brent's method in the bracket.
MuFit FitMu(const CycleSamples& samples, const FitMuOptions& options = {});

// J on a grid of mu (paper Fig. 11).
Eigen::VectorXd CostCurve(const CycleSamples& samples,
                          const Eigen::VectorXd& mu_grid);

// A slope of the sliding path known along the plate coordinate (from the
// scan), linearly interpolated; NaN outside.
struct SlopeProfile {
  Eigen::VectorXd x_mm;  // increasing
  Eigen::VectorXd k;
  double At(double x) const;
};

enum class SlopeSource { kForce, kScan };

struct FrictionFitOptions {
  force::SlopeOptions slope;  // derivative and S for the force-side slope
  FitMuOptions fit;
  bool IsValid(std::string* why) const;
};

// Gathers the gross-slip samples of a cycle with k from the force channel,
// k = (1/S) dP/dx, or from a scan slope profile.
CycleSamples GatherCycle(const force::ForceRecord& record,
                         const force::Cycle& cycle,
                         SlopeSource source,
                         const FrictionFitOptions& options,
                         const SlopeProfile* scan_slope = nullptr);

// mu-hat for every cycle (Eq. 6), slope from the chosen source.
std::vector<MuFit> FitFrictionPerCycle(
    const force::ForceRecord& record,
    const force::CycleSet& cycles,
    SlopeSource source,
    const FrictionFitOptions& options = {},
    const SlopeProfile* scan_slope = nullptr);

}  // namespace wearscar::fusion
