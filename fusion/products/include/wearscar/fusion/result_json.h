#pragma once
// result.json's contents from a test's result (and scan.json's parts of a
// map alone), formatted only: result_json.cc. diagnosis.json's are the
// diagnosis's (diagnosis_files.h).

#include <nlohmann/json.hpp>
#include <string>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/provenance.h"
#include "wearscar/fusion/result.h"
#include "wearscar/scan/level.h"
#include "wearscar/scan/track.h"

namespace wearscar::fusion {

// The summary of one test (result.json; also a row of an audit's table):
// inputs, every option that shaped the analysis, running-in, statistics
// after running-in, the comparison of the slopes, the scan's levelling,
// track and alignment, the verdict, the warnings, and each analysis unit's
// section (LuGre, the friction map, ...) under its kind, with the options
// the analysis ran with (result.options). With a provenance, its
// "provenance" too.
nlohmann::json ResultJson(const std::string& name,
                          const force::ForceRecord& record,
                          const TestResult& result,
                          const Provenance* provenance = nullptr);

// The worn track and the levelling as JSON (result.json, scan.json).
nlohmann::json TrackJson(const scan::Track& track);
nlohmann::json LevelJson(const scan::LevelSummary& level);

}  // namespace wearscar::fusion
