#include "wearscar/fusion/fuse.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <future>
#include <limits>
#include <tuple>

#include "wearscar/fusion/assumptions.h"
#include "wearscar/fusion/compare_slopes.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/fusion/profile_decision.h"
#include "wearscar/support/check.h"

namespace wearscar::fusion {
namespace {

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

// How closely an alignment's scan profile follows the force side's: the
// waviness's correlation where it stands above its noise (what tells one
// track from another), else the whole profiles'.
double Follows(const Alignment& a, const VerdictOptions& v) {
  return a.waviness_to_noise >= v.min_waviness_to_noise &&
                 std::isfinite(a.waviness_correlation)
             ? a.waviness_correlation
             : a.correlation_noise_corrected;
}

// The premise that a rigid sphere of the radius given rides the scanned
// track, checked on which path the force side follows: the sphere's (kept
// unless the centreline follows it closer by more than `margin`) or the
// centreline's (a sphere that conforms to the track: k from the
// centreline, said).
void ChoosePath(const FuseOptions& options, ScanAnalysis* s) {
  Premise& p = s->rigid_sphere;
  p.rule = "k from the scan";
  p.statement = fmt::format(
      "a rigid sphere of radius {:g} mm rides the scanned track (its path, "
      "not the centreline, tilts the contact)",
      options.sphere.radius_mm);
  p.otherwise =
      "k from the scan is the centreline's slope: the force side's path "
      "follows the centreline, as a sphere that conforms to the track does";
  if (options.sphere.radius_mm <= 0) {
    p.evidence = "not checked: --sphere-radius 0 takes the centreline";
    s->centreline_used = true;
    return;
  }
  Alignment centre;
  try {
    centre = AlignProfiles(s->force_profile, s->centreline, options.align);
  } catch (const FusionError&) {
    p.state = Premise::State::kHeld;
    p.evidence = "the centreline could not be aligned";
    return;
  }
  constexpr double kMargin = 0.02;
  const double sphere = Follows(s->alignment, options.verdict);
  const double line = Follows(centre, options.verdict);
  p.evidence = fmt::format(
      "the force side's path follows the sphere's at r = {:.3f}, the "
      "centreline at r = {:.3f} ({})",
      sphere,
      line,
      s->alignment.waviness_to_noise >= options.verdict.min_waviness_to_noise
          ? "the waviness, corrected for noise"
          : "the whole profiles: the waviness is within its noise");
  if (line > sphere + kMargin) {
    p.state = Premise::State::kFailed;
    s->profile = s->centreline;
    s->alignment = centre;
    s->centreline_used = true;
  } else {
    p.state = Premise::State::kHeld;
    if (line > sphere - kMargin) s->centreline_alignment = centre;
  }
}

// The force side's profile over the compared cycles (the last N, none of
// the running-in) from `source`, aligned with the prepared scan's
// sphere path or centreline (ChoosePath). Throws FusionError naming both
// files when they cannot be aligned.
ScanAnalysis AlignScan(const force::ForceRecord& record,
                       const ForceAnalysis& force,
                       ScanAnalysis s,
                       const FuseOptions& options,
                       ProfileSource source,
                       double depth_sign) {
  ForceProfileOptions fpo = options.force_profile;
  const int nc = static_cast<int>(force.cycles.cycles.size());
  if (fpo.first_cycle < 0 && nc > 0) {
    fpo.first_cycle =
        std::max(nc - fpo.cycles, std::min(force.running_in.cycles, nc - 1));
    fpo.last_cycle = nc - 1;
  }
  s.force_profile =
      source == ProfileSource::kFriction
          ? ComputeFrictionProfile(record, force.cycles, fpo)
      : source == ProfileSource::kDepth
          ? ComputeDepthProfile(record, force.cycles, fpo, depth_sign)
          : ComputeForceProfile(record,
                                force.cycles,
                                options.analysis.friction.slope.spring_n_per_mm,
                                fpo);
  try {
    s.alignment = AlignProfiles(s.force_profile, s.profile, options.align);
    ChoosePath(options, &s);
  } catch (const FusionError& e) {
    // Name both files and the figures that decide the overlap: a wrong
    // pixel size shrinks the scan, a wrong x unit stretches the stroke.
    const scan::HeightMap& map = s.levelled;
    throw FusionError(fmt::format(
        "{}: {} (the scan: {} x {} pixels of {:.4g} um, {:.3g} x {:.3g} mm, "
        "track {:.3g} mm long; the stroke of {}: {:.3g} mm); check the scan's "
        "pixel size and the force file's x unit",
        map.metadata.source,
        e.what(),
        map.cols(),
        map.rows(),
        1e3 * map.dx_mm,
        map.cols() * map.dx_mm,
        map.rows() * map.dy_mm,
        s.track.length_mm,
        record.metadata.source,
        force.cycles.stroke_mm));
  }
  return s;
}

// The scan's slope in plate coordinates over the stroke.
PlateProfile ScanSlopeOverTheStroke(const force::ForceRecord& record,
                                    const ForceAnalysis& force,
                                    const FuseOptions& options,
                                    const ScanAnalysis& s) {
  // The sphere's excursion over the complete cycles bounds the sliding
  // path: the scan beyond it is the groove's end walls.
  double stroke_min = -std::numeric_limits<double>::infinity();
  double stroke_max = std::numeric_limits<double>::infinity();
  if (!force.cycles.cycles.empty()) {
    // Isolated gaps in x are allowed: finite samples only.
    std::tie(stroke_min, stroke_max) =
        force::CyclesXRange(record.x_mm, force.cycles);
  }
  return ScanSlopeInPlate(
      s.profile, s.alignment, options.scan_slope, stroke_min, stroke_max);
}

// mu-hat with the scan's slope (unless the force slope alone was asked
// for). `history` (null unless options.scan_slope_history) scales the
// scan's slope per cycle.
void FitScanSide(const force::ForceRecord& record,
                 const ForceAnalysis& force,
                 const FuseOptions& options,
                 const TrackHistory* history,
                 ScanAnalysis* s) {
  if (options.slopes == SlopeChoice::kForce) {
    s->fit_scan.assign(force.cycles.cycles.size(), MuFit{});
    for (auto& f : s->fit_scan) f.message = "not fitted (force slope only)";
    return;
  }
  if (history != nullptr) s->slope_scale = ScanSlopeScale(*history, options);
  // On both cores where the test has them (halves of the cycles).
  FrictionFitOptions friction = options.analysis.friction;
  if (options.parallel) friction.threads = std::max(friction.threads, 2);
  s->fit_scan = FitFrictionPerCycle(record,
                                    force.cycles,
                                    SlopeSource::kScan,
                                    friction,
                                    &s->slope,
                                    history ? &s->slope_scale : nullptr);
}

// The pipeline's figures for DecideProfile, each computed when first asked
// for, and what the decision needed kept for the analysis after it: the
// fit with k from P/S, the scan (prepared on another thread) and its
// alignment with P/S. Where the decision will ask for that alignment
// whatever it finds (a scan, no depth channel, the profile from the spring
// or auto), it is made on the scan's thread as soon as the scan is ready.
class PipelineEvidence : public ProfileEvidence {
 public:
  PipelineEvidence(const force::ForceRecord& record,
                   const ForceAnalysis& segmented,
                   const AnalysisOptions& analysis,
                   const FuseOptions& options,
                   std::future<ScanAnalysis> prepared,
                   std::shared_future<TrackHistory> history = {})
      : record_(record),
        segmented_(segmented),
        analysis_(analysis),
        options_(options),
        has_scan_(prepared.valid()),
        history_(std::move(history)) {
    // (The scan's thread holds `this`.)
    if (!has_scan_) return;
    const bool spring_sure =
        !record.has_depth() && (options.profile_from == ProfileSource::kAuto ||
                                options.profile_from == ProfileSource::kSpring);
    scan_side_ = std::async(
        spring_sure && options.parallel ? std::launch::async
                                        : std::launch::deferred,
        [this, spring_sure, o = options, p = std::move(prepared)]() mutable {
          ScanSide side;
          try {
            side.prepared = p.get();
          } catch (...) {
            side.scan_error = std::current_exception();
            return side;
          }
          if (spring_sure) AlignWithSpring(o, &side);
          return side;
        });
  }

