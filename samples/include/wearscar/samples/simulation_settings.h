#pragma once

#include <string>
#include <vector>

#include "wearscar/samples/virtual_tribometer.h"
#include "wearscar/support/settings.h"

namespace wearscar::samples {

// What `wearscar simulate` (and wearscar.simulate in Python) is asked for:
// paper cases with their overrides (-1: each case's own value).
struct SimulationRequest {
  std::vector<std::string> cases;
  bool all = false;
  int cycles = -1;
  double rate_hz = -1;
  double amplitude_mm = -1, frequency_hz = -1;
  double spring_n_per_mm = -1;  // the rig's loading spring
  int scan_cols = -1, scan_rows = -1;
  double scan_pitch_mm = -1;
  bool no_elastic = false;
  double noise = -1;                 // scale of the calibrated sensor noise
  double elastic_fraction = -1;      // S-RL-R-like elastic part, of the profile
  double ring_width_cv = -1;         // rings of varying width (sd / mean)
  std::vector<std::string> effects;  // name=value
  bool triangle = false;
  bool rigid_sphere = false;  // the sphere rides the track as a rigid ball
  int record_from = -1;       // the record starts at this cycle of the test
  bool dead_weight = false;   // --rig dead-weight
  int depth_channel = -1;     // --depth-channel on|off; -1: on a dead weight
  long seed = -1;
};

// Every setting of a simulation as text: "case" (repeatable), "all",
// "cycles", "rate", ..., "effect" (name=value, repeatable).
const std::vector<support::Setting<SimulationRequest>>& SimulationSettingList();

// The cases asked for, each with the overrides, checked. Throws
// support::SettingFailed naming the setting for an unknown case or effect
// or an invalid combination.
std::vector<SimulationOptions> SimulationCases(const SimulationRequest& r);

}  // namespace wearscar::samples
