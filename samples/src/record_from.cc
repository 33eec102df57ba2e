#include "record_from.h"

#include <cmath>

namespace wearscar::samples::internal {
namespace {

Eigen::VectorXd Tail(const Eigen::VectorXd& v, Eigen::Index from) {
  if (v.size() == 0) return v;
  return v.tail(v.size() - from);
}

}  // namespace

SimulatedTest SimulateFrom(const SimulationOptions& o) {
  SimulationOptions whole = o;
  whole.cycles = o.cycles + o.record_from_cycle;
  whole.record_from_cycle = 0;
  SimulatedTest t = Simulate(whole);
  // The record starts at x = 0 going up: the cycle's first period
  // boundary (a cycle runs from minimum to minimum, a quarter later).
  SimulatedChannels& r = t.record;
  const Eigen::Index from = std::min<Eigen::Index>(
      r.size() - 1,
      static_cast<Eigen::Index>(std::llround(
          o.record_from_cycle * r.sampling_rate_hz / o.frequency_hz)));
  const double t0 = r.time_s[from];
  r.time_s = (Tail(r.time_s, from).array() - t0).matrix();
  r.x_mm = Tail(r.x_mm, from);
  r.tangential_n = Tail(r.tangential_n, from);
  r.normal_n = Tail(r.normal_n, from);
  r.depth_mm = Tail(r.depth_mm, from);
  GroundTruth& g = t.truth;
  g.mu_per_cycle = g.mu_per_cycle.tail(o.cycles).eval();
  g.waviness_sd_mm = g.waviness_sd_mm.tail(o.cycles).eval();
  return t;
}

}  // namespace wearscar::samples::internal