  PipelineEvidence(const PipelineEvidence&) = delete;
  PipelineEvidence& operator=(const PipelineEvidence&) = delete;

  bool HasDepthChannel() const override { return record_.has_depth(); }
  std::string DepthColumn() const override {
    const auto& names = record_.metadata.channel_names;
    return names.size() > 4 ? names[4] : "depth";
  }
  bool DepthIsPenetration() const override {
    return record_.metadata.depth_is_penetration;
  }
  bool HasScan() const override { return has_scan_; }
  bool ForceSlopeFitted() const override { return analysis_.fit_force_slope; }
  double PSlopeSignificance() override {
    return ProfileSignificance(SpringFit());
  }
  int FittedCycles() override {
    return static_cast<int>(SpringFit().fit_force.size());
  }
  int CorrelatedCycles() override { return SpringFit().correlated_cycles; }
  double SpringDepthAgreement() override {
    return fusion::SpringDepthAgreement(
        record_, segmented_, analysis_.friction.slope.spring_n_per_mm);
  }
  double DepthAgreement() override {
    return fusion::DepthAgreement(record_, segmented_);
  }
  double SpringPathRatio() override {
    if (!history_.valid()) return NAN;
    const ForceProfileOptions last = LastCycles();
    return SpringOverFrictionPath(
        history_.get(), last.first_cycle, last.last_cycle);
  }
  double SpringAmplitudeRatio() override {
    const ScanSide& side = AlignedWithSpring();
    return side.spring ? side.spring->alignment.amplitude_ratio : NAN;
  }

