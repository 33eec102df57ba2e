#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::app {

// What to write besides the summary.
struct WriteOptions {
  std::vector<int>
      loop_cycles;  // hysteresis loops to export (empty = 3 early + last)
  int detail_cycle =
      -1;  // cycle for slope, reconstruction and J(mu); -1 = last
};

// The columns of cycles.csv, and the 1-based index of one of them (for
// the figures' gnuplot scripts; aborts on a name that is not a column).
const std::vector<std::string>& CycleColumns();
int CycleColumn(const std::string& name);

// Summary of one test as JSON (also the row of the audit table).
nlohmann::json ResultJson(const std::string& name,
                          const force::ForceRecord& record,
                          const fusion::TestResult& result,
                          const fusion::FuseOptions& options);

// Writes result.json, cycles.csv, loops.csv, detail.csv, cost_curve.csv and,
// with a scan, profiles.csv into `dir`; returns the files written.
std::vector<std::string> WriteTestResults(const std::string& dir,
                                          const std::string& name,
                                          const force::ForceRecord& record,
                                          const fusion::TestResult& result,
                                          const fusion::FuseOptions& options,
                                          const WriteOptions& write = {});

// Adds a warning to the result.json in `dir` (figures that were asked for
// and not drawn are known only after it was written).
void AddWarningToResult(const std::string& dir, const std::string& warning);

// Exit status of fuse and audit when the results were written but figures
// asked for were not drawn (README).
constexpr int kExitFiguresMissing = 4;

// Prints the human summary of one test to stdout.
void PrintSummary(const std::string& name, const fusion::TestResult& result);

}  // namespace wearscar::app
