#pragma once

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
  // statistics and the verdict.
  int running_in_cycles = 50;

  bool IsValid(std::string* why) const;
};

// Mean and standard deviation over the cycles after running-in.
struct Statistic {
  double mean = 0.0;
  double sd = 0.0;
  int count = 0;
};

// Everything the force side of one test yields.
struct ForceAnalysis {
  force::CycleSet cycles;
  std::vector<force::CycleCof> cof;
  std::vector<MuFit> fit_force;  // mu-hat with k from the force channel
  Statistic mu_hat, cost, mu_mean, mu_energy;
  int slip_fallbacks = 0;  // half cycles where the central fallback was used
};

// Segments, finds gross slip, computes the classic COFs and fits mu-hat per
// cycle with the force-side slope. Throws force::ForceError for records that
// cannot be segmented.
ForceAnalysis AnalyzeForce(const force::ForceRecord& record,
                           const AnalysisOptions& options);

// Mean and sd of values[i] over i >= first where finite.
Statistic Summarise(const std::vector<double>& values, int first);

}  // namespace wearscar::fusion
