#pragma once

#include "common/simulated.h"
#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::fusion {

// Simulates a case (200 cycles), runs the force and scan analysis for the
// cycles (gross slip found with `slip`) and the aligned groove depth, then
// diagnoses the cycles after the first 100.
inline Diagnosis DiagnoseSimulated(samples::SimulationOptions o,
                                   samples::GroundTruth* truth = nullptr,
                                   DiagnoseOptions d = {},
                                   const force::GrossSlipOptions& slip = {}) {
  o.cycles = 200;
  const sim::SimulatedTest t = sim::Simulate(o);
  if (truth) *truth = t.truth;
  FuseOptions f;
  f.fit_lugre = false;
  f.analysis.running_in_cycles = 100;
  f.analysis.slip = slip;
  const TestResult r = AnalyzeTest(t.record, t.scan, f);
  PlateProfile depth;
  depth.x_mm = r.scan->force_profile.x_mm;
  depth.k = -ScanHeightAtPlate(r.scan->profile, r.scan->alignment, depth.x_mm);
  d.running_in_cycles = 100;
  return Diagnose(
      t.record, r.force.cycles, f.analysis.friction, &depth, nullptr, d);
}

}  // namespace wearscar::fusion
