#pragma once
// Whether the spring displacement P/S is the sliding path at the stiffness
// used. Two things besides the path set P/S's amplitude:
// - the stiffness: P/S is the path times the rig's stiffness over the one
//   used;
// - an elastic part (the sphere sinking further into softer wood): it
//   moves P without tilting the contact, and needs no wear.
// The friction tells the path apart from P: on the wear-scar model the
// two directions at the same x see atan(Q/P) = theta + s atan(mu), so
// their mean is the contact's inclination whatever the spring and any
// elastic part (TrackHistory::friction_height_mm). Per cycle c, P/S's
// profile and the friction's are projected on the compared cycles' P/S
// profile: p_c = r f_c + e, with r the stiffness ratio and e the elastic
// part's projection.
//
// The split into r and e rests on a premise the data must show: the
// groove changes during the record (it grows from the first contact; a
// pre-worn specimen, a resumed test, a record that starts after
// running-in or a later block of a long test carry theirs from the first
// cycle). Where f_c's spread does not decide r, only the path ratio
// rho = p / f over the compared cycles is known, r (1 + elastic part over
// the worn part). An elastic part is deeper where the wood is softer, as
// the wear is, so it only adds: rho below 1 is a stiffness (the rig's at
// most rho S); rho above 1 is a stiffness or an elastic part, and the data
// cannot tell which (both leave the path the friction and the scan show,
// so mu-hat with k from the scan stands either way).

#include <cmath>
#include <string>
#include <vector>

#include "wearscar/fusion/premise.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion {

struct SpringCheckOptions {
  // The spring used is contradicted when the 95% interval of the stiffness
  // ratio (or of the path ratio, where the growth does not decide) lies
  // wholly beyond this factor, either way.
  double max_stiffness_ratio = 1.15;
  // P/S carries an elastic part when the lower end of the elastic share's
  // 95% interval exceeds this (the share of the worn track's profile at
  // the end; the amplitude ratio against the scan's 1.15 before).
  double min_elastic_share = 0.15;
  // The growth decides the split when the stiffness ratio's 95% interval
  // is narrower than this fraction of it on either side, and the friction
  // profile's change over the cycles stands this many times (in variance)
  // above its noise.
  double max_split_width = 0.1;
  double min_growth_to_noise = 10.0;
  // The friction's path needs Q in time with x: judged only where Q turns
  // at the reversals within this of x (the lower end of the delay's 95%
  // interval; 1 ms shifts the passes by 2 x 18 um at the paper's speed).
  double max_q_delay_s = 0.001;
  bool IsValid(std::string* why) const;
};

struct SpringCheck {
  bool judged = false;  // P/S and the friction's profile over enough cycles
  double used_n_per_mm = NAN;
  // P/S over the friction's path, projected, over the compared cycles:
  // r (1 + elastic part / worn part), with its 95% interval.
  double path_ratio = NAN, path_ratio_low = NAN, path_ratio_high = NAN;
  // The friction's path over the compared cycles against the last tenth's
  // (the track the scan shows): how far the groove had grown by them.
  double growth = NAN;
  // The premise of the split (the groove changes during the record), its
  // check and the figure: the friction profile's variance over the cycles
  // in its noise's.
  Premise changing_groove;
  // Q in time with x (TrackHistory::q_turn): failed, nothing is judged.
  Premise q_in_time;
  double growth_to_noise = NAN;
  // With the premise held: the rig's stiffness over the one used, and the
  // part of P/S that does not follow the path's growth (the elastic part)
  // as a share of the worn track's profile at the end (0: none), each with
  // its 95% interval. NaN otherwise.
  double stiffness_ratio = NAN, stiffness_ratio_low = NAN,
         stiffness_ratio_high = NAN;
  double elastic_share = NAN, elastic_share_low = NAN, elastic_share_high = NAN;
  // With the premise held: the path ratio the split's line gives at the
  // end of the record (the last tenth's path), where an elastic part
  // weighs least, with its 95% interval.
  double end_ratio = NAN, end_ratio_low = NAN, end_ratio_high = NAN;
  // The findings: the stiffness contradicted (the split's ratio, or a path
  // ratio below the limit where the growth does not decide); an elastic
  // part; a path ratio above the limit that a stiffness and an elastic part
  // explain alike (undecided).
  bool contradicted = false;
  bool elastic = false;
  bool undecided = false;

  // The rig's stiffness over the one used: the split's r where the split
  // resolves an elastic part (its share's interval above 0), else the
  // path ratio at the end of the record where the groove's growth decides
  // (the split's slope is the noisier), else the compared cycles' path
  // ratio rho (at most the stiffness; all of rho when undecided).
  bool SplitsTheStiffness() const;
  // A contradicted spring whose stiffness is only bounded: without the
  // groove's change an elastic part cannot be split off, and one would
  // lower the stiffness further, so the path ratio gives its upper end
  // (the stiffness cannot be told from a softer one beside an elastic part).
  bool UpperBoundOnly() const {
    return contradicted && !changing_groove.Held();
  }
  double StiffnessRatio() const;
  double ImpliedStiffness() const;
  double ImpliedLow() const;
  double ImpliedHigh() const;
  // "the spring's stiffness appears to be 24.6 N/mm (95%: ...), not the
  // 10.19 N/mm assumed (the default: not given): ..."; `how` names where
  // the used stiffness came from.
  std::string Describe(const std::string& how) const;
  // "cannot tell a spring of 17.3 N/mm from an elastic part of 41% of
  // P/S: ...; give --spring, or record from the first contact".
  std::string DescribeUndecided(const std::string& how) const;
  // "P/S carries an elastic part: 38% of its profile (95% ...) does not
  // follow the path's growth".
  std::string DescribeElastic(const std::string& profile_name) const;
};

// The check over the compared cycles [first, last] (0-based) of a history
// that holds the friction's profile, split over the cycles from
// `steady_from` on (after the running-in: the friction's path needs the
// same friction on the two passes over a bin, and a running-in changes it
// between them faster than the cycles' drift tells).
SpringCheck CheckSpring(const TrackHistory& history,
                        int steady_from,
                        int first,
                        int last,
                        double spring_n_per_mm,
                        const SpringCheckOptions& options);

// P/S's mean profile over cycles [first, last] against the path the
// friction shows over them, projected on the latter (each less its line in
// x): about 1 on a spring rig at its stiffness, about 0 on a dead weight
// (P constant, the height not in it). NaN where the friction's path does
// not stand out of its noise four times in variance (a flat track).
double SpringOverFrictionPath(const TrackHistory& history, int first, int last);

}  // namespace wearscar::fusion
