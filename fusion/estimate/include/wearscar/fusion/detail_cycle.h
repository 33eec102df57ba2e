#pragma once

#include <Eigen/Core>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/fit_mu.h"
#include "wearscar/fusion/lugre.h"

namespace wearscar::fusion {

// One cycle looked at closely (the paper's Figs. 10-12 and 17): its
// gross-slip samples with both slopes of the sliding path and Q as the
// wear-scar model gives it with each; J(mu) over the fit's interval with
// each slope; and the wear-scar model along LuGre's trace of the cycle.
struct DetailCycle {
  int cycle = -1;  // 0-based; -1: none
  // Per gross-slip sample, forward then reverse (direction +1, -1).
  Eigen::VectorXd direction, x_mm, q_n, p_n;
  Eigen::VectorXd k_force, k_scan;  // k_scan NaN without a scan
  Eigen::VectorXd q_model_force_n, q_model_scan_n;
  // J(mu) on a uniform grid of mu (paper Fig. 11); cost_scan NaN without
  // a scan.
  Eigen::VectorXd cost_mu, cost_force, cost_scan;
  // At each sample of the LuGre fit's trace: Q of the wear-scar model
  // with k from P and the cycle's mu-hat, NaN outside gross slip (the
  // model describes gross slip only) or where k had no value.
  Eigen::VectorXd lugre_q_wearscar_n;
};

// The detail of `cycle` from the analysis already done: mu-hat of each
// side (the force side's in `force_fits` (`fit_scan` and `scan_slope` null
// without a scan), `lugre` null when it was not fitted; `cost_points` points of
// J(mu).
DetailCycle ComputeDetailCycle(const force::ForceRecord& record,
                               const ForceAnalysis& force,
                               const SlopeFits& force_fits,
                               const FrictionFitOptions& options,
                               int cycle,
                               int cost_points,
                               const MuFit* fit_scan,
                               const PlateProfile* scan_slope,
                               const LugreFit* lugre);

}  // namespace wearscar::fusion
