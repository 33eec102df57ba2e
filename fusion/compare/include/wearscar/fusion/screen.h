#pragma once
// The screen of an explained test: the loops repeat a misfit that acts as
// friction does (changing sign with the motion) above their noise, so an
// effect the wear-scar model misses may bias mu-hat. Its premise: only
// such a misfit biases mu-hat; one that acts as a slope does (the same in
// both directions: an elastic part, a groove deepening over the compared
// cycles, a scaled k) cancels between the directions, and the spring
// check and the scan judge it. Decided once on the comparison by the
// screen's analysis unit (fusion/units), before the verdict, which reads
// it (MismatchReport::Screen) where the test is explained with the force
// side's k.

#include <cmath>
#include <string>

#include "wearscar/fusion/premise.h"

namespace wearscar::fusion {

struct MismatchReport;
struct VerdictOptions;

struct ScreenFinding {
  // J's split over the compared cycles with the slope the verdict judges:
  // the excess screened (its part that changes sign with the motion where
  // the misfit was split by direction, else all of it), its 95% interval
  // and the noise floor. NaN where nothing was split.
  double excess = NAN, excess_low = NAN, excess_high = NAN, floor = NAN;
  bool by_direction = false;
  // Screened only with the force side's k: with the scan's, the excess
  // holds the track's growth over the compared cycles too (the scan shows
  // the last one's).
  bool with_force_slope = false;
  // The finding's words where the excess's lower end reaches the limit
  // (VerdictOptions::screen_excess_to_floor of the floor), "" otherwise.
  std::string finding;
  Premise premise;
};

ScreenFinding ScreenTheLoops(const MismatchReport& r, const VerdictOptions& o);

}  // namespace wearscar::fusion
