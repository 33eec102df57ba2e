#pragma once
// The comparison of the force side's and the scan's view of one test over
// its compared cycles (the MismatchReport the verdict judges).

#include <optional>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/result.h"

namespace wearscar::fusion {

// The mismatch over cycles [first, last] with the profile as decided:
// mu-hat with the force side's k only where it is judged (P/S or the
// depth, not the friction's circular profile); the scan's side when
// `scan` is given, with KRmsDifference computed here unless given; the
// force side's mu-hat from `fits`, the scan's from `scan_fits`, the classic
// methods from `classic` (the units "mu_fit_spring" or "mu_fit_depth",
// "mu_fit_scan" and "classic_cofs").
MismatchReport CompareSlopes(
    const force::ForceRecord& record,
    const ForceAnalysis& force,
    const SlopeFits& fits,
    const ClassicCofs& classic,
    const ScanAnalysis* scan,
    const ScanFits& scan_fits,
    const ProfileDecision& profile,
    int first,
    int last,
    const FuseOptions& options,
    std::optional<double> k_rms_difference = std::nullopt);

// RMS of the force side's k minus the scan's slope over the gross-slip
// samples of cycles [first, last] (the force side's ensemble taken over
// those cycles alone); with `parallel`, on two threads.
double KRmsDifference(const force::ForceRecord& record,
                      const ForceAnalysis& force,
                      const PlateProfile& scan_slope,
                      const FrictionFitOptions& friction,
                      int first,
                      int last,
                      bool parallel);

}  // namespace wearscar::fusion
