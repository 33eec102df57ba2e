#pragma once
// Where the sphere turned: the worn track's end walls are the sphere's
// imprint at the stroke's reversals, so each wall beyond the last
// position the sphere's centre reached is a circle of the sphere's radius
// (a parabola, (s - e)^2 / 2R, over a groove's depth). Fitted with that
// curvature fixed, the wall gives the reversal's position e whatever the
// groove's local depth there, where the track's threshold outline moves
// with it (a shallow latewood band at an end shortens the outline by a
// tenth of a millimetre). Premise: the walls are the sphere's (a rigid
// sphere of that radius, no springback or debris at the ends); checked by
// the fit's residual and, by the caller, against the record's stroke.

#include <limits>

#include "wearscar/scan/track.h"

namespace wearscar::scan {

struct TrackEnd {
  // The sphere centre's last position at this end, along the profile (mm;
  // NaN where the wall is not measured: beyond the field, or too few
  // points on it).
  double position_mm = std::numeric_limits<double>::quiet_NaN();
  int points = 0;  // on the wall, between 15% and 85% of the groove's depth
  // The fit's rms residual over the groove's depth near the end.
  double residual_to_depth = std::numeric_limits<double>::quiet_NaN();
  bool Found() const { return position_mm == position_mm; }
};

struct TrackEnds {
  TrackEnd low, high;     // at the profile's smaller and larger s
  double depth_mm = 0.0;  // the groove's median depth over the central half
};

struct TrackEndOptions {
  double sphere_radius_mm = 3.25;
  int min_points = 8;
  // A wall whose fit leaves more than this share of the depth is no
  // sphere's imprint (debris, a torn end): not used.
  double max_residual_to_depth = 0.08;
};

// The two reversals from a profile along the track (the centreline, its
// heights; it must reach past the walls). Never throws: an end it cannot
// fit stays NaN.
TrackEnds FitTrackEnds(const WearProfile& profile,
                       const TrackEndOptions& options = {});

}  // namespace wearscar::scan
