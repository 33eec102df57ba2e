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
  if (r.cost_force.count > 0 && r.cost_force.mean > o.max_cost) {
    v.reasons.push_back(
        fmt::format("J = {:.3f} after running-in (k from P) exceeds {:.2f}",
                    r.cost_force.mean,
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
  if (r.mu_force.count > 0) {
    if (std::abs(r.mu_force_minus_energy.mean) > o.max_method_difference) {
      v.reasons.push_back(
          fmt::format("the methods disagree: mu-hat {:.4f} vs energy method "
                      "{:.4f} (limit {:.3f}; mean "
                      "method {:.4f})",
                      r.mu_force.mean,
                      r.mu_energy.mean,
                      o.max_method_difference,
                      r.mu_mean.mean));
    }
  }
  v.explained = v.reasons.empty();
  return v;
}

}  // namespace wearscar::fusion
