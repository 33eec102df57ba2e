#pragma once
// The diagnosis's data from a record: which cycles, the bins along x, each
// cycle's base slope (from P/S, the depth channel or a fixed profile) and
// its gross-slip samples.

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "diagnose_model.h"
#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/fusion/diagnosis.h"
#include "wearscar/fusion/fit_mu.h"

namespace wearscar::fusion::internal {

// Up to max_cycles cycles spread evenly over those after running-in.
std::vector<int> ChooseCycles(int n, int first, int max_cycles);

// Bins along x over the chosen cycles: the option's width, or the largest
// x step between samples (so that every bin holds samples at low sampling
// rates).
struct ProfileGrid {
  double x_lo = INFINITY, x_hi = -INFINITY, bin = 0;
  Eigen::Index bins = 0;
  Eigen::VectorXd centres;
};

// The diagnosis's data from a record: the cycles' samples with their
// slopes and depth, and where the samples slide.
struct Prepared {
  Data data;
  ProfileGrid grid;
  PlateProfile depth;
  double slip_lo = INFINITY, slip_hi = -INFINITY;
};

// The delay of Q's turn at the chosen cycles' reversals behind x's
// (DirectEvidence::q_delay_s): the median over the turns, with its
// standard error; left NaN with fewer than four turns whose stick tells.
void ReversalDelay(const force::ForceRecord& record,
                   const force::CycleSet& cycles,
                   const std::vector<int>& chosen,
                   DirectEvidence* evidence);

// Fills `p` from the chosen cycles: `depth` (the scan's) or the force
// side's profile, k per cycle from `friction` or the fixed `slope`.
void Prepare(const force::ForceRecord& record,
             const force::CycleSet& cycles,
             const FrictionFitOptions& friction,
             const PlateProfile* depth,
             const PlateProfile* slope,
             const std::vector<int>& chosen,
             const DiagnoseOptions& o,
             Prepared* p);

}  // namespace wearscar::fusion::internal
