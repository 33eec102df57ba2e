#pragma once

#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "wearscar/force/periodic.h"
#include "wearscar/fusion/align.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/detail_cycle.h"
#include "wearscar/fusion/friction_map.h"
#include "wearscar/fusion/lugre.h"
#include "wearscar/fusion/track_history.h"
#include "wearscar/fusion/verdict.h"
#include "wearscar/fusion/wear.h"
#include "wearscar/scan/height_map.h"
#include "wearscar/scan/level.h"
#include "wearscar/scan/track.h"

namespace wearscar::fusion {

// Everything that shapes one test's analysis, with the paper's defaults.
enum class SlopeChoice { kForce, kScan, kBoth };

// "force", "scan", "both"; false for anything else.
bool ParseSlopeChoice(const std::string& name, SlopeChoice* choice);
const char* SlopeChoiceName(SlopeChoice choice);

// Where the force side's profile of the sliding path comes from: P/S
// through the loading spring, or the friction of the two directions at the
// same x (ComputeFrictionProfile) for rigs that load with a dead weight,
// or the record's depth channel (k = -d depth/dx); auto: the spring unless
// P's slope is insignificant, then the depth when logged, else the
// friction when P does not follow the track the scan shows.
enum class ProfileSource { kAuto, kSpring, kFriction, kDepth };

// "auto", "spring", "friction", "depth"; false for anything else.
bool ParseProfileSource(const std::string& name, ProfileSource* source);
const char* ProfileSourceName(ProfileSource source);

struct FuseOptions {
  AnalysisOptions analysis;
  scan::LevelOptions level;
  scan::SpikeOptions spikes;
  scan::TrackOptions track;
  // The centreline reaches 0.5 mm beyond the track's ends, room for the
  // alignment to shift it against the stroke.
  scan::ProfileOptions profile = [] {
    scan::ProfileOptions p;
    p.extend_mm = 0.5;
    return p;
  }();
  ForceProfileOptions force_profile;
  AlignOptions align;
  // Derivative of the scan profile (window in scan samples): quadratic
  // Savitzky-Golay over 15 samples. No spring: the scan sees the path.
  force::DerivativeOptions scan_slope = [] {
    force::DerivativeOptions d;
    d.method = force::DerivativeMethod::kSavitzkyGolay;
    d.window = 15;
    d.polynomial_order = 2;
    return d;
  }();
  VerdictOptions verdict;
  DataWarningOptions warnings;
  // Whether the spring's stiffness (analysis.friction.slope) was given by
  // the user; when not, its default is the paper's rig's and the result
  // says so, with the stiffness a scan implies (MakeTestSettings sets it).
  bool spring_given = false;
  // Where the force file states the spring's stiffness and it was not
  // given ("line 3: 'Spring stiffness [N/mm]: 25'"; WithStatedSpring).
  std::string spring_stated;
  // mu(x, cycle) along the stroke, raw and corrected for the slope.
  FrictionMapOptions friction_map;
  // h(x, cycle) from P/S: the track's shape under load as it wears.
  TrackHistoryOptions track_history;
  // The scan shows the track's final state; earlier cycles slid on a
  // shallower track. When set, the scan's slope of each cycle is scaled by
  // that cycle's waviness from the spring over the final waviness
  // (TrackHistory; the factor kept within [0, max_scan_slope_scale]), so the
  // scan-side mu-hat no longer carries the track's growth. This borrows
  // from the force side: the scan-side mu-hat is then no longer
  // independent of P.
  bool scan_slope_history = false;
  double max_scan_slope_scale = 2.0;
  // Which slope mu-hat is fitted with when a scan is given: the force
  // side's k = (1/S) dP/dx, the scan's, or both (without a scan: force).
  SlopeChoice slopes = SlopeChoice::kBoth;
  // The force side's profile (the one aligned with the scan and compared
  // with it).
  ProfileSource profile_from = ProfileSource::kAuto;
  // auto takes the profile from the friction when P's repeatable slope is
  // within this many of its standard errors of nothing (the k split's
  // repeatable rms against noise / sqrt(cycles)) and P/S varies less than
  // dead_weight_ratio of the scanned profile.
  double dead_weight_significance = 3.0;
  double dead_weight_ratio = 0.2;
  // With a depth channel, auto also takes the depth when P varies but its
  // profile (P/S) correlates with the depth's by less than this in
  // magnitude: P's variation is not the track's (Q's crosstalk into P on a
  // dead weight follows the track's slope, not its height).
  double spring_depth_agreement = 0.5;
  // LuGre beside the wear-scar fit (paper Fig. 17) on the detail cycle.
  bool fit_lugre = true;
  LugreOptions lugre;
  int detail_cycle = -1;  // cycle for LuGre and the detail outputs; -1 = last
  // Points of J(mu) over the fit's mu interval on the detail cycle (paper
  // Fig. 11).
  int cost_curve_points = 201;
  // The scan's preparation and the products that need only the force side
  // run on threads of their own beside the force analysis (and a test's
  // folder checksums its inputs beside its tables). False runs all of it
  // on the caller's thread, for callers whose own threads keep every core
  // busy already (an audit's workers). The results are the same.
  bool parallel = true;
  // Periodic lines removed from Q and P before the analysis (Hz; --notch),
  // each a sinusoid fitted in blocks (force::NotchLine), said in the
  // assumptions. Lines the drive does not make are sought either way and
  // warned about (force::FindPeriodicLines).
  std::vector<double> notch_hz;
  bool find_periodic_lines = true;

