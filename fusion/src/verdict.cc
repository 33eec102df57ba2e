#include "wearscar/fusion/verdict.h"

#include <fmt/format.h>

#include <cmath>

namespace wearscar::fusion {

bool VerdictOptions::IsValid(std::string* why) const {
  if (!(max_cost > 0) || !(max_amplitude_ratio > 0) ||
      !(min_correlation > -1) || !(max_method_difference > 0)) {
    if (why) *why = "verdict thresholds must be positive (correlation > -1)";
    return false;
  }
  return true;
}

std::string Verdict::Summary() const {
  if (explained) return "explained by wear-scar interaction";
  std::string s = "not explained by wear-scar interaction: ";
  for (size_t i = 0; i < reasons.size(); ++i) s += (i ? "; " : "") + reasons[i];
  return s;
}

Verdict Judge(const MismatchReport& r, const VerdictOptions& o) {
  Verdict v;
  // J and mu-hat from the force-side slope when it was fitted, else from
  // the scan's (--slope scan).
  const bool from_force = r.cost_force.count > 0;
  const Statistic& cost = from_force ? r.cost_force : r.cost_scan;
  const char* source = from_force ? "k from P" : "k from the scan";
  if (cost.count > 0 && cost.mean > o.max_cost) {
    v.reasons.push_back(
        fmt::format("J = {:.3f} after running-in ({}) exceeds {:.2f}",
                    cost.mean,
                    source,
                    o.max_cost));
  }
  if (r.has_scan) {
    if (r.amplitude_ratio > o.max_amplitude_ratio) {
      v.reasons.push_back(
          fmt::format("the spring displacement varies {:.2f}x as much as the "
                      "scanned profile (limit {:.2f}): "
                      "part of the normal displacement is not worn geometry",
                      r.amplitude_ratio,
                      o.max_amplitude_ratio));
    }
    if (r.correlation < o.min_correlation) {
      v.reasons.push_back(
          fmt::format("the aligned profiles correlate at r = {:.2f} < {:.2f}",
                      r.correlation,
                      o.min_correlation));
    }
  }
  const Statistic& mu = from_force ? r.mu_force : r.mu_scan;
  const double difference = from_force ? r.mu_force_minus_energy.mean
                                       : r.mu_scan.mean - r.mu_energy.mean;
  if (mu.count > 0 && std::abs(difference) > o.max_method_difference) {
    v.reasons.push_back(
        fmt::format("the methods disagree: mu-hat {:.4f} ({}) vs energy "
                    "method {:.4f} (limit {:.3f}; mean method {:.4f})",
                    mu.mean,
                    source,
                    r.mu_energy.mean,
                    o.max_method_difference,
                    r.mu_mean.mean));
  }
  v.explained = v.reasons.empty();
  return v;
}

}  // namespace wearscar::fusion
