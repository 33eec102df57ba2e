// The screen as an analysis unit (screen.h): whether the loops of a test
// the verdict may pass repeat a misfit that acts as friction does above
// their noise. It runs on the comparison after the spring check (which
// decides whose k the verdict judges) and before the verdict, which reads
// it (MismatchReport::Screen); its premise and its result.json section
// live here.

#include "units.h"
#include "wearscar/fusion/screen.h"
#include "wearscar/fusion/spring_check.h"

namespace wearscar::fusion::internal {
namespace {

class ScreenUnit : public TypedUnit<ScreenFinding> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "screen",
        "whether the loops repeat a misfit above their noise that acts as "
        "friction does (changing sign with the motion), which may bias "
        "mu-hat in a test the verdict passes",
        {"spring", "the comparison (J's split over the compared cycles)"},
        {}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kCompared;
  }
  // On the comparison with the spring check's result, which says whose k
  // the verdict judges.
  ScreenFinding Run(const UnitInput& in) const override {
    MismatchReport m = in.judged->mismatch;
    m.spring_check = in.units.Share<SpringCheck>();
    return ScreenTheLoops(m, in.options.verdict);
  }
  std::vector<Premise> Premises(const ScreenFinding& s,
                                const TestResult&) const override {
    return {s.premise};
  }
  nlohmann::json Json(const ScreenFinding& s,
                      const TestResult& r) const override {
    if (!std::isfinite(s.excess)) return nullptr;
    return {{"with_force_slope", s.with_force_slope},
            {"by_direction", s.by_direction},
            {"excess", s.excess},
            {"excess_interval", {s.excess_low, s.excess_high}},
            {"noise_floor", s.floor},
            {"limit_to_floor", r.options.verdict.screen_excess_to_floor},
            {"screened", !s.finding.empty()}};
  }
};

}  // namespace

const AnalysisUnit& ScreenAnalysis() {
  static const ScreenUnit unit;
  return unit;
}

}  // namespace wearscar::fusion::internal
