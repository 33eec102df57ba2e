#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "wearscar/force/force_record.h"

namespace wearscar::force {

// One monotonic half of a cycle: samples [begin, end) between two reversals.
// direction = +1 forward (x increasing), -1 reverse.
struct HalfCycle {
  Eigen::Index begin = 0;
  Eigen::Index end = 0;
  int direction = 0;
  // Gross-slip window [slip_begin, slip_end) inside the half; filled by
  // FindGrossSlip.
  Eigen::Index slip_begin = 0;
  Eigen::Index slip_end = 0;
  bool slip_fallback = false;  // the central-fraction fallback was used
};

// A cycle starts at a minimum of x: a forward half, then a reverse half.
struct Cycle {
  int index = 0;  // 0-based among the complete cycles
  HalfCycle forward;
  HalfCycle reverse;
};

struct CycleSet {
  std::vector<Cycle> cycles;
  // Samples before the first and after the last complete cycle, reported.
  Eigen::Index leading_samples_dropped = 0;
  Eigen::Index trailing_samples_dropped = 0;
  double stroke_mm = 0.0;  // robust peak-to-peak of x
  std::vector<std::string> notes;
  // The least and greatest finite x of the complete cycles' samples,
  // [cycles.front().forward.begin, cycles.back().reverse.end), mm, as
  // SegmentCycles found them in the x whose values start at x_range_of
  // (CyclesXRange: the grids and stroke bounds of the analysis each took
  // a pass over x for them, nine per test).
  double x_min_mm = 0.0, x_max_mm = 0.0;
  const double* x_range_of = nullptr;
};

// The least and greatest finite x of the complete cycles' samples of
// `x_mm` (+inf and -inf when there are none): CycleSet's own when it was
// segmented from this x, else by a pass over it.
std::pair<double, double> CyclesXRange(
    const Eigen::Ref<const Eigen::VectorXd>& x_mm, const CycleSet& cycles);

struct SegmentOptions {
  // Reversal hysteresis as a fraction of the robust stroke (p99 - p1): x must
  // come back by this much from an extreme before that extreme counts.
  double hysteresis_fraction = 0.1;
  // Fewer complete cycles than this is an error.
  int min_cycles = 2;

  bool IsValid(std::string* why) const;
};

// Finds reversals in x with hysteresis thresholds (robust to noise and to
// sinusoidal, triangular or constant-speed drives) and groups them into
// complete cycles; incomplete first and last cycles are dropped and counted.
// Throws ForceError (naming `source`) when fewer than min_cycles remain.
CycleSet SegmentCycles(const Eigen::Ref<const Eigen::VectorXd>& x_mm,
                       const SegmentOptions& options = {},
                       const std::string& source = "force record");

struct GrossSlipOptions {
  // Tangential stiffness criterion: slip starts at the first sample after
  // the reversal where the local |dQ/dx| falls below this fraction of the
  // stick stiffness measured just after the reversal.
  double stiffness_fraction = 0.2;
  // Local dQ/dx is a least-squares slope over this many samples.
  int slope_window = 9;
  // Samples after the reversal used to measure the stick stiffness.
  int stick_samples = 9;
  // The stick is the first 5-30% of Q's climb instead of 20-80% when that
  // part is this much stiffer (a steep wall moves the sliding level).
  double early_stick_ratio = 1.5;
  // The window must hold at least this fraction of the half's stroke;
  // otherwise the fallback is used.
  double min_window_fraction = 0.3;
  // Fallback: the central fraction of the half's stroke.
  double fallback_central_fraction = 0.8;
  // Samples dropped before the next reversal (0 = slip to the end).
  int end_margin_samples = 0;
  // The paper's procedure: gross slip is the central fraction of every
  // half's stroke (fallback_central_fraction), no stiffness criterion. Such
  // windows are not counted as fallbacks.
  bool central_fraction_only = false;

  bool IsValid(std::string* why) const;
};

// Fills slip_begin / slip_end of every half cycle.
void FindGrossSlip(const ForceRecord& record,
                   CycleSet* cycles,
                   const GrossSlipOptions& options = {});

// A record that grew since `known` was segmented from it (SegmentCycles
// and FindGrossSlip, its indices the record's): the known cycles as they
// were, then those completed since, segmented by SegmentCycles' rule from
// the middle of the last known cycle's reverse half (its end, a minimum, is
// found again) with their gross slip: the cycles segmenting the whole
// record gives, for the samples of a few. The hysteresis is that of the
// known cycles' stroke.
// No cycles when none is known or the new ones do not start where the
// known end (segment the record afresh then); the known ones alone when
// none has completed since.
CycleSet ExtendCycles(const ForceRecord& record,
                      const CycleSet& known,
                      const SegmentOptions& segment = {},
                      const GrossSlipOptions& slip = {});

}  // namespace wearscar::force
