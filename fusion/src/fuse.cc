#include "wearscar/fusion/fuse.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <tuple>

#include "assumptions.h"
#include "profile_choice.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/support/check.h"

namespace wearscar::fusion {
namespace {

bool CheckScanSlopeScale(double max_scale, std::string* why) {
  if (max_scale >= 1.0 && std::isfinite(max_scale)) return true;
  if (why) *why = "max_scan_slope_scale must be finite and >= 1";
  return false;
}

// RMS of k_force - k_scan over the gross-slip samples of cycles [first,
// last].
double KRmsDifference(const force::ForceRecord& record,
                      const ForceAnalysis& force,
                      const ScanAnalysis& scan,
                      int first,
                      int last,
                      const FuseOptions& options) {
  double sum2 = 0;
  long n = 0;
  FrictionFitOptions friction = options.analysis.friction;
  friction.k_from_depth = scan.profile_source == ProfileSource::kDepth;
  const ForceSlopes force_slopes(record, force.cycles, friction, first, last);
  for (int c = first; c <= last; ++c) {
    const CycleSamples kf = force_slopes.Gather(c);
    for (const SlipSamples* s : {&kf.forward, &kf.reverse}) {
      for (Eigen::Index i = 0; i < s->k.size(); ++i) {
        const double ks = scan.slope.At(s->x_mm[i]);
        if (!std::isfinite(ks)) continue;
        sum2 += (s->k[i] - ks) * (s->k[i] - ks);
        ++n;
      }
    }
  }
  return n > 0 ? std::sqrt(sum2 / n) : std::nan("");
}

}  // namespace

bool FuseOptions::IsValid(std::string* why) const {
  for (double f : notch_hz) {
    if (!(f > 0) || !std::isfinite(f)) {
      if (why) *why = "notch frequencies must be > 0 Hz";
      return false;
    }
  }
  if (cost_curve_points < 2 || cost_curve_points > 1000000) {
    if (why) *why = "cost_curve_points must be 2 to 10^6";
    return false;
  }
  return analysis.IsValid(why) && level.IsValid(why) && track.IsValid(why) &&
         profile.IsValid(why) && force_profile.IsValid(why) &&
         align.IsValid(why) && scan_slope.IsValid(why) &&
         verdict.IsValid(why) && warnings.IsValid(why) &&
         friction_map.IsValid(why) && track_history.IsValid(why) &&
         CheckScanSlopeScale(max_scan_slope_scale, why);
}

MismatchReport CompareSlopes(const force::ForceRecord& record,
                             const ForceAnalysis& force,
                             const ScanAnalysis* scan,
                             int first,
                             int last,
                             const FuseOptions& options,
                             bool force_slope_used) {
  MismatchReport r;
  r.first_cycle = first;
  r.last_cycle = last;
  auto stat = [&](auto value) {
    std::vector<double> v;
    for (int c = first; c <= last; ++c) v.push_back(value(c));
    return Summarise(v, 0);
  };
  // mu-hat and what is computed from it carry the fits' standard errors,
  // correlated over the cycles that share a slope; the classic COFs are
  // judged by their own scatter (SummariseSeries).
  auto series = [&](auto value) {
    std::vector<double> v;
    for (int c = first; c <= last; ++c) v.push_back(value(c));
    return SummariseSeries(v, 0, static_cast<int>(v.size()) - 1);
  };
  auto with_errors =
      [&](const std::vector<MuFit>& fits, int correlated, auto value) {
        std::vector<double> v, se;
        for (int c = first; c <= last; ++c) {
          const bool ok = fits[c].converged;
          v.push_back(ok ? value(c) : std::nan(""));
          se.push_back(ok ? fits[c].standard_error : std::nan(""));
        }
        return SummariseWithErrors(
            v, se, 0, static_cast<int>(v.size()) - 1, correlated);
      };
  // Without a profile in P (a dead weight) its fits are not used: empty.
  static const std::vector<MuFit> kUnused;
  const auto& ff = force_slope_used ? force.fit_force : kUnused;
  const int shared = force.correlated_cycles;
  if (force_slope_used) {
    r.mu_force = with_errors(ff, shared, [&](int c) { return ff[c].mu_hat; });
    r.cost_force = stat(
        [&](int c) { return ff[c].converged ? ff[c].cost : std::nan(""); });
  }
  r.mu_mean = series([&](int c) { return force.cof[c].mu_mean; });
  r.mu_energy = series([&](int c) { return force.cof[c].mu_energy_g; });
  // The classic COFs' own noise is small against mu-hat's (they average
  // Q/P over whole half cycles): the differences carry mu-hat's errors.
  if (force_slope_used) {
    r.mu_force_minus_mean = with_errors(
        ff, shared, [&](int c) { return ff[c].mu_hat - force.cof[c].mu_mean; });
    r.mu_force_minus_energy = with_errors(ff, shared, [&](int c) {
      return ff[c].mu_hat - force.cof[c].mu_energy_g;
    });
    r.split_force = SplitCost(ff, first, last);
  }
  // mu-hat minus mu_energy with the slope the verdict judges.
  auto method_difference = [&](const std::vector<MuFit>& fits) {
    std::vector<double> d(fits.size(), std::nan(""));
    for (int c = first; c <= last && c < static_cast<int>(fits.size()); ++c) {
      if (fits[c].converged) d[c] = fits[c].mu_hat - force.cof[c].mu_energy_g;
    }
    return MeanInterval(d, first, last);
  };
  r.method_difference = method_difference(ff);
  if (scan == nullptr) return r;
  r.has_scan = true;
  r.correlation = scan->alignment.correlation;
  r.correlation_noise_corrected = scan->alignment.correlation_noise_corrected;
  r.amplitude_ratio = scan->alignment.amplitude_ratio;
  r.amplitude_ratio_low = scan->alignment.amplitude_ratio_low;
  r.amplitude_ratio_high = scan->alignment.amplitude_ratio_high;
  const auto& fs = scan->fit_scan;
  r.split_scan = SplitCost(fs, first, last);
  if (r.cost_force.count == 0) r.method_difference = method_difference(fs);
  // One scan slope for every cycle: its errors are common to all.
  r.mu_scan =
      with_errors(fs, last - first + 1, [&](int c) { return fs[c].mu_hat; });
  r.cost_scan =
      stat([&](int c) { return fs[c].converged ? fs[c].cost : std::nan(""); });
  r.mu_force_minus_scan = r.mu_force.mean - r.mu_scan.mean;
  r.k_rms_difference =
      force_slope_used
          ? KRmsDifference(record, force, *scan, first, last, options)
          : std::nan("");
  if (scan->profile_source == ProfileSource::kFriction)
    r.force_profile_name = "the profile from the friction";
  if (scan->profile_source == ProfileSource::kDepth)
    r.force_profile_name = "the depth channel's profile";
  return r;
}

const char* SlopeChoiceName(SlopeChoice choice) {
  switch (choice) {
    case SlopeChoice::kForce:
      return "force";
    case SlopeChoice::kScan:
      return "scan";
    case SlopeChoice::kBoth:
      break;
  }
  return "both";
}

bool ParseSlopeChoice(const std::string& name, SlopeChoice* choice) {
  if (name == "force") {
    *choice = SlopeChoice::kForce;
  } else if (name == "scan") {
    *choice = SlopeChoice::kScan;
  } else if (name == "both") {
    *choice = SlopeChoice::kBoth;
  } else {
    return false;
  }
  return true;
}

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

// The rest of the scan side on a prepared scan: the force profile, the
// alignment, the slope in plate coordinates and mu-hat with it. Throws
// FusionError when the scan's profile cannot be aligned with the force's.
// `history` (null unless options.scan_slope_history) scales the scan's
// slope per cycle.
ScanAnalysis AnalyzeScan(const force::ForceRecord& record,
                         const ForceAnalysis& force,
                         ScanAnalysis s,
                         const FuseOptions& options,
                         const TrackHistory* history,
                         ProfileSource source) {
  const scan::HeightMap& map = s.levelled;
  // The last N cycles, but none of the running-in.
  ForceProfileOptions fpo = options.force_profile;
  const int nc = static_cast<int>(force.cycles.cycles.size());
  if (fpo.first_cycle < 0 && nc > 0) {
    fpo.first_cycle =
        std::max(nc - fpo.cycles, std::min(force.running_in.cycles, nc - 1));
    fpo.last_cycle = nc - 1;
  }
  s.profile_source = source;
  s.force_profile =
      source == ProfileSource::kFriction
          ? ComputeFrictionProfile(record, force.cycles, fpo)
      : source == ProfileSource::kDepth
          ? ComputeDepthProfile(
                record, force.cycles, fpo, options.analysis.friction.depth_sign)
          : ComputeForceProfile(record,
                                force.cycles,
                                options.analysis.friction.slope.spring_n_per_mm,
                                fpo);
  try {
    s.alignment = AlignProfiles(s.force_profile, s.profile, options.align);
  } catch (const FusionError& e) {
    // Name both files and the figures that decide the overlap: a wrong
    // pixel size shrinks the scan, a wrong x unit stretches the stroke.
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
  // The sphere's excursion over the complete cycles bounds the sliding
  // path: the scan beyond it is the groove's end walls.
  double stroke_min = -std::numeric_limits<double>::infinity();
  double stroke_max = std::numeric_limits<double>::infinity();
  if (nc > 0) {
    // Isolated gaps in x are allowed: finite samples only.
    std::tie(stroke_min, stroke_max) =
        force::CyclesXRange(record.x_mm, force.cycles);
  }
  s.slope = ScanSlopeInPlate(
      s.profile, s.alignment, options.scan_slope, stroke_min, stroke_max);
  if (options.slopes != SlopeChoice::kForce) {
    if (history != nullptr) s.slope_scale = ScanSlopeScale(*history, options);
    s.fit_scan = FitFrictionPerCycle(record,
                                     force.cycles,
                                     SlopeSource::kScan,
                                     options.analysis.friction,
                                     &s.slope,
                                     history ? &s.slope_scale : nullptr);
  } else {
    s.fit_scan.assign(force.cycles.cycles.size(), MuFit{});
    for (auto& f : s.fit_scan) f.message = "not fitted (force slope only)";
  }
  return s;
}

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

// What needs only the force side once it is analysed: the friction map
// and the LuGre fit (on a second core while the scan's slope is fitted).
struct ForceOnlyProducts {
  FrictionMap friction_map;
  std::optional<LugreFit> lugre;
};

ForceOnlyProducts ComputeForceOnlyProducts(const force::ForceRecord& record,
                                           const ForceAnalysis& force,
                                           int detail_cycle,
                                           const FuseOptions& options) {
  ForceOnlyProducts p;
  p.friction_map = ComputeFrictionMap(record,
                                      force.cycles,
                                      options.analysis.friction,
                                      force.running_in.cycles,
                                      options.friction_map);
  if (options.fit_lugre) {
    p.lugre = FitLugre(record, force.cycles, detail_cycle, options.lugre);
  }
  return p;
}

// The scan side on the prepared scan, or why it was not used: a scan that
// cannot serve (no track, no overlap with the stroke) does not lose the
// test; the force side stands, with a warning that says why (unless the
// scan's slope alone was asked for).
void AddScanSide(const force::ForceRecord& record,
                 std::future<ScanAnalysis> prepared,
                 const FuseOptions& options,
                 ProfileSource source,
                 TestResult* result) {
  try {
    // The spring's history scales the scan's slope only where P is the
    // profile.
    result->scan = AnalyzeScan(
        record,
        result->force,
        prepared.get(),
        options,
        options.scan_slope_history && source == ProfileSource::kSpring
            ? &result->track_history
            : nullptr,
        source);
  } catch (const std::exception& e) {
    if (options.slopes == SlopeChoice::kScan) throw;
    if (const auto* no_track = dynamic_cast<const NoTrackInMap*>(&e))
      result->unused_map = no_track->levelled;
    result->scan_skipped = fmt::format(
        "the scan was not used ({}); mu-hat and the verdict rest on k "
        "from P alone{}",
        e.what(),
        source == ProfileSource::kFriction
            ? ", which is noise where P carries no profile (a dead weight)"
            : "");
  }
}

// The comparison of the slopes, the verdict, the warnings and the wear,
// once both sides are analysed.
void CompareAndJudge(const force::ForceRecord& record,
                     const FuseOptions& options,
                     TestResult* result) {
  // Compare over the cycles the scan describes best: the force profile's
  // range with a scan, else everything after running-in.
  const int n = static_cast<int>(result->force.cycles.cycles.size());
  int first = result->force.running_in.cycles, last = n - 1;
  if (result->scan) {
    first = result->scan->force_profile.first_cycle;
    last = result->scan->force_profile.last_cycle;
  }
  const ScanAnalysis* scan = result->scan ? &*result->scan : nullptr;
  const bool from_spring = result->profile_source == ProfileSource::kSpring;
  const bool force_slope_used =
      from_spring || result->profile_source == ProfileSource::kDepth;
  result->mismatch = CompareSlopes(
      record, result->force, scan, first, last, options, force_slope_used);
  if (result->profile_source == ProfileSource::kDepth)
    result->mismatch.force_slope_name = "the depth";
  result->verdict = Judge(result->mismatch, options.verdict);
  // A doubted scan (possibly another test's) says nothing of this test's
  // elastic part or spring.
  const bool scan_doubted = !result->verdict.scan_doubt.empty();
  MismatchReport judged = result->mismatch;
  judged.has_scan = judged.has_scan && !scan_doubted;
  result->warnings = DataWarnings(result->force, judged, options.warnings);
  if (result->profile_source == ProfileSource::kFriction) {
    // k from P is not used: what its noise does to it is no warning.
    result->warnings.erase(std::remove_if(result->warnings.begin(),
                                          result->warnings.end(),
                                          [](const std::string& w) {
                                            return w.rfind("k from P", 0) == 0;
                                          }),
                           result->warnings.end());
  } else if (from_spring && !scan &&
             options.profile_from == ProfileSource::kAuto) {
    const double sig = result->p_slope_significance;
    // What fails with a slope that is noise is no finding about the test.
    if (sig < options.dead_weight_significance && !result->verdict.explained) {
      result->verdict.not_judged = fmt::format(
          "P does not vary along the stroke beyond its noise ({:.1f} "
          "standard errors), so k from P is noise if the rig has no spring, "
          "and nothing else gives the slope (no scan, no depth channel); "
          "give the track's scan or the depth channel. What k from P missed: "
          "{}",
          sig,
          fmt::join(result->verdict.reasons, "; "));
    }
    if (sig < options.dead_weight_significance) {
      result->warnings.push_back(fmt::format(
          "P does not vary along the stroke beyond its noise ({:.1f} "
          "standard errors): if the rig loads the ball with a dead weight, "
          "k from P is noise; with a scan of the track the profile is taken "
          "from the friction (--profile-from friction)",
          sig));
    }
  }
  for (std::string& w : internal::StatedButNotFound(record, result->force))
    result->warnings.push_back(std::move(w));
  if (scan != nullptr) {
    for (const std::string& w : scan->levelled.metadata.warnings)
      result->warnings.push_back("the scan: " + w);
  }
  if (!result->scan_skipped.empty())
    result->warnings.insert(result->warnings.begin(), result->scan_skipped);
  if (!result->verdict.scan_doubt.empty())
    result->warnings.insert(result->warnings.begin(),
                            result->verdict.scan_doubt);
  if (scan != nullptr && scan->track.low_confidence)
    result->warnings.push_back("the scan's track: " + scan->track.message);
  result->assumptions = internal::Assumptions(record, *result, options);
  const internal::ImpliedSpring implied =
      internal::SpringTheScanImplies(*result, options);
  const double s = options.analysis.friction.slope.spring_n_per_mm;
  if (from_spring && !options.spring_given && !scan_doubted &&
      implied.low > s * 1.15) {
    result->warnings.push_back(fmt::format(
        "the spring's stiffness was not given and the default {:g} N/mm is "
        "used, but the scan implies {:.3g} N/mm (95%: {:.3g}-{:.3g}) if all "
        "of P's waviness is the worn path: give --spring if that is the "
        "rig's (the verdict depends on it); if the default is right, part of "
        "P's waviness is elastic",
        s,
        implied.value,
        implied.low,
        implied.high));
  }
  result->wear = MeasureWear(
      record,
      result->force.cycles,
      scan ? std::optional<scan::Track>(scan->track) : std::nullopt);
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
  s.profile = scan::ExtractCentreline(map, s.track, options.profile);
  s.levelled = std::move(map);
  return s;
}

namespace {

// Periodic lines the drive does not make: a warning each, and a failed
// verdict says its excess may come from them.
void NoteLines(const force::ForceRecord& record, TestResult* result) {
  const auto& c = result->force.cycles.cycles;
  if (c.size() < 2) return;
  const double span = record.time_s[c.back().reverse.end - 1] -
                      record.time_s[c.front().forward.begin];
  if (!(span > 0)) return;
  result->periodic_lines =
      force::FindPeriodicLines(record, static_cast<double>(c.size()) / span);
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

TestResult AnalyzeTest(const force::ForceRecord& record,
                       std::future<ScanAnalysis> prepared_scan,
                       const std::string& scan_file,
                       const FuseOptions& given) {
  WEARSCAR_CHECK(record.IsConsistent(),
                 "AnalyzeTest needs channels of one length");
  if (!given.notch_hz.empty()) {
    // The lines asked for removed, the record analysed, and it said.
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
  const FuseOptions options = WithStatedSpring(given, record);
  std::string why;
  if (!options.IsValid(&why)) throw FusionError("fuse options: " + why);
  if (options.slopes == SlopeChoice::kScan && !prepared_scan.valid())
    throw FusionError("mu-hat with the scan slope only, but no scan given");
  const std::launch policy =
      options.parallel ? std::launch::async : std::launch::deferred;
  TestResult result;
  result.scan_file = scan_file;
  AnalysisOptions ao = options.analysis;
  ao.fit_force_slope = options.slopes != SlopeChoice::kScan;
  // The force side's fit on both cores where this test has them (its
  // second half of the cycles beside the first; the same fits).
  if (options.parallel) ao.friction.threads = std::max(ao.friction.threads, 2);
  if (record.has_depth()) {
    const auto& names = record.metadata.channel_names;
    result.depth_column = names.size() > 4 ? names[4] : "depth";
    result.depth_is_penetration = record.metadata.depth_is_penetration;
  }
  if (options.profile_from == ProfileSource::kDepth) {
    if (!record.has_depth()) {
      throw FusionError(
          "--profile-from depth, but the force file has no depth channel; "
          "name its column with --columns depth=NAME:UNIT");
    }
    ao.friction.k_from_depth = true;
    result.profile_source = ProfileSource::kDepth;
  }
  result.force = AnalyzeForce(record, ao);
  result.p_slope_significance = internal::ProfileSignificance(result.force);
  // auto with a depth channel logged: k from the depth when P's slope is
  // insignificant (no spring), or when P varies but not with the depth (its
  // variation is not the track's: Q's crosstalk into P on a dead weight).
  const bool auto_with_depth = options.profile_from == ProfileSource::kAuto &&
                               record.has_depth() && ao.fit_force_slope;
  const bool p_varies =
      result.p_slope_significance >= options.dead_weight_significance;
  if (auto_with_depth && p_varies) {
    result.spring_depth_agreement = internal::SpringDepthAgreement(
        record, result.force, ao.friction.slope.spring_n_per_mm);
  }
  if (auto_with_depth && (!p_varies || std::abs(result.spring_depth_agreement) <
                                           options.spring_depth_agreement)) {
    ao.friction.k_from_depth = true;
    result.profile_source = ProfileSource::kDepth;
    result.force = AnalyzeForce(record, ao);
  }
  // The depth's sign checked against the friction's profile (which needs
  // no sign): one running against it is turned over, and said.
  if (result.profile_source == ProfileSource::kDepth) {
    result.depth_agreement = internal::DepthAgreement(record, result.force);
    if (result.depth_agreement < -0.5) {
      ao.friction.depth_sign = -1.0;
      result.force = AnalyzeForce(record, ao);
    }
  }
  // What follows reads the force side's k where it came from.
  FuseOptions used = options;
  used.analysis.friction.k_from_depth = ao.friction.k_from_depth;
  used.analysis.friction.depth_sign = ao.friction.depth_sign;
  const FuseOptions& o_used = used;
  const int n = static_cast<int>(result.force.cycles.cycles.size());
  RefuseCyclesBeyondTheTest(o_used, n);
  result.detail_cycle = o_used.detail_cycle >= 0 && o_used.detail_cycle < n
                            ? o_used.detail_cycle
                            : n - 1;
  // Nothing below changes result.force, which this thread reads.
  std::future<ForceOnlyProducts> force_only = std::async(
      policy,
      [&record, &force = result.force, detail = result.detail_cycle, &o_used] {
        return ComputeForceOnlyProducts(record, force, detail, o_used);
      });
  // The track's history from the spring (before the scan: it may scale
  // the scan's slope).
  result.track_history =
      ComputeTrackHistory(record,
                          result.force.cycles,
                          o_used.analysis.friction.slope.spring_n_per_mm,
                          o_used.track_history);
  if (o_used.profile_from == ProfileSource::kFriction) {
    if (!prepared_scan.valid()) {
      throw FusionError(
          "--profile-from friction needs a scan of the track: the slope from "
          "the friction alone is circular, and nothing else gives k");
    }
    result.profile_source = ProfileSource::kFriction;
  }
  double spring_ratio = NAN;
  if (prepared_scan.valid()) {
    AddScanSide(record,
                std::move(prepared_scan),
                o_used,
                result.profile_source,
                &result);
    // auto: a rig whose P carries no profile (a dead weight) aligns the
    // scan with the friction's profile instead, and fits again.
    if (result.scan) spring_ratio = result.scan->alignment.amplitude_ratio;
    if (o_used.profile_from == ProfileSource::kAuto && result.scan &&
        result.profile_source == ProfileSource::kSpring &&
        internal::ChooseProfile(result, o_used) == ProfileSource::kFriction) {
      result.profile_source = ProfileSource::kFriction;
      ScanAnalysis prepared = *result.scan;
      std::promise<ScanAnalysis> again;
      again.set_value(std::move(prepared));
      result.scan.reset();
      AddScanSide(record,
                  again.get_future(),
                  o_used,
                  ProfileSource::kFriction,
                  &result);
    }
  }
  result.profile_reason =
      internal::ProfileReason(result,
                              o_used,
                              o_used.profile_from == ProfileSource::kAuto,
                              spring_ratio);
  CompareAndJudge(record, o_used, &result);
  if (o_used.find_periodic_lines) NoteLines(record, &result);
  ForceOnlyProducts p = force_only.get();
  result.friction_map = std::move(p.friction_map);
  result.lugre = std::move(p.lugre);
  const ScanAnalysis* scan = result.scan ? &*result.scan : nullptr;
  const int dc = result.detail_cycle;
  result.detail = ComputeDetailCycle(
      record,
      result.force,
      o_used.analysis.friction,
      dc,
      o_used.cost_curve_points,
      scan && dc >= 0 && dc < n ? &scan->fit_scan[dc] : nullptr,
      scan ? &scan->slope : nullptr,
      result.lugre ? &*result.lugre : nullptr);
  return result;
}

std::string Headline(const TestResult& r) {
  const MismatchReport& m = r.mismatch;
  const bool from_p = m.mu_force.count > 0;
  const Statistic& mu = from_p ? m.mu_force : m.mu_scan;
  if (mu.count == 0) {
    return "no mu to quote: no mu-hat was fitted (too few sliding samples "
           "per cycle; see the warnings)";
  }
  if (!r.verdict.not_judged.empty()) {
    return "no mu to quote: not judged, P carries no profile and nothing "
           "else gives the slope (no scan, no depth channel)";
  }
  if (!r.verdict.explained) {
    return fmt::format(
        "no mu to quote: not explained by wear-scar interaction, the model "
        "misses an effect (reasons below; `wearscar diagnose` names it); "
        "mu-hat {:.4f} and mu energy {:.4f} are for comparison only",
        mu.mean,
        m.mu_energy.mean);
  }
  const std::string interval =
      std::isfinite(mu.low)
          ? fmt::format(" (95%: {:.4f}-{:.4f})", mu.low, mu.high)
          : std::string();
  return fmt::format(
      "mu = {:.4f}{}: mu-hat, k from {}, cycles {}-{}; explained by wear-scar "
      "interaction",
      mu.mean,
      interval,
      from_p ? m.force_slope_name : std::string("the scan"),
      m.first_cycle + 1,
      m.last_cycle + 1);
}

}  // namespace wearscar::fusion
