#pragma once
// The scan side of the pipeline (scan_side.cc): the scan aligned with the
// force side's profile and its slope over the stroke.

#include <future>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/fuse_options.h"
#include "wearscar/fusion/result.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion::internal {

// The cycles the profiles are compared over: the last
// ForceProfileOptions::cycles after running-in, unless a range was given.
ForceProfileOptions ComparedCycles(const ForceAnalysis& force,
                                   const FuseOptions& options);

// The force side's profile over the compared cycles (the last N, none of
// the running-in) from `source`, aligned with the prepared scan's sphere
// path or centreline (ChoosePath: the premise that a rigid sphere rides
// the track, checked on which path the force side follows). Throws
// FusionError naming both files when they cannot be aligned.
ScanAnalysis AlignScan(const force::ForceRecord& record,
                       const ForceAnalysis& force,
                       ScanAnalysis s,
                       const FuseOptions& options,
                       ProfileSource source,
                       double depth_sign);

// The scan's slope in plate coordinates over the stroke.
PlateProfile ScanSlopeOverTheStroke(const force::ForceRecord& record,
                                    const ForceAnalysis& force,
                                    const FuseOptions& options,
                                    const ScanAnalysis& s);

}  // namespace wearscar::fusion::internal
