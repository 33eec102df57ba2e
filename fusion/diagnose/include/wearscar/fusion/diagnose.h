#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/fusion/diagnosis.h"
#include "wearscar/fusion/effects.h"
#include "wearscar/fusion/fit_mu.h"
#include "wearscar/fusion/result.h"

namespace wearscar::fusion {

// Pearson correlation of the shape (linear between its knots) with a
// profile v(x) over the x the shape spans; NaN when either is constant.
double ShapeCorrelation(const AlongTrackFrictionShape& shape,
                        const Eigen::VectorXd& x_mm,
                        const Eigen::VectorXd& v);

// Greedy forward selection of the effects that the wear-scar model misses.
// `depth_mm` gives the groove depth along the plate coordinate (from the
// scan); without it the force side's profile stands in. k comes from P/S,
// or the depth channel (friction.k_from_depth), per cycle; `slope`, when
// given (the scan's centreline on a rig whose P carries no profile), is
// every cycle's k, and the diagnosis takes the last cycles.
Diagnosis Diagnose(const force::ForceRecord& record,
                   const force::CycleSet& cycles,
                   const FrictionFitOptions& friction,
                   const PlateProfile* depth_mm,
                   const PlateProfile* slope = nullptr,
                   const DiagnoseOptions& options = {});

// Diagnoses a test AnalyzeTest analysed with `fuse`: the groove depth from
// the aligned scan when it was used (levelled reference = unworn), else
// from the force side; k where the analysis took it (result.profile, with
// result.options' spring and depth sign). `fuse` gives the lines notched
// (FuseOptions::notch_hz), removed from the record here as there.
Diagnosis DiagnoseTest(const force::ForceRecord& record,
                       const TestResult& result,
                       const FuseOptions& fuse,
                       const DiagnoseOptions& options = {});

}  // namespace wearscar::fusion
