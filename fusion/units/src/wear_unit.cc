// The wear as two analysis units (wear.h): the sliding (the mean load and
// the distance, from the cycles, beside the decision) and the wear (the
// scanned track's size and Archard's specific rate, once the scan side is
// judged), which reads the sliding.

#include <cmath>

#include "units.h"
#include "wearscar/fusion/wear.h"

namespace wearscar::fusion::internal {
namespace {

class SlidingUnit : public TypedUnit<Sliding> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "sliding",
        "the mean normal load and the sliding distance over the complete "
        "cycles (the wear's force side; in result.json's wear)",
        {"the record", "the cycles"},
        {}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kCycles;
  }
  Sliding Run(const UnitInput& in) const override {
    return MeasureSliding(in.record, in.force.cycles);
  }
  // Said in the wear's section.
  nlohmann::json Json(const Sliding&, const TestResult&) const override {
    return nullptr;
  }
};

class WearUnit : public TypedUnit<Wear> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "wear",
        "the worn track's volume, depth, width and length from the scan, "
        "the load and the sliding distance, and Archard's specific wear "
        "rate V / (F_N s)",
        {"sliding", "the scan's track"},
        {}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kJudged;
  }
  // Without a usable scan the scan side is NaN.
  Wear Run(const UnitInput& in) const override {
    const Sliding* sliding = in.units.Find<Sliding>();
    const ScanAnalysis* scan = in.judged->scan ? &*in.judged->scan : nullptr;
    return WearOf(
        sliding ? *sliding : MeasureSliding(in.record, in.force.cycles),
        scan ? std::optional<scan::Track>(scan->track) : std::nullopt);
  }
  nlohmann::json Json(const Wear& w, const TestResult&) const override {
    return {{"volume_mm3", w.volume_mm3},
            {"mean_depth_mm", w.mean_depth_mm},
            {"max_depth_mm", w.max_depth_mm},
            {"width_mm", w.width_mm},
            {"length_mm", w.length_mm},
            {"normal_load_n", w.normal_load_n},
            {"sliding_distance_m", w.sliding_distance_m},
            {"specific_wear_rate_mm3_per_n_m", w.specific_rate_mm3_per_n_m}};
  }
};

}  // namespace

const AnalysisUnit& SlidingAnalysis() {
  static const SlidingUnit kUnit;
  return kUnit;
}

const AnalysisUnit& WearAnalysis() {
  static const WearUnit kUnit;
  return kUnit;
}

}  // namespace wearscar::fusion::internal
