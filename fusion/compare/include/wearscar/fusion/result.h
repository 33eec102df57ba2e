#pragma once

#include <cmath>
// What one test's analysis yields (AnalyzeTest): every number, table and
// reconstruction a user can see, each decision recorded once as given and
// as used. Below the pipeline: the products, the summaries, the figures and
// the diagnosis read this header, not fuse.h.

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "wearscar/fusion/align.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/detail_cycle.h"
#include "wearscar/fusion/fuse_options.h"
#include "wearscar/fusion/premise.h"
#include "wearscar/fusion/unit_results.h"
#include "wearscar/fusion/verdict.h"
#include "wearscar/scan/height_map.h"
#include "wearscar/scan/level.h"
#include "wearscar/scan/track.h"
#include "wearscar/scan/track_ends.h"

namespace wearscar::fusion {

// Where the force side's profile of the sliding path came from (Ceres'
// Summary style: given and used), with the figures the choice read. Made
// once by DecideProfile (profile_decision.h); the fit, the verdict,
// result.json, the summary, the figures, the viewer and the diagnosis read
// it and never decide again.
struct ProfileDecision {
  ProfileSource given = ProfileSource::kAuto;  // FuseOptions::profile_from
  ProfileSource used = ProfileSource::kSpring;
  // -1: the depth channel read turned over (its profile ran against the
  // friction's); +1 otherwise. Only meaningful with used == kDepth.
  double depth_sign = 1.0;
  // The depth channel's column and how its name reads (when logged).
  std::string depth_column;
  bool depth_is_penetration = true;
  // The figures the choice read (NaN where it did not need them): P's
  // repeatable slope in its standard errors; the depth's profile against
  // the friction's; P/S's profile against the depth's; P/S's amplitude
  // against the friction's path or the scanned profile.
  double p_slope_significance = std::numeric_limits<double>::quiet_NaN();
  double depth_agreement = std::numeric_limits<double>::quiet_NaN();
  double spring_depth_agreement = std::numeric_limits<double>::quiet_NaN();
  double spring_amplitude_ratio = std::numeric_limits<double>::quiet_NaN();
  // Whether that ratio is against the path the friction shows (else the
  // scanned profile).
  bool ratio_against_friction = false;
  // Why, in words (result.json profile.why, the assumptions).
  std::string reason;

