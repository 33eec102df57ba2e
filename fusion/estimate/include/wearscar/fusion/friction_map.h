#pragma once

#include <string>
#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/fusion/fit_mu.h"

namespace wearscar::fusion {

struct FrictionMapOptions {
  // Bin width along the stroke, mm: about the contact radius (the paper's
  // 3.25 mm sphere under 30 N on wood leaves a track about 1-1.5 mm wide).
  double bin_mm = 0.5;
  // A bin of a cycle and direction with fewer gross-slip samples is empty.
  int min_samples = 3;
  // The map's k: the ensemble slope of the fit (FrictionFitOptions) with
  // the local polynomial's degree and span replaced by these. The fit's
  // quadratic is biased at the track's steepest flanks by about span^2
  // P'''/40, which averages out of a cycle's mu-hat but stays in the map,
  // bin by bin; a cubic removes that term (0 keeps the fit's).
  int slope_polynomial_order = 3;
  double slope_span_mm = 0.1;
  // Each cycle's loop, binned this many times along the stroke
  // (FrictionMap::loop_*): what the report's loop viewer draws. 0: none
  // (and no viewer).
  int loop_bins = 100;

  bool IsValid(std::string* why) const;
};

// The friction coefficient along the stroke, per cycle and direction: raw,
// s Q / P, and corrected for the slope k of the sliding path, Eqs. 1-2
// solved for the local coefficient at each gross-slip sample,
//   mu_local = s (Q - P k) / (P + k Q),
// with k the force side's (1/S) dP/dx. Where the wear-scar interaction
// explains the loops the corrected map is flat along x while the raw one
// follows the track; where it is not, friction varies along the track or an
// effect is missing.
struct FrictionMap {
  std::vector<double> x_mm;  // bin centres
  // The slope fit's span and polynomial order the map used: the options',
  // the span at least two of the fit's bins.
  double slope_span_mm = 0.0;
  int slope_polynomial_order = 0;
  int cycles = 0;
  // Per (cycle, direction, bin) at (cycle * 2 + direction) * bins + bin;
  // direction 0 forward, 1 reverse. NaN where the bin is empty.
  std::vector<double> mu_raw, mu_corrected;
  std::vector<int> samples;
  // The along-track variation over the steady cycles: the sd over x of the
  // map averaged over those cycles (each cycle and direction about its own
  // mean, so the drift of mu over cycles does not count), raw and
  // corrected, and the sd that the noise alone leaves in that average (the
  // standard error of each bin's mean over cycles, rms over the bins).
  int first_steady_cycle = 0;
  double spatial_sd_raw = 0.0;
  double spatial_sd_corrected = 0.0;
  double spatial_sd_noise = 0.0;
  // What the corrected sd has beyond the floor: sqrt(sd^2 - floor^2), 0
  // when the floor explains it all.
  double spatial_sd_excess = 0.0;
  // The steady average per direction and bin (forward then reverse), about
  // each direction's mean: the along-track pattern of mu.
  std::vector<double> steady_corrected;
  // Each cycle's gross-slip loop binned finely along the stroke: the means
  // of Q (N), P (N) and k (the map's slope) per (cycle, direction, bin) at
  // LoopIndex, over the bins centred at loop_x_mm; NaN where a bin is
  // empty. The wear-scar model's Q of a cycle follows from them and its
  // mu-hat (LoopModelQ).
  std::vector<double> loop_x_mm;
  std::vector<float> loop_q_n, loop_p_n, loop_k;

  size_t Index(int cycle, int direction, size_t bin) const {
    return (static_cast<size_t>(cycle) * 2 + direction) * x_mm.size() + bin;
  }
  size_t LoopIndex(int cycle, int direction, size_t bin) const {
    return (static_cast<size_t>(cycle) * 2 + direction) * loop_x_mm.size() +
           bin;
  }
  // The wear-scar model's Q at a loop bin with coefficient mu (Eqs. 1-2 on
  // the bin's mean P and k); NaN where the bin is empty.
  double LoopModelQ(int cycle, int direction, size_t bin, double mu) const;
};

// The map of every complete cycle; the variation over cycles
// [first_steady, last]. Throws FusionError for invalid options.
// Requires record.IsConsistent().
FrictionMap ComputeFrictionMap(const force::ForceRecord& record,
                               const force::CycleSet& cycles,
                               const FrictionFitOptions& friction,
                               int first_steady,
                               const FrictionMapOptions& options = {});

}  // namespace wearscar::fusion
