// The scan's identity as an analysis unit (scan_identity.h): whether the
// scan is this test's track and this specimen's, decided on the
// comparison before the verdict, which reads it (MismatchReport::Identity).
// Its premise (the waviness stands above its noise and lines up at one
// place, or the track's place is known), what it says where it cannot
// check, and its section of result.json live here.

#include <fmt/format.h>

#include <cmath>

#include "units.h"
#include "wearscar/fusion/scan_identity.h"

namespace wearscar::fusion::internal {
namespace {

class ScanIdentityUnit : public TypedUnit<ScanIdentity> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "scan_identity",
        "whether the scan is this test's track (its length against the "
        "stroke) and this specimen's (where its track lies against the "
        "stroke, its waviness against P/S's)",
        {"the scan", "the comparison (the aligned waviness)"},
        {}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kCompared;
  }
  ScanIdentity Run(const UnitInput& in) const override {
    return JudgeScanIdentity(in.judged->mismatch, in.options.verdict);
  }
  // Where the identity cannot be checked, the assumptions say why.
  void Say(const ScanIdentity& id, TestResult* r) const override {
    if (!r->scan || !r->mismatch.has_scan) return;
    if (!id.judged) {
      r->assumptions.push_back(
          "the scan's identity is not checked against the profile from the "
          "friction (integrated from it, its errors are not a sensor's "
          "noise)");
    } else if (!id.checkable) {
      r->assumptions.push_back(Uncheckable(id, *r));
    }
  }
  std::vector<Premise> Premises(const ScanIdentity& id_result,
                                const TestResult& r) const override {
    if (!r.scan || !r.mismatch.has_scan) return {};
    const MismatchReport& m = r.mismatch;
    const VerdictOptions& v = r.options.verdict;
    Premise id;
    id.rule = "the scan's identity";
    id.statement =
        "the track's waviness (its rings and texture) stands above the "
        "force profile's noise, so another specimen's track would not fit "
        "as well";
    id.state = !id_result.judged     ? Premise::State::kNotChecked
               : id_result.checkable ? Premise::State::kHeld
                                     : Premise::State::kFailed;
    id.evidence =
        id_result.judged
            ? fmt::format(
                  "the waviness stands {:.1f}x above its noise in "
                  "variance (at least {:g}); it correlates at r = "
                  "{:.2f} (at least {:.2f} for this specimen's scan)",
                  m.waviness_to_noise,
                  v.min_waviness_to_noise,
                  m.waviness_correlation,
                  v.min_waviness_correlation) +
                  (id_result.lines_up_twice
                       ? fmt::format(", and at r = {:.2f} shifted {:.2f} mm "
                                     "(only the track's place tells them "
                                     "apart)",
                                     m.waviness_runner_up,
                                     m.waviness_runner_up_shift_mm -
                                         r.scan->alignment.shift_mm)
                       : std::string())
            : "not checked against the profile from the friction";
    id.otherwise =
        "the scan's identity is not checked (the track's length and centre "
        "still are)";
    return {id};
  }
  nlohmann::json Json(const ScanIdentity& id,
                      const TestResult& r) const override {
    if (!r.scan || !r.mismatch.has_scan) return nullptr;
    return {{"judged", id.judged},
            {"checkable", id.checkable},
            {"lines_up_twice", id.lines_up_twice},
            {"another_test", id.another_test},
            {"moved", id.moved},
            {"foreign_waviness", id.foreign},
            {"doubted", id.Doubted()}};
  }

 private:
  static std::string Uncheckable(const ScanIdentity& id, const TestResult& r) {
    const MismatchReport& m = r.mismatch;
    const VerdictOptions& v = r.options.verdict;
    const double above = m.waviness_to_noise;
    return fmt::format(
        "the scan's identity cannot be checked: {}, so another specimen's "
        "track of the same case would fit as well (the number to quote does "
        "not depend on it)",
        above >= v.min_waviness_to_noise && id.lines_up_twice
            ? fmt::format(
                  "its waviness lines up at r = {:.2f} here and at r = "
                  "{:.2f} {:.2f} mm away (rings of one width), and where its "
                  "track lies against the stroke is not known (the track "
                  "runs off the scanned field, was placed by hand or found "
                  "with low confidence)",
                  m.waviness_correlation,
                  m.waviness_runner_up,
                  m.waviness_runner_up_shift_mm - r.scan->alignment.shift_mm)
        : std::isfinite(above) && above >= 1
            ? fmt::format("the track's waviness (its rings and texture) "
                          "stands only {:.1f}x above P/S's noise in variance "
                          "(at least {:g} is needed)",
                          above,
                          v.min_waviness_to_noise)
            : std::string("the track shows no waviness (rings, texture) "
                          "above P/S's noise"));
  }
};

}  // namespace

const AnalysisUnit& ScanIdentityAnalysis() {
  static const ScanIdentityUnit unit;
  return unit;
}

}  // namespace wearscar::fusion::internal
