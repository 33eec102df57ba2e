#include "wearscar/fusion/wear.h"

#include <cmath>
#include <limits>

#include "wearscar/support/check.h"

namespace wearscar::fusion {

Sliding MeasureSliding(const force::ForceRecord& record,
                       const force::CycleSet& cycles) {
  WEARSCAR_CHECK(record.IsConsistent(), "MeasureSliding needs one length");
  double distance_mm = 0, load_sum = 0;
  long load_n = 0;
  for (const force::Cycle& c : cycles.cycles) {
    for (const force::HalfCycle* h : {&c.forward, &c.reverse}) {
      if (h->end <= h->begin) continue;
      const double travel = record.x_mm[h->end - 1] - record.x_mm[h->begin];
      if (std::isfinite(travel)) distance_mm += std::abs(travel);
      for (Eigen::Index i = h->begin; i < h->end; ++i) {
        if (!std::isfinite(record.normal_n[i])) continue;
        load_sum += record.normal_n[i];
        ++load_n;
      }
    }
  }
  return {
      load_n > 0 ? load_sum / load_n : std::numeric_limits<double>::quiet_NaN(),
      distance_mm * 1e-3};
}

Wear WearOf(const Sliding& sliding, const std::optional<scan::Track>& track) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Wear w;
  w.normal_load_n = sliding.normal_load_n;
  w.sliding_distance_m = sliding.sliding_distance_m;
  if (!track) {
    w.volume_mm3 = w.mean_depth_mm = w.max_depth_mm = w.width_mm = w.length_mm =
        w.specific_rate_mm3_per_n_m = nan;
    return w;
  }
  w.volume_mm3 = track->volume_mm3;
  w.mean_depth_mm = track->mean_depth_mm;
  w.max_depth_mm = track->max_depth_mm;
  w.width_mm = track->width_mm;
  w.length_mm = track->length_mm;
  const double work = w.normal_load_n * w.sliding_distance_m;
  w.specific_rate_mm3_per_n_m = work > 0 ? w.volume_mm3 / work : nan;
  return w;
}

}  // namespace wearscar::fusion