  bool IsValid(std::string* why) const;
};

// The scan side of one test.
struct ScanAnalysis {
  scan::HeightMap levelled;  // after levelling and spike removal (for figures)
  scan::LevelSummary level;
  int spikes_removed = 0;
  scan::Track track;
  scan::WearProfile profile;
  ForceProfile force_profile;  // P/S, or from the friction (profile_source)
  ProfileSource profile_source = ProfileSource::kSpring;
  Alignment alignment;
  PlateProfile slope;           // k_scan in plate coordinates
  std::vector<MuFit> fit_scan;  // mu-hat per cycle with k from the scan
  // Per cycle, the factor on the scan's slope (FuseOptions::
  // scan_slope_history); empty when the slope was used as scanned.
  std::vector<double> slope_scale;
};

struct TestResult {
  ForceAnalysis force;
  // The force side's profile used (kSpring or kFriction) and why, in words.
  ProfileSource profile_source = ProfileSource::kSpring;
  std::string profile_reason;
  // The depth channel's column and sign as read (when the record has one).
  std::string depth_column;
  bool depth_is_penetration = true;
  // P's repeatable slope in its standard errors, as auto read it (NaN when
  // P's k was not split).
  double p_slope_significance = std::numeric_limits<double>::quiet_NaN();
  // The depth's profile against the friction's (correlation; NaN when not
  // computed): below -0.5 the depth was read turned over.
  double depth_agreement = std::numeric_limits<double>::quiet_NaN();
  // P/S's profile against the depth channel's (NaN when not computed: no
  // depth channel, or P's slope insignificant).
  double spring_depth_agreement = std::numeric_limits<double>::quiet_NaN();
  std::optional<ScanAnalysis> scan;
  MismatchReport mismatch;
  Verdict verdict;
  // How well the data carry the method (DataWarnings), and why a scan
  // given was not used (scan_skipped, also the first warning).
  std::vector<std::string> warnings;
  // Periodic lines in Q and P the drive does not make (after any notch).
  std::vector<force::PeriodicLine> periodic_lines;
  // What the result rests on that the files did not state, in words: the
  // spring's stiffness and where it came from, the slope the verdict
  // judges, the force file's layout and units (stated or guessed), the
  // running-in (detected or given), in that order.
  std::vector<std::string> assumptions;
  std::string scan_skipped;
  std::string scan_file;  // the scan's source, used or not ("" without one)
  // A scan left out for want of a track: its levelled map, for the figure
  // that shows it (null otherwise).
  std::shared_ptr<const scan::HeightMap> unused_map;
  // Track size, load, sliding distance and specific wear rate (the scan
  // side NaN without a usable scan).
  Wear wear;
  // mu along the stroke per cycle and direction (force-side k), and its
  // along-track variation after running-in.
  FrictionMap friction_map;
  // The force-side profile of every cycle, its waviness over the cycles.
  TrackHistory track_history;
  int detail_cycle = 0;
  std::optional<LugreFit> lugre;
  // The detail cycle's slopes, reconstructions, J(mu) and the wear-scar
  // model beside LuGre (paper Figs. 10-12, 17).
  DetailCycle detail;
};

// Force analysis, then (when a scan is given) levelling, spikes, track,
// centreline, alignment, scan slope and mu-hat with it; then the mismatch
// report and the verdict. The scan is taken by value (it is levelled). A
// scan without a findable track, or whose profile cannot be aligned with
// the stroke, is left out with the reason in scan_skipped and the warnings
// (with SlopeChoice::kScan it is an error).
// Requires record.IsConsistent() and a consistent map (checked in debug
// and sanitizer builds; the readers return only such data).
TestResult AnalyzeTest(const force::ForceRecord& record,
                       std::optional<scan::HeightMap> height_map,
                       const FuseOptions& options = {});

// The one line to read first: the coefficient to quote, how it was got
// and the verdict ("mu = 0.1443 (95%: 0.1436-0.1449): mu-hat, k from P,
// cycles 13-59; explained by wear-scar interaction"), or why there is none
// to quote. The other coefficients are comparisons.
std::string Headline(const TestResult& result);

// The options a record is analysed with: when the spring's stiffness was
// not given and the force file states one, that one (spring_given set,
// spring_stated saying where). AnalyzeTest and the result's options block
// apply it.
FuseOptions WithStatedSpring(const FuseOptions& options,
                             const force::ForceRecord& record);

// PrepareScan's scan::NoTrackError, with the map as levelled (drawn so that
// the user sees why no track was found).
class NoTrackInMap : public scan::NoTrackError {
 public:
  NoTrackInMap(const scan::NoTrackError& e, scan::HeightMap levelled_map)
      : scan::NoTrackError(e),
        levelled(
            std::make_shared<const scan::HeightMap>(std::move(levelled_map))) {}
  std::shared_ptr<const scan::HeightMap> levelled;
};

// The scan's own stages, which need nothing of the force record: levelling,
// spikes, track, centreline (`levelled` holds the map; the rest of
// ScanAnalysis is filled by AnalyzeTest). Throws NoTrackInMap when the map
// holds no track.
ScanAnalysis PrepareScan(scan::HeightMap map, const FuseOptions& options);

// AnalyzeTest with the scan prepared elsewhere (PrepareScan), possibly
// still under way (a caller reading the force file meanwhile), and the
// scan's source; an invalid future: no scan.
TestResult AnalyzeTest(const force::ForceRecord& record,
                       std::future<ScanAnalysis> prepared_scan,
                       const std::string& scan_file,
                       const FuseOptions& options = {});

// The mismatch over cycles [first, last] (after running-in by default).
MismatchReport CompareSlopes(const force::ForceRecord& record,
                             const ForceAnalysis& force,
                             const ScanAnalysis* scan,
                             int first_cycle,
                             int last_cycle,
                             const FuseOptions& options);

}  // namespace wearscar::fusion
