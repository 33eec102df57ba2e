#pragma once
// How late Q turns at the reversals behind x. In the stick that follows a
// reversal the contact's tangential stiffness makes Q follow x: Q = F +
// K (x(t) - x_turn) from the turn until gross slip, F the slip level
// before it. A Q channel that lags by tau shows the same hinge tau later;
// friction varying along the track, a wavy track or an elastic part
// change nothing there. The premise of the friction's path (Q and P in
// time with x) and the direct evidence of a lag.

#include <limits>
#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"

namespace wearscar::force {

struct TurnDelay {
  double delay_s =
      std::numeric_limits<double>::quiet_NaN();  // median over the turns (NaN:
                                                 // not judged)
  double delay_se_s =
      std::numeric_limits<double>::quiet_NaN();  // its standard error
  int turns = 0;                                 // the turns whose hinge told
};

// Over the half cycles of `cycles` [first, last] (0-based; each half starts
// at a turn and slips from its slip_begin), the hinge's delay per turn,
// searched within +-0.03 s: the shift d at which Q = F + K g(t - d) fits
// best, g the retreat from the turn (0 before it), refined by a parabola.
// Not judged (NaN) with fewer than four turns that tell.
TurnDelay MeasureTurnDelay(const ForceRecord& record,
                           const CycleSet& cycles,
                           int first,
                           int last);

}  // namespace wearscar::force
