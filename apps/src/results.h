#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"

namespace wearscar::app {

using fusion::CycleColumn;
using fusion::CycleColumns;
using fusion::ResultJson;

// Writes the products of one test (fusion::MakeTestProducts) into `dir`,
// each atomically; returns result.json's contents.
nlohmann::json WriteTestResults(const std::string& dir,
                                const std::string& name,
                                const force::ForceRecord& record,
                                const fusion::TestResult& result,
                                const fusion::FuseOptions& options,
                                const fusion::ProductOptions& write = {});

// Adds a warning to the result.json in `dir` (figures that were asked for
// and not drawn are known only after it was written).
void AddWarningToResult(const std::string& dir, const std::string& warning);

// Exit status of fuse and audit when the results were written but figures
// asked for were not drawn (README).
constexpr int kExitFiguresMissing = 4;
// Exit status of audit when any specimen failed (the rest are complete);
// 2 stays a usage error.
constexpr int kExitSpecimensFailed = 3;

// Prints the human summary of one test to stdout.
void PrintSummary(const std::string& name, const fusion::TestResult& result);

}  // namespace wearscar::app