  // The force side fitted with k where the decision put it.
  ForceAnalysis TakeForce(const AnalysisOptions& used) {
    if (used.friction.k_from_depth) {
      ForceAnalysis a = segmented_;
      FitForceSide(record_, used, &a);
      return a;
    }
    return std::move(SpringFit());
  }

  // The scan aligned with the decided profile; throws what its preparation
  // or its alignment threw. Requires HasScan().
  ScanAnalysis TakeAlignedScan(const ProfileDecision& d) {
    if (d.FromSpring()) {
      ScanSide& side = AlignedWithSpring();
      if (side.align_error) std::rethrow_exception(side.align_error);
      return std::move(*side.spring);
    }
    return AlignScan(
        record_, segmented_, Prepared(), options_, d.used, d.depth_sign);
  }

 private:
  // The prepared scan, or what its reading or preparation threw; its
  // alignment with P/S once made, or what that threw.
  struct ScanSide {
    std::optional<ScanAnalysis> prepared;
    std::exception_ptr scan_error;
    std::optional<ScanAnalysis> spring;
    std::exception_ptr align_error;
  };

  // The last cycles after running-in, as AlignScan compares (at most
  // ForceProfileOptions::cycles).
  ForceProfileOptions LastCycles() const {
    ForceProfileOptions o = options_.force_profile;
    const int n = static_cast<int>(segmented_.cycles.cycles.size());
    if (o.first_cycle < 0 && n > 0) {
      o.first_cycle =
          std::max(n - o.cycles, std::min(segmented_.running_in.cycles, n - 1));
      o.last_cycle = n - 1;
    }
    return o;
  }
  ForceAnalysis& SpringFit() {
    if (!spring_fit_) {
      spring_fit_ = segmented_;
      AnalysisOptions spring = analysis_;
      spring.friction.k_from_depth = false;
      FitForceSide(record_, spring, &*spring_fit_);
    }
    return *spring_fit_;
  }
  ScanSide& Side() {
    if (!side_) side_ = scan_side_.get();
    return *side_;
  }
  const ScanAnalysis& Prepared() {
    const ScanSide& side = Side();
    if (side.scan_error) std::rethrow_exception(side.scan_error);
    return *side.prepared;
  }
  // (`options` the pipeline's as they were before the decision: the
  // decision writes its choice into them while this may run.)
  void AlignWithSpring(const FuseOptions& options, ScanSide* side) const {
    if (side->spring || side->align_error) return;
    try {
      if (side->scan_error) std::rethrow_exception(side->scan_error);
      side->spring = AlignScan(record_,
                               segmented_,
                               *side->prepared,
                               options,
                               ProfileSource::kSpring,
                               1.0);
    } catch (...) {
      side->align_error = std::current_exception();
    }
  }
  ScanSide& AlignedWithSpring() {
    ScanSide& side = Side();
    AlignWithSpring(options_, &side);
    return side;
  }

