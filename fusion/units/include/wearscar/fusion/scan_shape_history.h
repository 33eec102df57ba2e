#pragma once
// When the scanned track's shape appeared in the record: per cycle, how
// much of the aligned scan profile that cycle's P/S holds. A groove that
// grows from a fresh surface shows a factor rising from near 0 to about 1
// over the compared cycles; a groove there from the first recorded cycle
// (a pre-worn specimen, a resumed test, a later block of a long test)
// shows about 1 from the start. An analysis unit (scan_shape_unit.cc).

#include <limits>
#include <string>
#include <vector>

#include "wearscar/fusion/premise.h"

namespace wearscar::fusion {

struct ScanShapeHistory {
  // Why it was not computed, naming the premise that failed ("" when it
  // was).
  std::string abstained;
  // Its premises as checked when it ran (result.json premises).
  std::vector<Premise> premises;
  // Per cycle (0-based, every cycle of the track's history): the
  // least-squares factor of the scan's profile, scaled as P/S sees it
  // over the compared cycles, in the cycle's P/S about its mean (1: the
  // whole scanned shape; 0: none of it), and their correlation along x.
  std::vector<double> factor, correlation;
  // The factor's mean over the first cycles and over the compared ones.
  double first_factor = std::numeric_limits<double>::quiet_NaN();
  double compared_factor = std::numeric_limits<double>::quiet_NaN();
  int first_cycles = 0;  // how many first cycles
  // The first cycle from which the factor stays at or above one half (-1
  // when it does not).
  int half_cycle = -1;
};

}  // namespace wearscar::fusion
