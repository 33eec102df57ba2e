// LuGre beside the wear-scar fit on the detail cycle (paper Fig. 17) as an
// analysis unit (lugre.h).

#include "units.h"
#include "wearscar/fusion/lugre.h"
#include "wearscar/support/check.h"

namespace wearscar::fusion::internal {
namespace {

class LugreUnit : public TypedUnit<LugreFit> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "lugre",
        "LuGre's parameters fitted on the detail cycle, beside the "
        "wear-scar model's J there (paper Fig. 17)",
        {"the record", "the cycles"},
        {{"lugre.csv",
          {"time_s", "x_mm", "Q_N", "Q_lugre_N", "Q_wearscar_N"},
          "LuGre against the wear-scar model on the detail cycle"}}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kCycles;
  }
  bool WorthAThread() const override { return true; }
  bool Wanted(const FuseOptions& o) const override { return o.fit_lugre; }
  LugreFit Run(const UnitInput& in) const override {
    const int n = static_cast<int>(in.force.cycles.cycles.size());
    return FitLugre(in.record,
                    in.force.cycles,
                    in.options.DetailedCycle(n),
                    in.options.lugre);
  }
  // The detail cycle: the last unless one is given (one beyond the test
  // is refused, not replaced).
  std::vector<UnitChoice> Choices(const LugreFit&,
                                  const TestResult& r) const override {
    const int given = r.options.detail_cycle;
    return {{"detail_cycle",
             given >= 0 ? nlohmann::json(given + 1) : nlohmann::json("last"),
             r.detail_cycle + 1,
             ""}};
  }
  nlohmann::json Json(const LugreFit& lg, const TestResult& r) const override {
    const auto& p = lg.parameters;
    return {
        {"cycle", r.detail_cycle + 1},
        {"sigma0_n_per_mm", p.sigma0_n_per_mm},
        {"sigma1_n_s_per_mm", p.sigma1_n_s_per_mm},
        {"sigma2_n_s_per_mm", p.sigma2_n_s_per_mm},
        {"sigma2_negative", p.sigma2_n_s_per_mm < 0},
        {"stribeck_speed_mm_s", p.stribeck_speed_mm_s},
        {"F_c_N", p.coulomb_n},
        {"F_s_N", p.static_n},
        {"J", lg.cost},
        {"J_wearscar_same_cycle", r.ForceFits().cycles[r.detail_cycle].cost},
        {"converged", lg.converged},
        {"physically_plausible", lg.physically_plausible},
        {"message", lg.message}};
  }
  // The wear-scar model describes gross slip only (NaN elsewhere).
  std::vector<UnitTable> Tables(const LugreFit& lg,
                                const force::ForceRecord&,
                                const TestResult& r) const override {
    const DetailCycle& d = r.units.Get<DetailCycle>();
    WEARSCAR_CHECK(d.lugre_q_wearscar_n.size() == lg.time_s.size(),
                   "the detail cycle holds the model along LuGre's trace");
    Table t(Spec().tables[0].columns);
    for (Eigen::Index i = 0; i < lg.time_s.size(); ++i) {
      t.rows.push_back({lg.time_s[i],
                        lg.x_mm[i],
                        lg.q_measured_n[i],
                        lg.q_lugre_n[i],
                        d.lugre_q_wearscar_n[i]});
    }
    return MovedList(UnitTable{"lugre.csv", std::move(t)});
  }
  std::vector<UnitFigure> Figures(const LugreFit&,
                                  const std::string& name,
                                  const TestResult& r) const override {
    using Role = UnitSeries::Role;
    UnitSeries measured{
        "lugre.csv", "x_mm", "Q_N", "measured", Role::kMeasured};
    UnitSeries lugre{
        "lugre.csv", "x_mm", "Q_lugre_N", "LuGre", Role::kClassic, 2, 2};
    UnitSeries model{
        "lugre.csv", "x_mm", "Q_wearscar_N", "wear-scar", Role::kForce, 2, 4};
    return {{"fig17_lugre",
             name + ": LuGre and wear-scar, cycle " +
                 std::to_string(r.detail_cycle + 1) + " (Fig. 17)",
             {{"",
               "x (mm)",
               "Q (N)",
               "",
               std::nullopt,
               "",
               {measured, lugre, model}}}}};
  }
};

}  // namespace

const AnalysisUnit& LugreAnalysis() {
  static const LugreUnit kUnit;
  return kUnit;
}

}  // namespace wearscar::fusion::internal
