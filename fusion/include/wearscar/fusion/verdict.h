#pragma once

#include <string>
#include <vector>

#include "wearscar/fusion/align.h"
#include "wearscar/fusion/analysis.h"

namespace wearscar::fusion {

// Differences between the force-side and the scan-side view of one test,
// over a range of cycles (the paper's Fig. 8, 14 and 16 quantities).
struct MismatchReport {
  bool has_scan = false;
  int first_cycle = 0, last_cycle = 0;
  double correlation = 0.0;         // aligned profiles
  double amplitude_ratio = 0.0;     // std(f) / std(h)
  double k_rms_difference = 0.0;    // RMS of k_force - k_scan over gross slip
  Statistic mu_force, mu_scan;      // mu-hat with each slope
  Statistic cost_force, cost_scan;  // J with each slope
  Statistic mu_mean, mu_energy;     // classic methods
  double mu_force_minus_scan = 0.0;
  Statistic mu_force_minus_mean;    // per-cycle differences, Fig. 16 (a)
  Statistic mu_force_minus_energy;  // Fig. 16 (b)
};

struct VerdictOptions {
  double max_cost = 0.4;             // J after running-in (paper)
  double max_amplitude_ratio = 1.5;  // spring varies more than the scan
  double min_correlation = 0.7;      // aligned profiles
  // |mu-hat - mu_energy| (energy method with delta_g). The mean method is
  // not judged: on a strongly wavy track mean|P (k + s mu)| exceeds mu P
  // even when the wear-scar model holds exactly, so its difference is
  // reported, not used.
  double max_method_difference = 0.02;
  bool IsValid(std::string* why) const;
};

struct Verdict {
  bool explained = false;
  std::vector<std::string> reasons;  // every criterion that failed
  std::string Summary()
      const;  // "explained by wear-scar interaction" or "not explained: ..."
};

Verdict Judge(const MismatchReport& report, const VerdictOptions& options = {});

}  // namespace wearscar::fusion
