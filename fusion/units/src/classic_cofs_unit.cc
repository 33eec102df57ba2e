// The classic friction coefficients per cycle as an analysis unit
// (force::ComputeClassicCof): the mean method (mean |Q| / mean P over gross
// slip) and the energy method (the loop's area over 4 P delta), with the
// cycle's envelopes. The pipeline's core detects the running-in on the mean
// method (FindRunningIn) and the comparison takes the energy method's
// difference to mu-hat (the verdict's criterion), so it runs first, on the
// cycles alone, and is collected before anything else runs.

#include <fmt/format.h>

#include <cmath>

#include "units.h"
#include "wearscar/support/numbers.h"

namespace wearscar::fusion::internal {
namespace {

class ClassicCofsUnit : public TypedUnit<ClassicCofs> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "classic_cofs",
        "the classic COFs per cycle: the mean method, the energy method "
        "with half the stroke and with the loop's opening, and the cycle's "
        "envelopes",
        {"the record", "the cycles"},
        {},
        {{"cycles.csv",
          "samples",
          {"mu_mean",
           "mu_energy_max",
           "mu_energy_g",
           "E_d_Nmm",
           "delta_max_mm",
           "delta_g_mm",
           "P_mean_N",
           "Q_max_N",
           "Q_min_N",
           "P_max_N",
           "P_min_N",
           "P_range_N",
           "QP_correlation"}}},
        "after_running_in"};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kSegmented;
  }
  ClassicCofs Run(const UnitInput& in) const override {
    return {force::ComputeClassicCof(in.record, in.force.cycles)};
  }
  // The mean method averages |Q| and P over each half cycle's gross slip:
  // where none was found the central part of the stroke stands in for it
  // (GrossSlipOptions), which takes Q's turn at a slow reversal for slip.
  std::vector<Premise> Premises(const ClassicCofs& cofs,
                                const TestResult& r) const override {
    Premise p;
    p.rule = "classic COFs";
    p.statement = "gross slip is found in every half cycle";
    const int halves = 2 * static_cast<int>(cofs.cycles.size());
    const int fallbacks = r.force.slip_fallbacks;
    p.state = halves == 0      ? Premise::State::kNotChecked
              : fallbacks == 0 ? Premise::State::kHeld
                               : Premise::State::kFailed;
    p.evidence = fmt::format(
        "{} of {} half cycles without gross slip found", fallbacks, halves);
    p.otherwise =
        "their mean method averages the stroke's central part there "
        "(cycles.csv's slip_fallback marks them); mu-hat fits the same "
        "samples";
    return {p};
  }
  // Their mean and scatter after running-in (each judged by its own
  // scatter: SummariseSeries).
  nlohmann::json Json(const ClassicCofs& cofs,
                      const TestResult& r) const override {
    const int n = static_cast<int>(cofs.cycles.size());
    std::vector<double> mean, energy;
    for (const force::CycleCof& c : cofs.cycles) {
      mean.push_back(c.mu_mean);
      energy.push_back(c.mu_energy_g);
    }
    const int first = r.force.running_in.cycles;
    return {
        {"mu_mean", StatisticJson(SummariseSeries(mean, first, n - 1))},
        {"mu_energy", StatisticJson(SummariseSeries(energy, first, n - 1))}};
  }
  std::vector<std::vector<double>> Columns(const ClassicCofs& cofs,
                                           const UnitColumns&,
                                           const TestResult&) const override {
    std::vector<std::vector<double>> rows;
    rows.reserve(cofs.cycles.size());
    for (const force::CycleCof& c : cofs.cycles) {
      rows.push_back({c.mu_mean,
                      c.mu_energy_max,
                      c.mu_energy_g,
                      c.dissipated_energy_nmm,
                      c.delta_max_mm,
                      c.delta_g_mm,
                      c.mean_normal_n,
                      c.q_max_n,
                      c.q_min_n,
                      c.p_max_n,
                      c.p_min_n,
                      c.p_range_n,
                      c.qp_correlation});
    }
    return rows;
  }
};

}  // namespace

const AnalysisUnit& ClassicCofsAnalysis() {
  static const ClassicCofsUnit kUnit;
  return kUnit;
}

}  // namespace wearscar::fusion::internal
