#pragma once

#include <string>
#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/force/turn_delay.h"

namespace wearscar::fusion {

struct TrackHistoryOptions {
  double bin_mm = 0.1;  // along the stroke
  // The waviness is steady from the first cycle after which it stays
  // within this fraction of its late trend (a line fitted over the second
  // half of the test).
  double steady_tolerance = 0.05;
  // The waviness of a cycle pools the (noise-corrected) variance of h over
  // this many cycles centred on it (odd; shifted inwards at the ends):
  // along the rings the waviness is 1-2 um, about the P sensor's
  // resolution over S, and a single cycle's estimate scatters by 10-30%;
  // the track changes little over a few cycles after running-in.
  int pool_cycles = 15;

  bool IsValid(std::string* why) const;
};

// The track's history from the spring alone: the force-side profile P/S of
// every cycle and direction, relative to its own mean (the load control
// holds the mean force, not the shape), is the track's shape under load as
// it wears: h(x, cycle), in mm, negative where the track is deeper.
struct TrackHistory {
  std::vector<double> x_mm;  // bin centres
  int cycles = 0;
  // At (cycle * 2 + direction) * bins + bin; NaN where a bin is empty.
  std::vector<double> height_mm;
  // Per cycle: the sd of h along the stroke (the waviness amplitude), the
  // root of the noise-corrected variance over the two directions and over
  // TrackHistoryOptions::pool_cycles cycles about this one.
  std::vector<double> waviness_sd_mm;
  // Per cycle: the sliding path's height from the friction alone, at
  // cycle * bins + bin. On the wear-scar model the two directions at the
  // same x see atan(Q/P) = theta + s atan(mu), so their mean is the
  // path's inclination whatever the spring and any elastic part (which
  // move P, not the contact's tilt); tan(theta) integrated along x, about
  // its mean. NaN where the two directions did not both slide.
  std::vector<double> friction_height_mm;
  // How late Q turns at the reversals behind x (a lag of the Q channel),
  // over every cycle: the friction's path needs Q in time with x.
  force::TurnDelay q_turn;
  int steady_cycle = 0;               // 0-based
  double final_waviness_sd_mm = 0.0;  // over the last tenth of the cycles
  double growth_per_cycle_mm = 0.0;   // of the late trend

  size_t Index(int cycle, int direction, size_t bin) const {
    return (static_cast<size_t>(cycle) * 2 + direction) * x_mm.size() + bin;
  }
  size_t FrictionIndex(int cycle, size_t bin) const {
    return static_cast<size_t>(cycle) * x_mm.size() + bin;
  }
};

// Throws FusionError for invalid options. Requires record.IsConsistent().
TrackHistory ComputeTrackHistory(const force::ForceRecord& record,
                                 const force::CycleSet& cycles,
                                 double spring_n_per_mm,
                                 const TrackHistoryOptions& options = {});

}  // namespace wearscar::fusion
