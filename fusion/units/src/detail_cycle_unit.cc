// The detail cycle as an analysis unit (ComputeDetailCycle): one cycle's
// gross-slip samples with both slopes, Q reconstructed with each, J(mu)
// with each, and the wear-scar model along LuGre's trace (the paper's
// Figs. 10-12 and 17), from the fits already made; the cycle is the
// result's (TestResult::detail_cycle: --detail-cycle, else the last).

#include "units.h"
#include "wearscar/fusion/lugre.h"

namespace wearscar::fusion::internal {
namespace {

double Number(int v) { return static_cast<double>(v); }

class DetailCycleUnit : public TypedUnit<DetailCycle> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "detail_cycle",
        "one cycle in detail: its gross-slip samples with both slopes, Q "
        "reconstructed with each, J(mu) with each, and the wear-scar model "
        "along LuGre's trace",
        {"the record", "the cycles", "mu_fit_spring", "mu_fit_scan", "lugre"},
        {{"detail.csv",
          {"cycle",
           "direction",
           "x_mm",
           "Q_N",
           "P_N",
           "k_force",
           "k_scan",
           "Q_model_force_N",
           "Q_model_scan_N"},
          "the detail cycle's gross-slip samples, both slopes, Q "
          "reconstructed with each"},
         {"cost_curve.csv",
          {"mu", "J_force", "J_scan"},
          "J(mu) on the detail cycle with each slope"}}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kJudged;
  }
  DetailCycle Run(const UnitInput& in) const override {
    const TestResult& r = *in.judged;
    const std::vector<MuFit>& scan_fits = r.ScanSlopeFits().cycles;
    const int dc = r.detail_cycle;
    const bool scanned =
        r.scan && dc >= 0 && dc < static_cast<int>(scan_fits.size());
    return ComputeDetailCycle(in.record,
                              in.force,
                              r.ForceFits(),
                              in.options.analysis.friction,
                              dc,
                              in.options.cost_curve_points,
                              scanned ? &scan_fits[dc] : nullptr,
                              r.scan ? &r.scan->slope : nullptr,
                              in.units.Find<LugreFit>());
  }
  nlohmann::json Json(const DetailCycle&, const TestResult&) const override {
    return nullptr;  // its tables (the cycle: result.json's detail_cycle)
  }
  std::vector<UnitTable> Tables(const DetailCycle& d,
                                const force::ForceRecord&,
                                const TestResult&) const override {
    Table t(Spec().tables[0].columns);
    for (Eigen::Index i = 0; i < d.x_mm.size(); ++i) {
      t.rows.push_back({Number(d.cycle + 1),
                        d.direction[i],
                        d.x_mm[i],
                        d.q_n[i],
                        d.p_n[i],
                        d.k_force[i],
                        d.k_scan[i],
                        d.q_model_force_n[i],
                        d.q_model_scan_n[i]});
    }
    Table c(Spec().tables[1].columns);
    for (Eigen::Index i = 0; i < d.cost_mu.size(); ++i)
      c.rows.push_back({d.cost_mu[i], d.cost_force[i], d.cost_scan[i]});
    return MovedList(UnitTable{"detail.csv", std::move(t)},
                     UnitTable{"cost_curve.csv", std::move(c)});
  }
};

}  // namespace

const AnalysisUnit& DetailCycleAnalysis() {
  static const DetailCycleUnit kUnit;
  return kUnit;
}

}  // namespace wearscar::fusion::internal
