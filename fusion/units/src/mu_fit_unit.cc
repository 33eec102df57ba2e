// mu-hat per cycle with each slope source as analysis units: k from P/S
// through the loading spring ("mu_fit_spring", on the cycles beside the
// other units, which the profile's decision reads: P's slope's
// significance), k from the depth channel ("mu_fit_depth", once the
// decision took it) and k from the scan ("mu_fit_scan", once the scan side
// has aligned the scan and taken its slope). The pipeline's core collects
// them before the comparison (UnitRunner::CollectOne) and reads them as
// TestResult::ForceFits and ScanSlopeFits; their columns in cycles.csv and
// their figures after running-in are the comparison's, written from there.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "units.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion::internal {
namespace {

template <typename R>
class MuFitUnit : public TypedUnit<R> {
 public:
  explicit MuFitUnit(UnitSpec spec, bool from_depth)
      : spec_(std::move(spec)), from_depth_(from_depth) {}
  const UnitSpec& Spec() const override { return spec_; }
  UnitStage Stage(const force::ForceRecord&) const override {
    return from_depth_ ? UnitStage::kDecided : UnitStage::kCycles;
  }
  // P/S's on every test (the decision reads it); the depth's where the
  // decision took the depth channel.
  bool Wanted(const FuseOptions& o) const override {
    return !from_depth_ || o.analysis.friction.k_from_depth;
  }
  R Run(const UnitInput& in) const override {
    AnalysisOptions ao = in.options.ForceSide();
    ao.friction.k_from_depth = from_depth_;
    R fits;
    static_cast<SlopeFits&>(fits) = FitForceSide(in.record, ao, in.force);
    return fits;
  }
  // k from P/S rests on P following the sphere's height through the
  // loading spring, which the profile's decision checks (on a dead weight
  // P carries no profile).
  std::vector<Premise> Premises(const R&, const TestResult& r) const override {
    if (from_depth_) return {};
    const ProfileDecision& d = r.profile;
    Premise p;
    p.rule = "the profile's source";
    p.statement = "P follows the sphere's height through the loading spring";
    p.state = d.FromSpring() ? Premise::State::kHeld : Premise::State::kFailed;
    p.evidence = d.reason;
    p.otherwise =
        "the profile is taken from the depth channel or the friction, and k "
        "from the scan is quoted";
    return {p};
  }
  nlohmann::json Json(const R&, const TestResult&) const override {
    return nullptr;  // the force side's (after_running_in, k_rms)
  }