  const force::ForceRecord& record_;
  const ForceAnalysis& segmented_;
  const AnalysisOptions& analysis_;
  const FuseOptions& options_;
  const bool has_scan_;
  std::shared_future<TrackHistory> history_;
  std::optional<ForceAnalysis> spring_fit_;
  std::future<ScanSide> scan_side_;
  std::optional<ScanSide> side_;
};

// A cycle asked for beyond the test's n complete cycles is refused, not
// replaced (messages count cycles from 1, as every output does).
void RefuseCyclesBeyondTheTest(const FuseOptions& options, int n) {
  for (auto [what, cycle] :
       {std::pair<const char*, int>{"the detail cycle", options.detail_cycle},
        {"the first compared cycle", options.force_profile.first_cycle},
        {"the last compared cycle", options.force_profile.last_cycle}}) {
    if (cycle >= n) {
      throw FusionError(fmt::format(
          "{} is cycle {}, but the test has {} complete cycles; expected 1 "
          "to {}",
          what,
          cycle + 1,
          n,
          n));
    }
  }
}

// The cycles quoted and compared: a range given; with a scan the force
// profile's (the last cycles after running-in: the scan shows the track
// after the last cycle, so the cycles nearest it); else every cycle after
// running-in.
CycleWindow QuotedWindow(const TestResult& r, const ScanAnalysis* scan) {
  const int n = static_cast<int>(r.force.cycles.cycles.size());
  const ForceProfileOptions& given = r.options.force_profile;
  const int running_in = r.force.running_in.cycles;
  CycleWindow w{running_in, n - 1, ""};
  if (given.first_cycle >= 0) {
    w.first = given.first_cycle;
    w.last = given.last_cycle >= 0 ? given.last_cycle : n - 1;
    w.why = "as given";
  } else {
    if (scan) {
      w.first = scan->force_profile.first_cycle;
      w.last = scan->force_profile.last_cycle;
    }
    w.why = w.first > running_in ? fmt::format("the last {} after running-in",
                                               w.last - w.first + 1)
            : running_in > 0     ? "every cycle after running-in"
                                 : "every cycle: no running-in";
    if (scan) w.why += ", whose track the scan shows";
  }
  return w;
}

// What the comparison and the wear take of the scan, made beside its fit:
// k's RMS difference over the quoted cycles (where the force side's k is
// judged) and the wear.
struct ScanSideBeside {
  std::optional<double> k_rms_difference;
  std::optional<Wear> wear;
};

// Where the profiles follow both paths alike (ChoosePath), the loops
// decide: mu-hat is fitted with each path's slope, and the one whose J
// over the quoted cycles is the lower kept (the tilt that reproduces Q).
void LetTheLoopsChoose(const force::ForceRecord& record,
                       const TestResult& result,
                       const TrackHistory* history,
                       ScanAnalysis* s) {
  const FuseOptions& o = result.options;
  ScanAnalysis c;
  c.profile = s->centreline;
  c.alignment = *s->centreline_alignment;
  c.slope = ScanSlopeOverTheStroke(record, result.force, o, c);
  FitScanSide(record, result.force, o, history, s);
  FitScanSide(record, result.force, o, history, &c);
  const CycleWindow w = QuotedWindow(result, s);
  auto mean_j = [&w](const std::vector<MuFit>& fits) {
    double sum = 0;
    int n = 0;
    for (int k = w.first; k <= w.last && k < static_cast<int>(fits.size());
         ++k) {
      if (fits[k].converged) sum += fits[k].cost, ++n;
    }
    return n > 0 ? sum / n : INFINITY;
  };
  const double sphere = mean_j(s->fit_scan), line = mean_j(c.fit_scan);
  Premise& p = s->rigid_sphere;
  p.evidence += fmt::format(
      "; the profiles follow both alike, so the loops decide: J {:.3f} with "
      "the sphere's path, {:.3f} with the centreline",
      sphere,
      line);
  s->centreline_alignment.reset();
  if (!(line < sphere)) return;
  p.state = Premise::State::kFailed;
  s->profile = s->centreline;
  s->alignment = c.alignment;
  s->slope = std::move(c.slope);
  s->fit_scan = std::move(c.fit_scan);
  s->slope_scale = std::move(c.slope_scale);
  s->centreline_used = true;
}

// The scan side aligned with the decided profile, or why it was not used:
// a scan that cannot serve (no track, no overlap with the stroke) does not
// lose the test; the force side stands, with a warning that says why
// (unless the scan's slope alone was asked for).
ScanSideBeside AddScanSide(const force::ForceRecord& record,
                           PipelineEvidence* evidence,
                           TestResult* result) {
  const FuseOptions& o = result->options;
  const ProfileDecision& d = result->profile;
  ScanSideBeside beside;
  std::exception_ptr beside_error;
  try {
    ScanAnalysis s = evidence->TakeAlignedScan(d);
    s.slope = ScanSlopeOverTheStroke(record, result->force, o, s);
    // The spring's history scales the scan's slope only where P is the
    // profile.
    const TrackHistory* history = o.scan_slope_history && d.FromSpring()
                                      ? &result->track_history
                                      : nullptr;
    const bool fitted =
        s.centreline_alignment.has_value() && o.slopes != SlopeChoice::kForce;
    if (fitted) LetTheLoopsChoose(record, *result, history, &s);
    // What needs the scan's slope and track, not its fit: beside the fit
    // (which reads the slope, and writes only its fits and scale).
    std::future<ScanSideBeside> made = std::async(
        o.parallel ? std::launch::async : std::launch::deferred,
        [&record, result, &s, &o] {
          const CycleWindow w = QuotedWindow(*result, &s);
          ScanSideBeside b;
          if (result->profile.ForceSlopeJudged()) {
            b.k_rms_difference = KRmsDifference(record,
                                                result->force,
                                                s.slope,
                                                o.analysis.friction,
                                                w.first,
                                                w.last,
                                                o.parallel);
          }
          b.wear = MeasureWear(record, result->force.cycles, s.track);
          return b;
        });
    if (!fitted) FitScanSide(record, result->force, o, history, &s);
    try {
      beside = made.get();
    } catch (...) {
      beside_error = std::current_exception();  // not the scan's failing
    }
    result->scan = std::move(s);
  } catch (const std::exception& e) {
    if (o.slopes == SlopeChoice::kScan) throw;
    if (const auto* no_track = dynamic_cast<const NoTrackInMap*>(&e))
      result->unused_map = no_track->levelled;
    result->scan_skipped = fmt::format(
        "the scan was not used ({}); mu-hat and the verdict rest on k "
        "from P alone{}",
        e.what(),
        d.FromFriction()
            ? ", which is noise where P carries no profile (a dead weight)"
            : "");
  }
  if (beside_error) std::rethrow_exception(beside_error);
  return beside;
}

// Without a scan, on a rig whose P may carry no profile (auto): what fails
// with a slope that is noise is no finding about the test.
void JudgeWithoutASlope(const FuseOptions& options, TestResult* result) {
  const double sig = result->profile.p_slope_significance;
  if (!(sig < options.dead_weight_significance)) return;
  if (!result->verdict.explained) {
    result->verdict.not_judged = fmt::format(
        "P does not vary along the stroke beyond its noise ({:.1f} "
        "standard errors), so k from P is noise if the rig has no spring, "
        "and nothing else gives the slope (no scan, no depth channel); "
        "give the track's scan or the depth channel. What k from P missed: "
        "{}",
        sig,
        fmt::join(result->verdict.reasons, "; "));
  }
  result->warnings.push_back(fmt::format(
      "P does not vary along the stroke beyond its noise ({:.1f} "
      "standard errors): if the rig loads the ball with a dead weight, "
      "k from P is noise; with a scan of the track the profile is taken "
      "from the friction (--profile-from friction)",
      sig));
}

// The warnings of a test once judged: the data's, the file's stated
// conditions the data contradict, the scan's, a doubted or unused scan
// first; then the assumptions and a default spring the scan contradicts.
void Warn(const force::ForceRecord& record, TestResult* result) {
  const FuseOptions& options = result->options;
  const ScanAnalysis* scan = result->scan ? &*result->scan : nullptr;
  // A doubted scan (possibly another test's) says nothing of this test's
  // elastic part or spring.
  const bool scan_doubted = !result->verdict.scan_doubt.empty();
  MismatchReport judged = result->mismatch;
  judged.has_scan = judged.has_scan && !scan_doubted;
  result->warnings = DataWarnings(result->force, judged, options.warnings);
  if (result->profile.FromSpring() && !scan &&
      options.profile_from == ProfileSource::kAuto)
    JudgeWithoutASlope(options, result);
  for (std::string& w : StatedButNotFound(record, result->force))
    result->warnings.push_back(std::move(w));
  if (scan != nullptr) {
    for (const std::string& w : scan->levelled.metadata.warnings)
      result->warnings.push_back("the scan: " + w);
  }
  if (!result->scan_skipped.empty())
    result->warnings.insert(result->warnings.begin(), result->scan_skipped);
  if (scan_doubted)
    result->warnings.insert(result->warnings.begin(),
                            result->verdict.scan_doubt);
  if (scan != nullptr && scan->track.low_confidence)
    result->warnings.push_back("the scan's track: " + scan->track.message);
  result->assumptions = Assumptions(record, *result, options);
  // A spring the data contradict, or one they cannot tell from an elastic
  // part, is said first: it changes what is quoted.
  const SpringCheck& spring = result->mismatch.spring;
  if (spring.contradicted) {
    result->warnings.insert(result->warnings.begin(),
                            spring.Describe(SpringOrigin(options)));
  } else if (spring.undecided) {
    result->warnings.insert(result->warnings.begin(),
                            spring.DescribeUndecided(SpringOrigin(options)));
  }
}

// P/S against the path the friction shows (SpringCheck): the stiffness
// and an elastic part. Only where k comes from P/S.
SpringCheck CheckTheSpring(const TestResult& r) {
  if (!r.profile.FromSpring()) return {};
  const FuseOptions& o = r.options;
  return CheckSpring(r.track_history,
                     r.force.running_in.cycles,
                     r.window.first,
                     r.window.last,
                     o.analysis.friction.slope.spring_n_per_mm,
                     o.spring_check);
}

// The comparison of the slopes, the verdict, the warnings and the wear,
// once both sides are analysed.
void CompareAndJudge(const force::ForceRecord& record,
                     const ScanSideBeside& beside,
                     TestResult* result) {
  const ScanAnalysis* scan = result->scan ? &*result->scan : nullptr;
  result->window = QuotedWindow(*result, scan);
  const int first = result->window.first, last = result->window.last;
  result->mismatch = CompareSlopes(record,
                                   result->force,
                                   scan,
                                   result->profile,
                                   first,
                                   last,
                                   result->options,
                                   beside.k_rms_difference);
  result->mismatch.spring = CheckTheSpring(*result);
  result->verdict = Judge(result->mismatch, result->options.verdict);
  Warn(record, result);
  result->wear = scan && beside.wear
                     ? *beside.wear
                     : MeasureWear(record, result->force.cycles, std::nullopt);
}

}  // namespace

ScanAnalysis PrepareScan(scan::HeightMap map, const FuseOptions& options) {
  ScanAnalysis s;
  s.level = scan::LevelHeightMap(&map, options.level);
  s.spikes_removed = scan::RemoveSpikes(&map, options.spikes);
  try {
    s.track = scan::FindTrack(map, options.track);
  } catch (const scan::NoTrackError& e) {
    throw NoTrackInMap(e, std::move(map));
  }
  s.centreline = scan::ExtractCentreline(map, s.track, options.profile);
  if (options.sphere.radius_mm > 0) {
    scan::TrackEndOptions ends;
    ends.sphere_radius_mm = options.sphere.radius_mm;
    s.ends = scan::FitTrackEnds(s.centreline, ends);
  }
  if (options.sphere.radius_mm > 0) {
    scan::SpherePathOptions sphere = options.sphere;
    sphere.extend_mm = options.profile.extend_mm;
    s.profile = scan::SpherePath(map, s.track, sphere);
  } else {
    s.profile = s.centreline;
  }
  s.levelled = std::move(map);
  return s;
}

namespace {

// Periodic lines in Q and P that the drive (its rate from the cycles)
// does not make.
std::vector<force::PeriodicLine> FindLines(const force::ForceRecord& record,
                                           const force::CycleSet& cycles) {
  const auto& c = cycles.cycles;
  if (c.size() < 2) return {};
  const double span = record.time_s[c.back().reverse.end - 1] -
                      record.time_s[c.front().forward.begin];
  if (!(span > 0)) return {};
  return force::FindPeriodicLines(record, static_cast<double>(c.size()) / span);
}

// The periodic lines found: a warning each, and a failed verdict says its
// excess may come from them.
void NoteLines(std::vector<force::PeriodicLine> lines, TestResult* result) {
  result->periodic_lines = std::move(lines);
  for (const force::PeriodicLine& l : result->periodic_lines) {
    result->warnings.push_back(fmt::format(
        "a periodic line at {} that the drive's motion does not make "
        "(mains pick-up, a resonance): it corrupts P's slope and the "
        "verdict; --notch {:.2f} removes it from Q and P",
        l.Describe(),
        l.frequency_hz));
  }
  if (!result->periodic_lines.empty() && !result->verdict.explained) {
    result->verdict.reasons.push_back(fmt::format(
        "the excess may come from the periodic line at {:.2f} Hz (see the "
        "warnings; analyse again with --notch {:.2f})",
        result->periodic_lines.front().frequency_hz,
        result->periodic_lines.front().frequency_hz));
  }
}

// AnalyzeTest on the record with the lines asked for removed, and it said.
TestResult AnalyzeNotched(const force::ForceRecord& record,
                          std::future<ScanAnalysis> prepared_scan,
                          const std::string& scan_file,
                          const FuseOptions& given) {
  force::ForceRecord notched = record;
  std::vector<std::string> removed;
  for (double f : given.notch_hz) {
    const auto [q, p] = force::NotchLine(&notched, f);
    removed.push_back(
        fmt::format("{:.2f} Hz (Q {:.4f} N, P {:.4f} N)", f, q, p));
  }
  FuseOptions inner = given;
  inner.notch_hz.clear();
  TestResult r =
      AnalyzeTest(notched, std::move(prepared_scan), scan_file, inner);
  r.assumptions.push_back(fmt::format(
      "notched (--notch): a sinusoid fitted in blocks of about 2 s removed "
      "from Q and P at {}",
      fmt::join(removed, ", ")));
  return r;
}

// The force side's options as this test's analysis runs them.
AnalysisOptions ForceOptions(const FuseOptions& options) {
  AnalysisOptions ao = options.analysis;
  ao.fit_force_slope = options.slopes != SlopeChoice::kScan;
  // The force side's fit on both cores where this test has them (its
  // second half of the cycles beside the first; the same fits).
  if (options.parallel) ao.friction.threads = std::max(ao.friction.threads, 2);
  return ao;
}

// The friction map on a thread of its own where the test has cores. Its k
// is P/S's or the depth's: `options` by value, since the decision writes
// its choice into the result's while a map made beside it runs.
std::future<FrictionMap> StartFrictionMap(const force::ForceRecord& record,
                                          const ForceAnalysis& force,
                                          FuseOptions options) {
  return std::async(
      options.parallel ? std::launch::async : std::launch::deferred,
      [&record, &force, o = std::move(options)] {
        return ComputeFrictionMap(record,
                                  force.cycles,
                                  o.analysis.friction,
                                  force.running_in.cycles,
                                  o.friction_map);
      });
}

// The cycle detailed: the one asked for, else the last.
int DetailedCycle(const FuseOptions& options, int cycles) {
  return options.detail_cycle >= 0 && options.detail_cycle < cycles
             ? options.detail_cycle
             : cycles - 1;
}

// After the profile's decision: the force side, then the scan side beside
// the products that need only the force side, the comparison and verdict,
// the lines and the detail cycle.
void AnalyzeDecided(const force::ForceRecord& record,
                    PipelineEvidence* evidence,
                    AnalysisOptions ao,
                    std::future<std::vector<force::PeriodicLine>> lines,
                    std::future<FrictionMap> map,
                    std::shared_future<TrackHistory> history,
                    std::future<std::optional<LugreFit>> lugre,
                    TestResult* result) {
  const FuseOptions& o = result->options;
  ao.friction.k_from_depth = o.analysis.friction.k_from_depth;
  ao.friction.depth_sign = o.analysis.friction.depth_sign;
  result->force = evidence->TakeForce(ao);
  const int n = static_cast<int>(result->force.cycles.cycles.size());
  RefuseCyclesBeyondTheTest(o, n);
  result->detail_cycle = DetailedCycle(o, n);
  // Nothing below changes result->force, which this thread reads. The
  // friction map, unless it runs already, beside the scan side's fit (the
  // cores share the threads out).
  if (!map.valid()) map = StartFrictionMap(record, result->force, o);
  // The track's history (before the scan: it may scale the scan's slope).
  result->track_history = history.get();
  ScanSideBeside beside;
  if (evidence->HasScan()) beside = AddScanSide(record, evidence, result);
  CompareAndJudge(record, beside, result);
  NoteLines(lines.get(), result);
  result->friction_map = map.get();
  result->lugre = lugre.get();
  const ScanAnalysis* scan = result->scan ? &*result->scan : nullptr;
  const int dc = result->detail_cycle;
  result->detail = ComputeDetailCycle(
      record,
      result->force,
      o.analysis.friction,
      dc,
      o.cost_curve_points,
      scan && dc >= 0 && dc < n ? &scan->fit_scan[dc] : nullptr,
      scan ? &scan->slope : nullptr,
      result->lugre ? &*result->lugre : nullptr);
}

}  // namespace

TestResult AnalyzeTest(const force::ForceRecord& record,
                       std::optional<scan::HeightMap> height_map,
                       const FuseOptions& options) {
  WEARSCAR_CHECK(!height_map || height_map->IsConsistent(),
                 "AnalyzeTest needs a consistent map");
  std::string why;
  if (!options.IsValid(&why)) throw FusionError("fuse options: " + why);
  std::future<ScanAnalysis> prepared;
  std::string scan_file;
  if (height_map) {
    // The scan's preparation needs nothing of the force record: on a
    // second core while the force side is analysed (deferred: run where
    // its result is asked for).
    scan_file = height_map->metadata.source;
    prepared = std::async(
        options.parallel ? std::launch::async : std::launch::deferred,
        [&options](scan::HeightMap m) {
          return PrepareScan(std::move(m), options);
        },
        std::move(*height_map));
  }
  return AnalyzeTest(record, std::move(prepared), scan_file, options);
}

ProfileDecision DecideForceProfile(const force::ForceRecord& record,
                                   const FuseOptions& given) {
  const FuseOptions options = WithStatedSpring(given, record);
  const AnalysisOptions ao = ForceOptions(options);
  const ForceAnalysis segmented = SegmentForce(record, ao);
  PipelineEvidence evidence(
      record, segmented, ao, options, std::future<ScanAnalysis>());
  return DecideProfile(&evidence, options);
}

FuseOptions WithStatedSpring(const FuseOptions& options,
                             const force::ForceRecord& record) {
  FuseOptions o = options;
  if (options.spring_given) return o;
  for (const force::StatedFact& f : record.metadata.stated) {
    // Plausible loading springs: 0.01 N/mm (a soft coil) to 1e5 N/mm (an
    // implausible one is a warning, StatedButNotFound).
    if (f.what != "spring" || !(f.value >= 0.01 && f.value <= 1e5)) continue;
    o.analysis.friction.slope.spring_n_per_mm = f.value;
    o.spring_given = true;
    o.spring_stated = fmt::format("line {}: '{}'", f.line_number, f.line);
    break;
  }
  return o;
}

namespace {

// A test without a scan whose P/S the friction's path scales by a spring
// other than the one used (or by one it cannot tell from an elastic part):
// k from P, the only slope, is taken at the stiffness that carries P/S
// onto the path (both readings leave the path the friction shows), the
// first pass's finding said first.
TestResult AtTheFrictionsSpring(const force::ForceRecord& record,
                                TestResult first) {
  const SpringCheck& c = first.mismatch.spring;
  if (!(c.contradicted || c.undecided) ||
      !first.options.spring_from_friction.empty() ||
      !(c.ImpliedStiffness() > 0))
    return first;
  const std::string how = SpringOrigin(first.options);
  FuseOptions again = first.options;
  again.spring_before_friction_n_per_mm =
      first.options.analysis.friction.slope.spring_n_per_mm;
  again.analysis.friction.slope.spring_n_per_mm = c.ImpliedStiffness();
  again.spring_from_friction =
      c.contradicted ? c.Describe(how) : c.DescribeUndecided(how);
  TestResult r =
      AnalyzeTest(record, std::future<ScanAnalysis>(), first.scan_file, again);
  r.warnings.insert(r.warnings.begin(), again.spring_from_friction);
  return r;
}

}  // namespace

TestResult AnalyzeTest(const force::ForceRecord& record,
                       std::future<ScanAnalysis> prepared_scan,
                       const std::string& scan_file,
                       const FuseOptions& given) {
  WEARSCAR_CHECK(record.IsConsistent(),
                 "AnalyzeTest needs channels of one length");
  if (!given.notch_hz.empty())
    return AnalyzeNotched(record, std::move(prepared_scan), scan_file, given);
  TestResult result;
  result.options = WithStatedSpring(given, record);
  std::string why;
  if (!result.options.IsValid(&why)) throw FusionError("fuse options: " + why);
  if (result.options.slopes == SlopeChoice::kScan && !prepared_scan.valid())
    throw FusionError("mu-hat with the scan slope only, but no scan given");
  result.scan_file = scan_file;
  const AnalysisOptions ao = ForceOptions(result.options);
  // Cycles, gross slip, the classic COFs and the running-in need no slope;
  // the profile's decision then asks for what it needs (the fit with k from
  // P/S, the depth's agreement, the scan's alignment) and the analysis
  // runs once with k where it put it.
  const ForceAnalysis segmented = SegmentForce(record, ao);
  // The search for periodic lines needs only the record and the drive's
  // rate: beside the rest, on a core of its own when there is one.
  std::future<std::vector<force::PeriodicLine>> lines = std::async(
      result.options.parallel ? std::launch::async : std::launch::deferred,
      [&record, &segmented, find = result.options.find_periodic_lines] {
        return find ? FindLines(record, segmented.cycles)
                    : std::vector<force::PeriodicLine>();
      });
  // The track's history from the spring and the LuGre fit of the detail
  // cycle need only the cycles and their options, which the decision does
  // not change: beside it too.
  const std::launch beside =
      result.options.parallel ? std::launch::async : std::launch::deferred;
  std::shared_future<TrackHistory> history = std::async(
      beside,
      [&record,
       &segmented,
       spring = result.options.analysis.friction.slope.spring_n_per_mm,
       options = result.options.track_history] {
        return ComputeTrackHistory(record, segmented.cycles, spring, options);
      });
  std::future<std::optional<LugreFit>> lugre = std::async(
      beside,
      [&record,
       &segmented,
       detail = DetailedCycle(result.options,
                              static_cast<int>(segmented.cycles.cycles.size())),
       fit = result.options.fit_lugre,
       options = result.options.lugre] {
        return fit ? std::optional<LugreFit>(
                         FitLugre(record, segmented.cycles, detail, options))
                   : std::nullopt;
      });
  // The map's k is P/S's unless the decision puts it on a depth channel:
  // without one, the map is made beside the decision.
  std::future<FrictionMap> map;
  if (!record.has_depth())
    map = StartFrictionMap(record, segmented, result.options);
  PipelineEvidence evidence(
      record, segmented, ao, result.options, std::move(prepared_scan), history);
  result.profile = DecideProfile(&evidence, result.options);
  FrictionFitOptions& friction = result.options.analysis.friction;
  friction.k_from_depth = result.profile.FromDepth();
  friction.depth_sign = result.profile.FromDepth() ? result.profile.depth_sign
                                                   : friction.depth_sign;
  AnalyzeDecided(record,
                 &evidence,
                 ao,
                 std::move(lines),
                 std::move(map),
                 history,
                 std::move(lugre),
                 &result);
  if (!evidence.HasScan())
    return AtTheFrictionsSpring(record, std::move(result));
  return result;
}

}  // namespace wearscar::fusion
