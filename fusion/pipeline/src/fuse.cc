#include "wearscar/fusion/fuse.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <future>
#include <limits>
#include <optional>
#include <tuple>

#include "pipeline_evidence.h"
#include "wearscar/force/periodic.h"
#include "wearscar/fusion/assumptions.h"
#include "wearscar/fusion/compare_slopes.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/fusion/profile_decision.h"
#include "wearscar/fusion/scan_identity.h"
#include "wearscar/fusion/unit.h"
#include "wearscar/support/check.h"

namespace wearscar::fusion {

using internal::AlignScan;
using internal::PipelineEvidence;
using internal::ScanSlopeOverTheStroke;
using internal::SpringFitsFuture;

namespace {

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

// What the comparison takes of the scan, made beside its fit: k's RMS
// difference over the quoted cycles (where the force side's k is judged).
struct ScanSideBeside {
  std::optional<double> k_rms_difference;
};

// Where the profiles follow both paths alike (ChoosePath), the loops
// decide: the scan's fit (the unit "mu_fit_scan") fitted mu-hat with each
// path's slope and kept the one whose J over the quoted cycles is the
// lower (the tilt that reproduces Q); the scan side takes that path.
void TakeThePathTheLoopsChose(const ScanFits& fits, ScanAnalysis* s) {
  Premise& p = s->rigid_sphere;
  p.evidence += fmt::format(
      "; the profiles follow both alike, so the loops decide: J {:.3f} with "
      "the sphere's path, {:.3f} with the centreline",
      fits.j_sphere,
      fits.j_centreline);
  if (fits.centreline) {
    p.state = Premise::State::kFailed;
    s->profile = s->centreline;
    // (In this tie the two paths' waviness is alike: the runner-up sought
    // on the sphere's stands for both.)
    Alignment c = *s->centreline_alignment;
    c.waviness_runner_up = s->alignment.waviness_runner_up;
    c.waviness_runner_up_shift_mm = s->alignment.waviness_runner_up_shift_mm;
    s->alignment = c;
    s->slope = std::move(*s->centreline_slope);
    s->centreline_used = true;
  }
  s->centreline_alignment.reset();
  s->centreline_slope.reset();
}

// k's RMS difference over the quoted cycles where the force side's k is
// judged, on a thread of its own where the test has cores.
std::future<ScanSideBeside> BesideTheScansFit(const force::ForceRecord& record,
                                              const TestResult& result) {
  return std::async(
      result.options.parallel ? std::launch::async : std::launch::deferred,
      [&record, &result] {
        ScanSideBeside b;
        if (!result.profile.ForceSlopeJudged()) return b;
        const FuseOptions& o = result.options;
        const CycleWindow w = QuotedWindow(result, &*result.scan);
        b.k_rms_difference = KRmsDifference(record,
                                            result.force,
                                            result.scan->slope,
                                            o.analysis.friction,
                                            w.first,
                                            w.last,
                                            o.parallel);
        return b;
      });
}

// The scan side aligned with the decided profile and its slope, mu-hat
// with it (the unit "mu_fit_scan", beside k's RMS difference), or why it
// was not used: a scan that cannot serve (no track, no overlap with the
// stroke) does not lose the test; the force side stands, with a warning
// that says why (unless the scan's slope alone was asked for).
ScanSideBeside AddScanSide(const force::ForceRecord& record,
                           PipelineEvidence* evidence,
                           UnitRunner* units,
                           TestResult* result) {
  const FuseOptions& o = result->options;
  const ProfileDecision& d = result->profile;
  ScanSideBeside beside;
  std::exception_ptr beside_error;
  try {
    ScanAnalysis s = evidence->TakeAlignedScan(d);
    s.slope = ScanSlopeOverTheStroke(record, result->force, o, s);
    const bool tie =
        s.centreline_alignment.has_value() && o.slopes != SlopeChoice::kForce;
    if (tie) {
      ScanAnalysis c;
      c.profile = s.centreline;
      c.alignment = *s.centreline_alignment;
      s.centreline_slope = ScanSlopeOverTheStroke(record, result->force, o, c);
    }
    result->scan = std::move(s);
    units->Start(UnitStage::kScanned, result->force, o, result);
    if (tie) {
      units->CollectOne("mu_fit_scan", &result->units);
      TakeThePathTheLoopsChose(result->units.Get<ScanFits>(), &*result->scan);
    }
    // What needs the scan's slope, not its fit, beside the fit (which runs
    // here, reads the scan side and writes nothing of it).
    std::future<ScanSideBeside> made = BesideTheScansFit(record, *result);
    std::exception_ptr fit_error;
    try {
      units->CollectOne("mu_fit_scan", &result->units);
    } catch (...) {
      fit_error = std::current_exception();
    }
    try {
      beside = made.get();
    } catch (...) {
      beside_error = std::current_exception();  // not the scan's failing
    }
    if (fit_error) std::rethrow_exception(fit_error);
  } catch (const std::exception& e) {
    if (o.slopes == SlopeChoice::kScan) throw;
    result->scan.reset();
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
  if (ClassifyPSlope(sig, options) != PSlope::kNoise) return;
  if (!result->verdict.explained) {
    result->verdict.not_judged = fmt::format(
        "{}, so k from P is noise if the rig has no spring, and nothing "
        "else gives the slope (no scan, no depth channel); give the track's "
        "scan or the depth channel. What k from P missed: {}",
        PSlopeNoiseText(sig),
        fmt::join(result->verdict.reasons, "; "));
  }
  result->warnings.push_back(fmt::format(
      "{}: if the rig loads the ball with a dead weight, k from P is noise; "
      "with a scan of the track the profile is taken from the friction "
      "(--profile-from friction)",
      PSlopeNoiseText(sig)));
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
  result->warnings = DataWarnings(
      result->force, result->ForceFits(), judged, options.warnings);
  if (result->profile.FromSpring() && !scan &&
      options.profile_from == ProfileSource::kAuto)
    JudgeWithoutASlope(options, result);
  for (std::string& w : StatedButNotFound(record, result->force))
    result->warnings.push_back(std::move(w));
  if (scan != nullptr) {
    for (const std::string& w : scan->Levelled().metadata.warnings)
      result->warnings.push_back("the scan: " + w);
  }
  if (!result->scan_skipped.empty())
    result->warnings.insert(result->warnings.begin(), result->scan_skipped);
  if (scan_doubted)
    result->warnings.insert(result->warnings.begin(),
                            result->verdict.scan_doubt);
  // (A short stroke's track is said among the assumptions.)
  if (scan != nullptr && scan->track.low_confidence &&
      !ShortStrokesTrack(scan->track,
                         result->force.cycles.stroke_mm,
                         result->mismatch.scan_pixel_mm,
                         options.track,
                         options.verdict))
    result->warnings.push_back("the scan's track: " + scan->track.message);
  result->assumptions = Assumptions(record, *result, options);
}

// The comparison of the slopes, the units that read it (the spring
// check), the verdict and the warnings, once both sides are analysed. The
// units started before are collected with them.
void CompareAndJudge(const force::ForceRecord& record,
                     const ScanSideBeside& beside,
                     UnitRunner* units,
                     TestResult* result) {
  const ScanAnalysis* scan = result->scan ? &*result->scan : nullptr;
  result->window = QuotedWindow(*result, scan);
  const int first = result->window.first, last = result->window.last;
  result->mismatch = CompareSlopes(record,
                                   result->force,
                                   result->ForceFits(),
                                   result->units.Get<ClassicCofs>(),
                                   scan,
                                   result->ScanSlopeFits(),
                                   result->profile,
                                   first,
                                   last,
                                   result->options,
                                   beside.k_rms_difference);
  units->Start(UnitStage::kCompared, result->force, result->options, result);
  units->Collect(&result->units);
  result->mismatch.spring_check = result->units.Share<SpringCheck>();
  result->mismatch.scan_identity = result->units.Share<ScanIdentity>();
  result->mismatch.screen = result->units.Share<ScreenFinding>();
  result->verdict = Judge(result->mismatch, result->options.verdict);
  Warn(record, result);
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
  s.levelled = std::make_shared<const scan::HeightMap>(std::move(map));
  return s;
}

namespace {

// AnalyzeTest on the record with the lines of given.notch_hz removed, and
// it said: lines given (--notch), or `found` in the record.
TestResult AnalyzeNotched(const force::ForceRecord& record,
                          std::future<ScanAnalysis> prepared_scan,
                          const std::string& scan_file,
                          const FuseOptions& given,
                          bool found = false) {
  force::ForceRecord notched = record;
  std::vector<std::string> removed;
  for (double f : given.notch_hz) {
    const auto [q, p] = force::NotchLine(&notched, f);
    removed.push_back(
        fmt::format("{:.2f} Hz (Q {:.4f} N, P {:.4f} N)", f, q, p));
  }
  FuseOptions inner = given;
  inner.notch_hz.clear();
  // (The record notched, the lines given are the only ones removed.)
  inner.notch_found_lines = false;
  TestResult r =
      AnalyzeTest(notched, std::move(prepared_scan), scan_file, inner);
  // What was removed, for result.json's options and the diagnosis.
  r.options.notch_hz = given.notch_hz;
  r.options.notch_found_lines = given.notch_found_lines;
  r.assumptions.push_back(fmt::format(
      "notched ({}): a sinusoid fitted in blocks of about 2 s removed from Q "
      "and P at {}",
      found ? "lines found in the record; --notch none keeps them" : "--notch",
      fmt::join(removed, ", ")));
  return r;
}

// The prepared scan for one pass of a test that a second pass may follow
// (the lines found removed): each pass reads its own copy.
std::future<ScanAnalysis> PassScan(const std::shared_future<ScanAnalysis>& s) {
  if (!s.valid()) return {};
  return std::async(std::launch::deferred, [s] { return s.get(); });
}

// A test whose Q and P carry periodic lines the drive does not make (mains
// pick-up at the drive's harmonic stands still along the stroke and reads
// as the track's slope in P: 0.02 N at 60 Hz is a slope of about 0.04 at
// the paper's speed) is analysed again with them removed, as --notch would,
// said first; null where none was found or the options keep them.
std::optional<TestResult> WithoutTheLinesFound(
    const force::ForceRecord& record,
    const std::shared_future<ScanAnalysis>& scan,
    const FuseOptions& given,
    const TestResult& first) {
  using Lines = std::vector<force::PeriodicLine>;
  const Lines* lines = first.units.Find<Lines>();
  if (!given.notch_found_lines || lines == nullptr || lines->empty())
    return std::nullopt;
  FuseOptions again = given;
  std::vector<std::string> found;
  for (const force::PeriodicLine& l : *lines) {
    again.notch_hz.push_back(l.frequency_hz);
    found.push_back(l.Describe());
  }
  TestResult r =
      AnalyzeNotched(record, PassScan(scan), first.scan_file, again, true);
  // result.json lists the lines of the record as read, those removed too.
  r.units.Put<Lines>("periodic_lines", first.units.Share<Lines>());
  r.warnings.insert(
      r.warnings.begin(),
      fmt::format(
          "{} {} that the drive's motion does not make (mains "
          "pick-up, a resonance) removed from Q and P before the "
          "analysis, as --notch {:.2f} would: such a line reads as "
          "the track's slope in P; --notch none keeps it",
          lines->size() > 1 ? "periodic lines at" : "a periodic line at",
          fmt::join(found, " and "),
          fmt::join(again.notch_hz, ",")));
  return r;
}

// After the profile's decision: the force side, then the scan side beside
// the units that need only the force side, the comparison and verdict,
// and the units that read the whole result (the detail cycle among them).
void AnalyzeDecided(const force::ForceRecord& record,
                    PipelineEvidence* evidence,
                    const ForceAnalysis& segmented,
                    UnitRunner* units,
                    TestResult* result) {
  const FuseOptions& o = result->options;
  result->force = segmented;
  const int n = static_cast<int>(result->force.cycles.cycles.size());
  RefuseCyclesBeyondTheTest(o, n);
  result->detail_cycle = o.DetailedCycle(n);
  // Nothing below changes result->force, which this thread reads. The
  // units that read the decided k (the fits with the depth channel's, the
  // friction map on a depth channel) beside the scan side's fit (the cores
  // share the threads out).
  units->Start(UnitStage::kDecided, result->force, o);
  // The force side's fits with k where the decision put it (and P/S's,
  // which it read), stored before the comparison reads them.
  units->CollectOne("mu_fit_spring", &result->units);
  units->CollectOne("mu_fit_depth", &result->units);
  ScanSideBeside beside;
  if (evidence->HasScan())
    beside = AddScanSide(record, evidence, units, result);
  CompareAndJudge(record, beside, units, result);
  units->Start(UnitStage::kJudged, result->force, o, result);
  units->Collect(&result->units);
  SayWhatTheUnitsFound(result);
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
  const AnalysisOptions ao = options.ForceSide();
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
  const SpringCheck& c = first.mismatch.Spring();
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
  // Where lines found would be removed, each pass reads its own copy of the
  // prepared scan.
  std::shared_future<ScanAnalysis> shared_scan;
  if (given.notch_found_lines && prepared_scan.valid()) {
    shared_scan = prepared_scan.share();
    prepared_scan = PassScan(shared_scan);
  }
  TestResult result;
  result.options = WithStatedSpring(given, record);
  std::string why;
  if (!result.options.IsValid(&why)) throw FusionError("fuse options: " + why);
  if (result.options.slopes == SlopeChoice::kScan && !prepared_scan.valid())
    throw FusionError("mu-hat with the scan slope only, but no scan given");
  result.scan_file = scan_file;
  const AnalysisOptions ao = result.options.ForceSide();
  // Cycles, gross slip, the classic COFs and the running-in need no slope;
  // the profile's decision then asks for what it needs (the fit with k from
  // P/S, the depth's agreement, the scan's alignment) and the analysis
  // runs once with k where it put it.
  ForceAnalysis segmented = SegmentCycles(record, ao);
  UnitRunner units(record, result.options.parallel);
  // The units on the cycles alone (the classic COFs), collected first: the
  // running-in is detected on the COFs' mean method.
  units.Start(UnitStage::kSegmented, segmented, result.options);
  units.Collect(&result.units);
  const ClassicCofs* classic = result.units.Find<ClassicCofs>();
  WEARSCAR_CHECK(classic != nullptr,
                 "the classic COFs' unit must run on every test");
  FindRunningIn(record, ao, *classic, &segmented);
  // The units that need only the record and its cycles (the periodic
  // lines, LuGre on the detail cycle, the friction map without a depth
  // channel) beside the rest, on cores of their own where there are.
  units.Start(UnitStage::kCycles, segmented, result.options);
  // The track's history from the spring, a unit of those, is read by the
  // decision before they are collected.
  std::shared_future<TrackHistory> history =
      std::async(std::launch::deferred, [&units] {
        const auto h = units.Await<TrackHistory>("track_history");
        WEARSCAR_CHECK(h != nullptr,
                       "the track's history unit must run on every test");
        return *h;
      });
  // So are the fits with k from P/S (P's slope's significance).
  const SpringFitsFuture spring = std::async(std::launch::deferred, [&] {
    auto f = units.Await<SpringFits>("mu_fit_spring");
    if (!f) f = result.units.Share<SpringFits>();  // collected already
    WEARSCAR_CHECK(f != nullptr, "the fits with k from P/S must run");
    return f;
  });
  PipelineEvidence evidence(record,
                            segmented,
                            ao,
                            result.options,
                            std::move(prepared_scan),
                            history,
                            spring);
  result.profile = DecideProfile(&evidence, result.options);
  ApplyProfile(result.profile, &result.options.analysis.friction);
  AnalyzeDecided(record, &evidence, segmented, &units, &result);
  if (auto notched = WithoutTheLinesFound(record, shared_scan, given, result))
    return std::move(*notched);
  if (!evidence.HasScan())
    return AtTheFrictionsSpring(record, std::move(result));
  return result;
}

}  // namespace wearscar::fusion
