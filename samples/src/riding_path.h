#pragma once
// The path of a rigid sphere that rides a worn track it did not carve to
// its own shape: the worn profile dilated by the sphere along the track
// (a rigid ball bridges the valleys that curve tighter than 1/R), as the
// ball envelope of ISO 16610-41 defines it. The simulator's sphere with
// SimulationOptions::rigid_sphere follows it: P/S and the contact's tilt
// take it, while the scan shows the worn profile.

#include <functional>
#include <map>
#include <utility>

#include "simulator_tools.h"
#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::samples::internal {

class RidingPath {
 public:
  // `worn_depth(u, amplitude)`: the worn depth (mm, into the surface) at
  // u along the track; the path over [-half, half] on a grid of `step`.
  RidingPath(std::function<double(double, double)> worn_depth,
             double radius_mm,
             double half_mm,
             double step_mm = 0.01);
  // On the simulator's groove: the worn profile `shape` (mean 1) times the
  // amplitude over the stroke, the sphere's end walls beyond it.
  RidingPath(const SimulationOptions& o, Grid shape);
  // The sphere's lowest point (mm, up positive: minus the depth where it
  // touches the floor) and its slope, for a depth amplitude; computed once
  // per amplitude to 0.5%.
  const std::pair<Grid, Grid>& At(double amplitude) const;

 private:
  std::function<double(double, double)> worn_depth_;
  double radius_, half_, step_;
  mutable std::map<long, std::pair<Grid, Grid>> cache_;
};

}  // namespace wearscar::samples::internal
