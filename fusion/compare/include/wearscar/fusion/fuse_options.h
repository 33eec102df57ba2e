#pragma once
// The options of one test's analysis (AnalyzeTest), with the paper's
// defaults: below the pipeline, read by everything that takes them.

#include <string>
#include <vector>

#include "wearscar/force/slope.h"
#include "wearscar/fusion/align.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/friction_map.h"
#include "wearscar/fusion/lugre.h"
#include "wearscar/fusion/spring_check.h"
#include "wearscar/fusion/track_history.h"
#include "wearscar/fusion/verdict.h"
#include "wearscar/scan/level.h"
#include "wearscar/scan/sphere_path.h"
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
// friction when P does not follow the track the scan shows (DecideProfile,
// profile_decision.h).
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
  // The sphere's path along the track from the scan (SpherePath): what
  // the scan's side aligns and takes k from; radius 0 takes the
  // centreline instead.
  scan::SpherePathOptions sphere;
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
  SpringCheckOptions spring_check;
  // Whether the spring's stiffness (analysis.friction.slope) was given by
  // the user; when not, its default is the paper's rig's and the result
  // says so, with the stiffness a scan implies (MakeTestSettings sets it).
  bool spring_given = false;
  // Where the force file states the spring's stiffness and it was not
  // given ("line 3: 'Spring stiffness [N/mm]: 25'"; WithStatedSpring).
  std::string spring_stated;
  // Set by the pipeline when a test without a scan was analysed again at
  // the stiffness the friction's path implies (SpringCheck), the first
  // pass's finding in words; the spring used is then that stiffness.
  std::string spring_from_friction;
  double spring_before_friction_n_per_mm = 0.0;  // the one used before that
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
  // A depth channel whose profile correlates with the friction's (which
  // needs no sign) by less than minus this runs the other way: a height
  // under a depth's name, read turned over.
  double depth_turn_agreement = 0.5;
  // LuGre beside the wear-scar fit (paper Fig. 17) on the detail cycle.
  bool fit_lugre = true;
  LugreOptions lugre;
  int detail_cycle = -1;  // cycle for LuGre and the detail outputs; -1 = last
  // The cycle detailed (0-based) of a test of `cycles`: the one asked
  // for, else the last.
  int DetailedCycle(int cycles) const {
    return detail_cycle >= 0 && detail_cycle < cycles ? detail_cycle
                                                      : cycles - 1;
  }
  // Points of J(mu) over the fit's mu interval on the detail cycle (paper
  // Fig. 11).
  int cost_curve_points = 201;
  // The scan's preparation and the products that need only the force side
  // run on threads of their own beside the force analysis (and a test's
  // force file is checksummed beside its reading, its tables written on
  // two threads). False runs all of it
  // on the caller's thread, for callers whose own threads keep every core
  // busy already (an audit's workers). The results are the same.
  bool parallel = true;
  // Periodic lines removed from Q and P before the analysis (Hz; --notch),
  // each a sinusoid fitted in blocks (force::NotchLine), said in the
  // assumptions. Lines the drive does not make are sought either way
  // (force::FindPeriodicLines); without notch_hz, those found are removed
  // (a second pass, said first in the warnings) unless notch_found_lines
  // is false (--notch none), when they are warned about.
  std::vector<double> notch_hz;
  bool notch_found_lines = true;
  bool find_periodic_lines = true;

  bool IsValid(std::string* why) const;
  // The force side's analysis options: `analysis`, the force slope fitted
  // unless the scan's alone was asked for, on both cores where `parallel`
  // (its second half of the cycles beside the first; the same fits).
  AnalysisOptions ForceSide() const;
};

}  // namespace wearscar::fusion
