// The spring check as an analysis unit (spring_check.h): P/S against the
// path the friction shows over the compared cycles, where k comes from
// P/S. It runs on the comparison, before the verdict, which reads it
// (MismatchReport::Spring); its finding is said first among the warnings.

#include "units.h"
#include "wearscar/fusion/assumptions.h"
#include "wearscar/fusion/spring_check.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion::internal {
namespace {

class SpringCheckUnit : public TypedUnit<SpringCheck> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "spring",
        "P/S against the path the friction shows: the stiffness used, one "
        "the data contradict, an elastic part, or a stiffness they cannot "
        "tell from an elastic part (k from P/S only)",
        {"track_history",
         "the decision",
         "the comparison (the compared cycles)",
         "the spring (as used)"},
        {}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kCompared;
  }
  // Only where k comes from P/S (an unjudged check otherwise).
  SpringCheck Run(const UnitInput& in) const override {
    const TestResult& r = *in.judged;
    if (!r.profile.FromSpring()) return {};
    return CheckSpring(in.units.Get<TrackHistory>(),
                       r.force.running_in.cycles,
                       r.window.first,
                       r.window.last,
                       in.options.analysis.friction.slope.spring_n_per_mm,
                       in.options.spring_check);
  }
  // A spring the data contradict, or one they cannot tell from an elastic
  // part, is said first: it changes what is quoted.
  void Say(const SpringCheck& c, TestResult* r) const override {
    if (c.contradicted) {
      r->warnings.insert(r->warnings.begin(),
                         c.Describe(SpringOrigin(r->options)));
    } else if (c.undecided) {
      r->warnings.insert(r->warnings.begin(),
                         c.DescribeUndecided(SpringOrigin(r->options)));
    }
  }
  // Q in time with x (the friction's path needs it) and the groove's
  // change during the record (the split of a stiffness from an elastic
  // part needs it).
  std::vector<Premise> Premises(const SpringCheck& c,
                                const TestResult&) const override {
    std::vector<Premise> out;
    if (!c.q_in_time.statement.empty()) out.push_back(c.q_in_time);
    if (!c.changing_groove.statement.empty()) out.push_back(c.changing_groove);
    return out;
  }
  nlohmann::json Json(const SpringCheck& c, const TestResult&) const override {
    if (!c.judged) return nullptr;
    return {
        {"judged", c.judged},
        {"path_ratio", c.path_ratio},
        {"path_ratio_interval", {c.path_ratio_low, c.path_ratio_high}},
        {"growth", c.growth},
        {"growth_to_noise", c.growth_to_noise},
        {"elastic_share", c.elastic_share},
        {"elastic_share_interval", {c.elastic_share_low, c.elastic_share_high}},
        {"elastic", c.elastic},
        {"stiffness_ratio", c.stiffness_ratio},
        {"stiffness_ratio_interval",
         {c.stiffness_ratio_low, c.stiffness_ratio_high}},
        {"used_n_per_mm", c.used_n_per_mm},
        {"implied_n_per_mm", c.ImpliedStiffness()},
        {"implied_interval_n_per_mm", {c.ImpliedLow(), c.ImpliedHigh()}},
        {"implied_is_upper_bound", c.UpperBoundOnly()},
        {"contradicted", c.contradicted},
        {"undecided", c.undecided}};
  }
};

}  // namespace

const AnalysisUnit& SpringCheckAnalysis() {
  static const SpringCheckUnit unit;
  return unit;
}

}  // namespace wearscar::fusion::internal