  bool FromSpring() const { return used == ProfileSource::kSpring; }
  bool FromDepth() const { return used == ProfileSource::kDepth; }
  bool FromFriction() const { return used == ProfileSource::kFriction; }
  // Whether mu-hat with the force side's own k is fitted and judged (P/S or
  // the depth); from the friction it is circular and the scan's k is used.
  bool ForceSlopeJudged() const { return !FromFriction(); }
  // The channel the force side's own k is fitted from, as every output
  // names it: "the depth" or "P" (also with the friction's profile, where
  // that fit is not judged); SlopeName() is "k from " that.
  const char* ChannelName() const;
  std::string SlopeName() const;
  // The same in a key or a table's few letters: "P" or "depth"; the
  // profile "P/S", "depth" or "friction profile".
  const char* ShortChannelName() const;
  const char* ShortProfileName() const;
  // The force side's profile as compared with the scan: "the spring
  // displacement", "the depth channel's profile", "the profile from the
  // friction".
  std::string ProfileName() const;
};

// The scan side of one test.
struct ScanAnalysis {
  // After levelling and spike removal (the figures draw it). Shared: a
  // test analysed twice (the lines found removed) keeps one map, not a
  // copy per pass.
  std::shared_ptr<const scan::HeightMap> levelled;
  const scan::HeightMap& Levelled() const { return *levelled; }
  scan::LevelSummary level;
  int spikes_removed = 0;
  scan::Track track;
  // The sphere's path along the track (SpherePath; the centreline with
  // FuseOptions::sphere.radius_mm 0): what is aligned and gives k_scan.
  scan::WearProfile profile;
  scan::WearProfile centreline;
  // The sphere's reversals, from the centreline's end walls (FitTrackEnds).
  scan::TrackEnds ends;
  // Whether the force side's path follows a rigid sphere's path on the
  // scanned surface or the centreline (a sphere that conforms to the
  // track), judged on the waviness (ChoosePath); `profile` is the one
  // followed.
  Premise rigid_sphere;
  bool centreline_used = false;
  // Where the profiles leave the choice open (both followed alike), the
  // centreline's alignment and slope, for the loops to decide (the scan's
  // fit, ScanFits::centreline; cleared once they have).
  std::optional<Alignment> centreline_alignment;
  std::optional<PlateProfile> centreline_slope;
  // P/S, the depth channel's or the friction's (TestResult::profile.used).
  ForceProfile force_profile;
  Alignment alignment;
  PlateProfile slope;  // k_scan in plate coordinates
};

// mu-hat per cycle with k from the scan: the result of the analysis unit
// "mu_fit_scan" (TestResult::ScanSlopeFits).
struct ScanFits {
  std::vector<MuFit> cycles;  // one per cycle ("not fitted" where not)
  // Per cycle, the factor on the scan's slope (FuseOptions::
  // scan_slope_history); empty when the slope was used as scanned.
  std::vector<double> slope_scale;
  // Where the profiles left the path open (ScanAnalysis::centreline_slope),
  // mu-hat was fitted with both and the lower mean J over the quoted
  // cycles kept (the tilt that reproduces Q): whether the centreline's, and
  // both J.
  bool centreline = false;
  double j_sphere = std::numeric_limits<double>::quiet_NaN();
  double j_centreline = std::numeric_limits<double>::quiet_NaN();
};

// The cycles the result quotes and compares (mu-hat's mean, J, the
// verdict) and why those: with a scan, the last cycles after running-in,
// whose track the scan shows; without one, every cycle after running-in;
// or a range given. Decided once (the pipeline's comparison).
struct CycleWindow {
  int first = 0, last = -1;  // 0-based, inclusive
  std::string why;           // "the last 50 after running-in, whose track ..."
};

struct TestResult {
  ForceAnalysis force;
  CycleWindow window;
  // Where the force side's profile came from, as given and as used, and
  // why: decided once (DecideProfile), read by everything after it.
  ProfileDecision profile;
  // The options the analysis ran with: the given ones with a spring the
  // force file states (WithStatedSpring) and the slope's source and the
  // depth's sign as decided.
  FuseOptions options;
  std::optional<ScanAnalysis> scan;
  MismatchReport mismatch;
  Verdict verdict;
  // How well the data carry the method (DataWarnings), and why a scan
  // given was not used (scan_skipped, also the first warning).
  std::vector<std::string> warnings;
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
  // The cycle shown in detail (the unit "detail_cycle"; LuGre's).
  int detail_cycle = 0;
  // The analysis units' results by kind (unit.h: the periodic lines, the
  // sliding and the wear, LuGre, the friction map, the track's history from
  // the spring, the scan's shape per cycle): read by type,
  // units.Find<FrictionMap>(); a unit that did not run has none.
  UnitResults units;

  // The force side's mu-hat per cycle with k where the profile's decision
  // put it: the depth channel's fits where it took them, else P/S's (the
  // units "mu_fit_depth" and "mu_fit_spring"); empty before they are
  // stored.
  const SlopeFits& ForceFits() const;
  // mu-hat per cycle with k from the scan (the unit "mu_fit_scan"); empty
  // without a scan.
  const ScanFits& ScanSlopeFits() const;
};

// The cycles quoted and compared: a range given; with a scan the force
// profile's (the last cycles after running-in: the scan shows the track
// after the last cycle, so the cycles nearest it); else every cycle after
// running-in.
CycleWindow QuotedWindow(const TestResult& r, const ScanAnalysis* scan);

// The number to quote and its status, one home for every table (summary
// rows, result.json "quote", the report's filter, Python's Result): the
// status is "explained", "not settled" (explained, but a repeating misfit
// above the screen's limit), "not explained", "not judged" or "not fitted";
// mu is NaN where the status gives none to quote, and `reason` says why.
struct Quote {
  std::string status;
  double mu = NAN, low = NAN, high = NAN;
  std::string k_from;  // "P", "the depth" or "the scan"
  std::string reason;  // why there is none ("" when mu is quoted)
  bool Quoted() const { return std::isfinite(mu); }
};
Quote QuoteOf(const TestResult& result);

// The one line to read first: the coefficient to quote, how it was got
// and the verdict ("mu = 0.1443 (95%: 0.1436-0.1449): mu-hat, k from P,
// cycles 13-59; explained by wear-scar interaction"), or why there is none
// to quote. The other coefficients are comparisons.
std::string Headline(const TestResult& result);

}  // namespace wearscar::fusion
