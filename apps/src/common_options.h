#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "wearscar/force/read_force.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/scan/read_scan.h"

namespace wearscar::app {

// Options shared by force, fuse and audit.
struct CommonArgs {
  force::ReadForceOptions read_force;
  scan::ReadScanOptions read_scan;
  fusion::FuseOptions fuse;
  std::string derivative = "central";
  std::string scan_derivative = "savgol";
  bool no_lugre = false;
  std::string running_in = "auto";
  std::string k_estimate = "ensemble";  // ensemble | cycle
  bool large_maps = false;              // --large-maps
  std::string verdict_cost = "excess";  // excess | paper
  std::string slope = "both";  // force | scan | both  // or a number of cycles
  std::string columns;         // time=NAME,x=NAME,q=NAME,p=NAME (names or #N)
};

void AddCommonOptions(CLI::App* cmd, CommonArgs* args, bool with_scan);

// Applies the string options and checks everything; UsageError when invalid.
void FinaliseCommonOptions(CommonArgs* args);

}  // namespace wearscar::app
