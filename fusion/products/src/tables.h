#pragma once
// The tables of one test's products, each from the analysis's result (no
// analysis here: formatting only).

#include <string>
#include <vector>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/result.h"
#include "wearscar/fusion/tables.h"

namespace wearscar::fusion::internal {

Table CycleTable(const TestResult& r);
// The samples of the cycles `loops` (0-based; empty: the first, third,
// eleventh and last that exist).
Table LoopTable(const force::ForceRecord& record,
                const TestResult& r,
                std::vector<int> loops);
// profiles.csv: the force side's profiles and the aligned scan profile
// along the plate.
Table ProfileTable(const ScanAnalysis& scan);
// centreline.csv: the scan's centreline.
Table CentrelineTable(const scan::WearProfile& profile);
// loop_viewer.json: each cycle's binned loop, the model's Q with its
// mu-hat and the friction map's row (FrictionMap::loop_*), for the report.
std::string LoopViewerJson(const TestResult& r);

}  // namespace wearscar::fusion::internal
