#pragma once

#include <string>

#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::app {

// Diagnoses one analysed test: the groove depth comes from the aligned scan
// when there is one (levelled reference = unworn), else from the force side.
fusion::Diagnosis DiagnoseTest(const force::ForceRecord& record,
                               const fusion::TestResult& result,
                               const fusion::FuseOptions& fuse,
                               const fusion::DiagnoseOptions& options);

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
