#pragma once
// The verdict on one test: whether the wear-scar model explains its loops,
// judged on the comparison (mismatch.h) by the limits (verdict_options.h),
// reading the spring check's, the scan identity's and the screen's
// findings; and the data warnings.

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "wearscar/fusion/align.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/mismatch.h"
#include "wearscar/fusion/scan_identity.h"
#include "wearscar/fusion/screen.h"
#include "wearscar/fusion/spring_check.h"
#include "wearscar/fusion/verdict_options.h"

namespace wearscar::fusion {

// When the data cannot carry the method well (warnings, not a verdict).
struct DataWarningOptions {
  int min_samples_per_stroke = 100;    // per half cycle, for the slope
  double max_fallback_fraction = 0.5;  // half cycles on the central fallback
  // Warn of an elastic part below the verdict's margin: the lower end of
  // the share the spring check splits off P/S above this; where it did not
  // judge P/S (a depth channel's profile), the lower end of the amplitude
  // ratio against the scan above 1 + this.
  double elastic_share = 0.05;
  bool IsValid(std::string* why) const;
};

struct Verdict {
  bool explained = false;
  std::vector<std::string> reasons;  // every criterion that failed
  // Set when the scan's profile does not match P/S (correlation below the
  // limit) while the force side alone passes: the scan may be another
  // test's, so it is not judged; the sentence says so (a warning).
  std::string scan_doubt;
  // Set when the test cannot be judged: P carries no profile (a dead
  // weight, or a track too flat to show) and nothing else gives k (no scan,
  // no depth channel); says so and what would. `explained` is then false.
  std::string not_judged;
  // Set when the test passes but its loops repeat a misfit above their
  // noise (VerdictOptions::screen_excess_to_floor): an effect the model
  // misses may bias mu-hat; says so and points to `wearscar diagnose`. The
  // headline then quotes mu as not settled. Judged with the force side's k
  // only (the scan's J holds the track's growth too).
  std::string screen;
  std::string Summary()
      const;  // "explained by wear-scar interaction" or "not explained: ..."
};

Verdict Judge(const MismatchReport& report, const VerdictOptions& options = {});

// Warnings on how well the data can carry the method: too few samples per
// stroke for the slope, gross slip found by the fallback on most half
// cycles, k dominated by noise (in the force side's `fits`), an elastic
// part. One sentence each, with the
// figure and the limit.
std::vector<std::string> DataWarnings(const ForceAnalysis& force,
                                      const SlopeFits& fits,
                                      const MismatchReport& report,
                                      const DataWarningOptions& options = {});

}  // namespace wearscar::fusion
