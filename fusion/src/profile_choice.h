#pragma once
// The choice of the force side's profile (FuseOptions::profile_from) and
// the words that say it (TestResult::profile_reason).

#include <string>

#include "wearscar/fusion/fuse.h"

namespace wearscar::fusion::internal {

// How far P's repeatable slope is from nothing, in its standard errors;
// NaN without the k split.
double ProfileSignificance(const ForceAnalysis& force);

// The correlation of the depth channel's profile with the friction's over
// the last cycles after running-in (the signs as read); NaN when either
// cannot be built.
double DepthAgreement(const force::ForceRecord& record,
                      const ForceAnalysis& force);

// The correlation of P/S's profile with the depth channel's over the same
// cycles (a spring's P follows the depth: near +-1); NaN when either cannot
// be built.
double SpringDepthAgreement(const force::ForceRecord& record,
                            const ForceAnalysis& force,
                            double spring_n_per_mm);

// auto's choice on a result analysed with P/S (its scan aligned with it).
ProfileSource ChooseProfile(const TestResult& r, const FuseOptions& o);

// The result's profile source and why, in words; `chosen` when auto chose
// it, `spring_ratio` P/S's amplitude against the scanned profile as the
// choice read it (NaN without a scan).
std::string ProfileReason(const TestResult& r,
                          const FuseOptions& o,
                          bool chosen,
                          double spring_ratio);

}  // namespace wearscar::fusion::internal
