#include "wearscar/fusion/analysis.h"

#include <cmath>

#include "wearscar/fusion/forward_model.h"

namespace wearscar::fusion {

bool AnalysisOptions::IsValid(std::string* why) const {
  if (!segment.IsValid(why) || !slip.IsValid(why) || !friction.IsValid(why))
    return false;
  if (running_in_cycles < 0) {
    if (why) *why = "running_in_cycles must be >= 0";
    return false;
  }
  return true;
}

Statistic Summarise(const std::vector<double>& values, int first) {
  Statistic s;
  double sum = 0, sum2 = 0;
  for (size_t i = static_cast<size_t>(std::max(0, first)); i < values.size();
       ++i) {
    if (!std::isfinite(values[i])) continue;
    sum += values[i];
    sum2 += values[i] * values[i];
    ++s.count;
  }
  if (s.count > 0) {
    s.mean = sum / s.count;
    s.sd = s.count > 1 ? std::sqrt(std::max(
                             0.0, (sum2 - sum * sum / s.count) / (s.count - 1)))
                       : 0.0;
  }
  return s;
}

ForceAnalysis AnalyzeForce(const force::ForceRecord& record,
                           const AnalysisOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw FusionError("analysis options: " + why);
  ForceAnalysis a;
  a.cycles = force::SegmentCycles(
      record.x_mm, options.segment, record.metadata.source);
  force::FindGrossSlip(record, &a.cycles, options.slip);
  for (const auto& c : a.cycles.cycles) {
    a.slip_fallbacks += c.forward.slip_fallback + c.reverse.slip_fallback;
  }
  a.cof = force::ComputeClassicCof(record, a.cycles);
  a.fit_force = FitFrictionPerCycle(
      record, a.cycles, SlopeSource::kForce, options.friction);
  // Running-in never swallows the whole test: keep at least the last half.
  const int n = static_cast<int>(a.cycles.cycles.size());
  const int first = std::min(options.running_in_cycles, n / 2);
  std::vector<double> mu, j, mm, me;
  for (int i = 0; i < n; ++i) {
    const bool ok = a.fit_force[i].converged;
    mu.push_back(ok ? a.fit_force[i].mu_hat : std::nan(""));
    j.push_back(ok ? a.fit_force[i].cost : std::nan(""));
    mm.push_back(a.cof[i].mu_mean);
    me.push_back(a.cof[i].mu_energy_g);
  }
  a.mu_hat = Summarise(mu, first);
  a.cost = Summarise(j, first);
  a.mu_mean = Summarise(mm, first);
  a.mu_energy = Summarise(me, first);
  return a;
}

}  // namespace wearscar::fusion
