#pragma once

#include "common/simulated.h"
#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::fusion {

// Simulates a case (200 cycles), runs the force and scan analysis (gross
// slip found with `slip`), then diagnoses the cycles after the first 100
// as the command does.
inline Diagnosis DiagnoseSimulated(samples::SimulationOptions o,
                                   samples::GroundTruth* truth = nullptr,
                                   DiagnoseOptions d = {},
                                   const force::GrossSlipOptions& slip = {}) {
  o.cycles = 200;
  const sim::SimulatedTest t = sim::Simulate(o);
  if (truth) *truth = t.truth;
  FuseOptions f;
  f.fit_lugre = false;
  // Periodic lines kept, as `--notch none` keeps them: the diagnosis names
  // the interference the analysis leaves (by default a line found is
  // removed before the analysis, and there is nothing of it to name).
  f.notch_found_lines = false;
  f.analysis.running_in_cycles = 100;
  f.analysis.slip = slip;
  const TestResult r = AnalyzeTest(t.record, t.scan, f);
  d.running_in_cycles = 100;
  // As `wearscar diagnose` does: the depth from the scan, k where the
  // analysis took it, and of the spring's stiffness and an elastic part
  // the one the track's history supports.
  return DiagnoseTest(t.record, r, f, d);
}

}  // namespace wearscar::fusion
