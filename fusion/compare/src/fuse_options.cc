// The options of one test's analysis: their checks and the slope choice's
// names.

#include "wearscar/fusion/fuse_options.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace wearscar::fusion {
namespace {

bool CheckScanSlopeScale(double max_scale, std::string* why) {
  if (max_scale >= 1.0 && std::isfinite(max_scale)) return true;
  if (why) *why = "max_scan_slope_scale must be finite and >= 1";
  return false;
}

bool CheckAgreements(const FuseOptions& o, std::string* why) {
  for (double a : {o.spring_depth_agreement, o.depth_turn_agreement}) {
    if (!(a >= 0.0 && a <= 1.0)) {
      if (why)
        *why = "spring_depth_agreement and depth_turn_agreement must be 0-1";
      return false;
    }
  }
  return true;
}

}  // namespace

AnalysisOptions FuseOptions::ForceSide() const {
  AnalysisOptions ao = analysis;
  ao.fit_force_slope = slopes != SlopeChoice::kScan;
  if (parallel) ao.friction.threads = std::max(ao.friction.threads, 2);
  return ao;
}

bool FuseOptions::IsValid(std::string* why) const {
  for (double f : notch_hz) {
    if (!(f > 0) || !std::isfinite(f)) {
      if (why) *why = "notch frequencies must be > 0 Hz";
      return false;
    }
  }
  if (cost_curve_points < 2 || cost_curve_points > 1000000) {
    if (why) *why = "cost_curve_points must be 2 to 10^6";
    return false;
  }
  return analysis.IsValid(why) && level.IsValid(why) && track.IsValid(why) &&
         profile.IsValid(why) && sphere.IsValid(why) &&
         force_profile.IsValid(why) && align.IsValid(why) &&
         scan_slope.IsValid(why) && verdict.IsValid(why) &&
         warnings.IsValid(why) && spring_check.IsValid(why) &&
         friction_map.IsValid(why) && track_history.IsValid(why) &&
         CheckScanSlopeScale(max_scan_slope_scale, why) &&
         CheckAgreements(*this, why);
}

const char* SlopeChoiceName(SlopeChoice choice) {
  switch (choice) {
    case SlopeChoice::kForce:
      return "force";
    case SlopeChoice::kScan:
      return "scan";
    case SlopeChoice::kBoth:
      break;
  }
  return "both";
}

bool ParseSlopeChoice(const std::string& name, SlopeChoice* choice) {
  if (name == "force") {
    *choice = SlopeChoice::kForce;
  } else if (name == "scan") {
    *choice = SlopeChoice::kScan;
  } else if (name == "both") {
    *choice = SlopeChoice::kBoth;
  } else {
    return false;
  }
  return true;
}

}  // namespace wearscar::fusion
