#pragma once

#include <string>

#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::app {

// Prints the human summary of one test to stdout (text mode).
void PrintSummary(const std::string& name, const fusion::TestResult& result);

// Prints the diagnosis's table of steps to stdout (text mode).
void PrintDiagnosis(const std::string& name,
                    const fusion::Diagnosis& d,
                    bool from_scan);

}  // namespace wearscar::app
