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
  samples::SimulatedChannels& c = t.record;
  return {force::RecordFromChannels(std::move(c.time_s),
                                    std::move(c.x_mm),
                                    std::move(c.tangential_n),
                                    std::move(c.normal_n),
                                    c.source,
                                    "simulated",
                                    c.sampling_rate_hz),
          std::move(t.scan),
          std::move(t.truth)};
}

}  // namespace wearscar::sim
