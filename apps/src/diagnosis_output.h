#pragma once

#include <string>

#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::app {

using fusion::DiagnoseTest;

// "c_p_N_per_mm = 7.5 +- 0.2, ..."
std::string ParameterText(const fusion::CandidateResult& c);

// Prints the table of steps to stdout.
void PrintDiagnosis(const std::string& name,
                    const fusion::Diagnosis& d,
                    bool from_scan);

// diagnosis.json, residual_map_before.csv / after.csv and (with figures)
// diagnosis_residual_map.png/.svg in `dir`. Returns the PNG path or "".
std::string WriteDiagnosis(const std::string& dir,
                           const std::string& name,
                           const fusion::Diagnosis& d,
                           bool figures);

}  // namespace wearscar::app
