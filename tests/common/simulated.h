#pragma once

// The virtual tribometer's test with its channels as the force record the
// analysis reads (samples knows nothing of the force library).

#include <utility>

#include "wearscar/force/force_record.h"
#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::sim {

struct SimulatedTest {
  force::ForceRecord record;
  scan::HeightMap scan;
  samples::GroundTruth truth;
};

inline SimulatedTest Simulate(const samples::SimulationOptions& options) {
  samples::SimulatedTest t = samples::Simulate(options);
  return {force::RecordFromChannels(std::move(t.record), "simulated"),
          std::move(t.scan),
          std::move(t.truth)};
}

}  // namespace wearscar::sim
