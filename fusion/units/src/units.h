#pragma once
// The analysis units of the registry (registry.cc), each defined in a file
// of its own, and what their figures share.

#include <string>
#include <vector>

#include "wearscar/fusion/unit.h"

namespace wearscar::fusion::internal {

const AnalysisUnit& ClassicCofsAnalysis();    // classic_cofs_unit.cc
const AnalysisUnit& SpringFitAnalysis();      // mu_fit_unit.cc
const AnalysisUnit& DepthFitAnalysis();       // mu_fit_unit.cc
const AnalysisUnit& ScanFitAnalysis();        // mu_fit_unit.cc
const AnalysisUnit& DetailCycleAnalysis();    // detail_cycle_unit.cc
const AnalysisUnit& PeriodicLinesAnalysis();  // periodic_lines_unit.cc
const AnalysisUnit& LugreAnalysis();          // lugre_unit.cc
const AnalysisUnit& FrictionMapAnalysis();    // friction_map_unit.cc
const AnalysisUnit& ScanShapeAnalysis();      // scan_shape_unit.cc
const AnalysisUnit& TrackHistoryAnalysis();   // track_history_unit.cc
const AnalysisUnit& SlidingAnalysis();        // wear_unit.cc
const AnalysisUnit& WearAnalysis();           // wear_unit.cc
const AnalysisUnit& SpringCheckAnalysis();    // spring_check_unit.cc
const AnalysisUnit& ScanIdentityAnalysis();   // scan_identity_unit.cc
const AnalysisUnit& ScreenAnalysis();         // screen_unit.cc

}  // namespace wearscar::fusion::internal
