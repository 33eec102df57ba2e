#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::app {

// The cases `wearscar simulate` (and wearscar.simulate in Python) runs:
// paper cases with their overrides (-1 = the case's own value).
struct SimulateArgs {
  std::vector<std::string> cases;
  bool all = false;
  int cycles = -1;
  double rate_hz = -1;
  double amplitude_mm = -1, frequency_hz = -1;
  int scan_cols = -1, scan_rows = -1;
  double scan_pitch_mm = -1;
  bool no_elastic = false;
  double noise = -1;             // scale of the calibrated sensor noise
  double elastic_fraction = -1;  // S-RL-R-like elastic part, of the profile
  std::vector<std::string> effect_settings;  // name=value
  bool triangle = false;
  long long seed = -1;
};

// --case, --all, --cycles, --rate, ..., --effect.
void AddSimulationOptions(CLI::App* cmd, SimulateArgs* args);

// The cases asked for, each with the overrides, checked; UsageError for
// an unknown case, effect or an invalid setting.
std::vector<samples::SimulationOptions> SimulationCases(const SimulateArgs& a);

}  // namespace wearscar::app
