#pragma once

// The project's simulator on another track history than a groove grown
// from the first contact, and the options the history tests run with
// (histories_test.cc, scan_shape_test.cc).

#include "common/simulated.h"
#include "wearscar/fusion/fuse_options.h"

namespace wearscar::sim {

// The paper's case `name` at `noise` times its sensor noise, `cycles`
// cycles recorded from cycle `record_from` of the test on (0: from the
// first contact, the groove growing; 300: a pre-worn or resumed specimen,
// or a later block of a long test).
inline SimulatedTest HistoryCase(const char* name,
                                 double noise,
                                 int record_from,
                                 int cycles = 60) {
  samples::SimulationOptions o = samples::PaperCase(name, false);
  o.cycles = cycles;
  o.record_from_cycle = record_from;
  o.noise_scale = noise;
  return sim::Simulate(o);
}

// The options without the LuGre fit (the slowest unit; not what a history
// test is about).
inline fusion::FuseOptions WithoutLugre() {
  fusion::FuseOptions o;
  o.fit_lugre = false;
  return o;
}

}  // namespace wearscar::sim
