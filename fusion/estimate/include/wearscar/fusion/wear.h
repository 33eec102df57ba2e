#pragma once

#include <optional>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/scan/track.h"

namespace wearscar::fusion {

// The wear of one test: the worn track's size from the scan, the load and
// sliding distance from the force record, and Archard's specific wear rate
// k = V / (F_N s). Without a scan only the force side is known (the scan
// side NaN).
struct Wear {
  double volume_mm3 = 0.0;  // below the levelled reference, inside the track
  double mean_depth_mm = 0.0;
  double max_depth_mm = 0.0;
  double width_mm = 0.0;
  double length_mm = 0.0;
  double normal_load_n = 0.0;       // mean P over the complete cycles
  double sliding_distance_m = 0.0;  // both halves of every complete cycle
  double specific_rate_mm3_per_n_m = 0.0;
};

// The force side of the wear: the mean load and the sliding distance.
struct Sliding {
  double normal_load_n = 0.0;       // mean P over the complete cycles
  double sliding_distance_m = 0.0;  // both halves of every complete cycle
};

// From the complete cycles of `record`: the distance is the sum of every
// half cycle's travel from reversal to reversal, so sensor noise on x does
// not lengthen it.
Sliding MeasureSliding(const force::ForceRecord& record,
                       const force::CycleSet& cycles);

// The wear from the sliding and the track, when there is one.
Wear WearOf(const Sliding& sliding, const std::optional<scan::Track>& track);

}  // namespace wearscar::fusion
