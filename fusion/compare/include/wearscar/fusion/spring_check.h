#pragma once
// Whether the spring displacement P/S is the worn track at the stiffness
// used. Two things make P/S vary otherwise than the scanned track, and
// they leave different traces:
// - a stiffness other than the one used scales every height alike. P/S is
//   then the worn track times a factor, and, like the worn track, it
//   starts from nothing: a fresh surface has no groove.
// - an elastic part (the sphere sinking further into softer wood) needs no
//   wear: it is there at the first cycle already, and stays.
// So the P/S profiles of the first cycles, projected on the compared
// cycles' profile and extrapolated back to the test's start, give the
// elastic share; what is left of the amplitude ratio against the scan,
// after the track's growth, is the stiffness's.

#include <cmath>
#include <string>

#include "wearscar/fusion/align.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion {

struct SpringCheckOptions {
  // The first cycles whose P/S profiles are extrapolated back to the
  // test's start (a straight line through their projections).
  int early_cycles = 6;
  // The spring used is contradicted when the 95% interval of the stiffness
  // ratio lies wholly beyond this factor, either way.
  double max_stiffness_ratio = 1.15;
  // P/S carries an elastic part when the lower end of the elastic share's
  // 95% interval exceeds this.
  double min_elastic_share = 0.1;
  bool IsValid(std::string* why) const;
};

struct SpringCheck {
  bool judged = false;  // a spring's profile with enough cycles
  // The share of the compared cycles' P/S profile already there before any
  // wear (0: none; 1: all of it), with its 95% interval.
  double elastic_share = NAN, elastic_share_low = NAN, elastic_share_high = NAN;
  bool elastic = false;  // the share's lower end above the limit
  // With a scan: the compared cycles' waviness over the final track's (the
  // scan shows the track after the last cycle) ...
  double growth = NAN;
  // ... and P/S's worn part against the scanned track after that growth:
  // the rig's stiffness over the one used, with its 95% interval.
  double stiffness_ratio = NAN, stiffness_ratio_low = NAN,
         stiffness_ratio_high = NAN;
  double used_n_per_mm = NAN;
  bool contradicted = false;  // the interval wholly beyond the limit
  double ImpliedStiffness() const { return used_n_per_mm * stiffness_ratio; }
  double ImpliedLow() const { return used_n_per_mm * stiffness_ratio_low; }
  double ImpliedHigh() const { return used_n_per_mm * stiffness_ratio_high; }
  // "the spring's stiffness appears to be 24.6 N/mm (95%: ...), not the
  // 10.19 N/mm assumed (the default): ..."; `how` names where the used
  // stiffness came from ("given", "assumed (the default)", "the force file
  // states").
  std::string Describe(const std::string& how) const;
};

// The elastic share alone, from the track's history: the P/S profile of
// each of the first `early_cycles` cycles (both directions averaged)
// projected on the mean profile of cycles [first, last] (0-based), a
// straight line through the projections against the cycle's number,
// extrapolated to cycle 0. Sets `check` 's elastic fields and `judged`.
void EstimateElasticShare(const TrackHistory& history,
                          int first,
                          int last,
                          const SpringCheckOptions& options,
                          SpringCheck* check);

// The whole check: the elastic share, and with an alignment of P/S
// against the scan (null: none) the stiffness ratio, the amplitude ratio
// times the worn share over the growth.
SpringCheck CheckSpring(const TrackHistory& history,
                        const Alignment* alignment,
                        int first,
                        int last,
                        double spring_n_per_mm,
                        const SpringCheckOptions& options);

}  // namespace wearscar::fusion
