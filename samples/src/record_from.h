#pragma once
// A test recorded from a later cycle (SimulationOptions::record_from_cycle).

#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::samples::internal {

// The whole test simulated from its first contact, its record cut at the
// start of cycle record_from_cycle (time from 0 there), the truth's
// per-cycle series with it; the scan is the whole test's end.
SimulatedTest SimulateFrom(const SimulationOptions& options);

}  // namespace wearscar::samples::internal
