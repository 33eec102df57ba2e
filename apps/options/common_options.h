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
  bool no_k_noise_correction = false;
  std::string running_in = "auto";
  std::string k_estimate = "ensemble";  // ensemble | cycle
  bool large_maps = false;              // --large-maps
  std::string verdict_cost = "excess";  // excess | paper
  std::string slope = "both";  // force | scan | both  // or a number of cycles
  std::string columns;         // time=NAME,x=NAME,q=NAME,p=NAME (names or #N)
};

// Groups of shared options; a command adds those it uses, so that its
// --help lists nothing it ignores.
enum OptionGroup : unsigned {
  kForceFileOptions = 1u << 0,  // columns, units, rate
  kSlopeOptions = 1u << 1,      // spring, k estimate, stencil, running-in
  kVerdictOptions = 1u << 2,    // the verdict's limits
  kLugreOptions = 1u << 3,
  kCompareOptions = 1u << 4,  // the slope choice, cycles compared with the scan
  kScanFileOptions = 1u << 5,    // reading a scan
  kLevelTrackOptions = 1u << 6,  // levelling and the track of a scan
  kMapOptions = kScanFileOptions | kLevelTrackOptions,
};
constexpr unsigned kForceCommandOptions =
    kForceFileOptions | kSlopeOptions | kVerdictOptions | kLugreOptions;
constexpr unsigned kFuseOptions =
    kForceCommandOptions | kCompareOptions | kMapOptions;
constexpr unsigned kDiagnoseOptions =
    kForceFileOptions | kSlopeOptions | kMapOptions;

void AddCommonOptions(CLI::App* cmd, CommonArgs* args, unsigned groups);

// Applies the string options and checks everything; UsageError when invalid.
void FinaliseCommonOptions(CommonArgs* args);

}  // namespace wearscar::app
