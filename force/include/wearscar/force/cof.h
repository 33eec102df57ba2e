#pragma once

#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"

namespace wearscar::force {

// Classic friction coefficients of one cycle.
struct CycleCof {
  int cycle = 0;
  // Mean method: mean |Q| over both gross-slip windows / mean P there.
  double mu_mean = 0.0;
  // Energy method mu_Ed = E_d / (4 P delta), E_d the loop area (N mm).
  double dissipated_energy_nmm = 0.0;
  double mean_normal_n = 0.0;
  double delta_max_mm = 0.0;   // half the stroke (the paper)
  double delta_g_mm = 0.0;     // half the loop opening at Q = 0 (Fouvry)
  double mu_energy_max = 0.0;  // with delta_max
  double mu_energy_g = 0.0;    // with delta_g
  // Envelopes (Figs. 5-6).
  double q_max_n = 0.0, q_min_n = 0.0, p_max_n = 0.0, p_min_n = 0.0;
  double p_range_n = 0.0;  // p_max_n - p_min_n over the cycle
  // Pearson correlation of the fluctuations of |Q| and P during gross slip,
  // each direction separately, averaged (the argument of the paper's Figs.
  // 7e-f): near +1 when Q follows P (wear-scar interaction or Coulomb), near
  // 0 when Q fluctuates on its own.
  double qp_correlation = 0.0;
};

std::vector<CycleCof> ComputeClassicCof(const ForceRecord& record,
                                        const CycleSet& cycles);

}  // namespace wearscar::force