 private:
  UnitSpec spec_;
  bool from_depth_;
};

// Per cycle, the track's waviness from the spring over the final one, within
// [0, max_scan_slope_scale]; 1 where the history has no value.
std::vector<double> ScanSlopeScale(const TrackHistory& history,
                                   const FuseOptions& options) {
  std::vector<double> scale(history.waviness_sd_mm.size(), 1.0);
  const double final_sd = history.final_waviness_sd_mm;
  if (!(final_sd > 0)) return scale;
  for (size_t c = 0; c < scale.size(); ++c) {
    const double r = history.waviness_sd_mm[c] / final_sd;
    if (std::isfinite(r))
      scale[c] = std::clamp(r, 0.0, options.max_scan_slope_scale);
  }
  return scale;
}

// mu-hat with the scan's slope (unless the force slope alone was asked
// for); where the profiles left the path open, with the centreline's too,
// the lower mean J over the quoted cycles kept.
class ScanFitUnit : public TypedUnit<ScanFits> {
 public:
  const UnitSpec& Spec() const override {
    static const UnitSpec kSpec{
        "mu_fit_scan",
        "mu-hat per cycle with k from the scan (the sphere's path, or the "
        "centreline where the loops fit it better)",
        {"the record", "the cycles", "the scan", "track_history"},
        {}};
    return kSpec;
  }
  UnitStage Stage(const force::ForceRecord&) const override {
    return UnitStage::kScanned;
  }
  ScanFits Run(const UnitInput& in) const override {
    const TestResult& r = *in.judged;
    const ScanAnalysis& s = *r.scan;
    const int n = static_cast<int>(in.force.cycles.cycles.size());
    ScanFits sphere;
    if (in.options.slopes == SlopeChoice::kForce) {
      sphere.cycles.assign(n, MuFit{});
      for (auto& f : sphere.cycles) f.message = "not fitted (force slope only)";
      return sphere;
    }
    // The spring's history scales the scan's slope only where P is the
    // profile.
    const TrackHistory* history =
        in.options.scan_slope_history && r.profile.FromSpring()
            ? in.units.Find<TrackHistory>()
            : nullptr;
    sphere = Fit(in, s.slope, history);
    if (!s.centreline_slope) return sphere;
    ScanFits line = Fit(in, *s.centreline_slope, history);
    const CycleWindow w = QuotedWindow(r, &s);
    sphere.j_sphere = line.j_sphere = MeanJ(sphere.cycles, w);
    sphere.j_centreline = line.j_centreline = MeanJ(line.cycles, w);
    if (!(line.j_centreline < line.j_sphere)) return sphere;
    line.centreline = true;
    return line;
  }
  // k from the scan rests on a rigid sphere riding the scanned track (its
  // path, not the centreline, tilts the contact), checked on which path
  // the force side follows and, where both alike, on the loops' J.
  std::vector<Premise> Premises(const ScanFits&,
                                const TestResult& r) const override {
    return {r.scan->rigid_sphere};
  }
  std::vector<UnitChoice> Choices(const ScanFits& f,
                                  const TestResult&) const override {
    if (!std::isfinite(f.j_sphere)) return {};
    return {{"path",
             "the sphere's",
             f.centreline ? "the centreline" : "the sphere's",
             f.centreline
                 ? fmt::format("the profiles follow both alike; J {:.3f} "
                               "with the centreline, {:.3f} with the "
                               "sphere's path",
                               f.j_centreline,
                               f.j_sphere)
                 : ""}};
  }
  nlohmann::json Json(const ScanFits&, const TestResult&) const override {
    return nullptr;  // the scan side's (scan.slope_scale, comparison)
  }

 private:
  static ScanFits Fit(const UnitInput& in,
                      const PlateProfile& slope,
                      const TrackHistory* history) {
    ScanFits f;
    if (history != nullptr)
      f.slope_scale = ScanSlopeScale(*history, in.options);
    // On both cores where the test has them (halves of the cycles).
    FrictionFitOptions friction = in.options.analysis.friction;
    if (in.options.parallel) friction.threads = std::max(friction.threads, 2);
    f.cycles = FitFrictionPerCycle(in.record,
                                   in.force.cycles,
                                   SlopeSource::kScan,
                                   friction,
                                   &slope,
                                   history ? &f.slope_scale : nullptr);
    return f;
  }
  static double MeanJ(const std::vector<MuFit>& fits, const CycleWindow& w) {
    double sum = 0;
    int n = 0;
    for (int k = w.first; k <= w.last && k < static_cast<int>(fits.size());
         ++k) {
      if (fits[k].converged) sum += fits[k].cost, ++n;
    }
    return n > 0 ? sum / n : INFINITY;
  }
};

}  // namespace

const AnalysisUnit& ScanFitAnalysis() {
  static const ScanFitUnit kUnit;
  return kUnit;
}

const AnalysisUnit& SpringFitAnalysis() {
  static const MuFitUnit<SpringFits> kUnit(
      {"mu_fit_spring",
       "mu-hat per cycle with k from P/S through the loading spring",
       {"the record", "the cycles", "the spring (as given)"},
       {}},
      false);
  return kUnit;
}

const AnalysisUnit& DepthFitAnalysis() {
  static const MuFitUnit<DepthFits> kUnit(
      {"mu_fit_depth",
       "mu-hat per cycle with k from the depth channel",
       {"the record", "the cycles", "the decision"},
       {}},
      true);
  return kUnit;
}

}  // namespace wearscar::fusion::internal
