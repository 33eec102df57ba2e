// A scan of another specimen of the same wood and case, on the
// simulator's 12 cases with growth rings of varying width (each specimen's
// rings fall elsewhere), at noise 1 and 2 and three seeds (80 cycles; the
// scan's field of 8.9 mm holds the whole track, its centre judged):
// flagged where the waviness stands above its noise and differs (not
// always: the simulator's specimens are look-alikes by chance, see the
// counts below), and where it does not stand out, the result says that the
// scan's identity cannot be checked; this specimen's own scan flagged on
// none. docs/method.md quotes the printed counts.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/simulated.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::fusion {
namespace {

bool Doubted(const TestResult& r) {
  if (!r.verdict.scan_doubt.empty()) return true;
  for (const std::string& reason : r.verdict.reasons) {
    if (reason.find("the scan's waviness") != std::string::npos ||
        reason.find("with its track's centre") != std::string::npos ||
        reason.find("the aligned profiles correlate at") != std::string::npos)
      return true;
  }
  return false;
}

bool SaysUncheckable(const TestResult& r) {
  for (const std::string& a : r.assumptions) {
    if (a.find("the scan's identity cannot be checked") != std::string::npos)
      return true;
  }
  return false;
}

TEST(MixupStudy, AnotherSpecimensScanIsFlaggedOrSaidUncheckable) {
  FuseOptions fuse;
  fuse.fit_lugre = false;
  int own = 0, own_flagged = 0, foreign = 0, checkable = 0, caught = 0,
      unsaid = 0, missed = 0;
  for (double noise : {1.0, 2.0}) {
    for (const samples::SimulationOptions& paper : samples::PaperCases(false)) {
      std::vector<sim::SimulatedTest> tests;
      for (int seed = 0; seed < 3; ++seed) {
        samples::SimulationOptions o = paper;
        o.cycles = 80;
        o.noise_scale = noise;
        o.ring_width_cv = 0.25;
        o.scan_cols = 1200;  // an 8.9 mm field: the whole track
        o.seed = 600 + seed + 10 * static_cast<int>(noise);
        tests.push_back(sim::Simulate(o));
      }
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const TestResult r =
              AnalyzeTest(tests[i].record, tests[j].scan, fuse);
          const std::string what = fmt::format(
              "{} noise {} force {} scan {}", paper.name, noise, i, j);
          const bool doubted = Doubted(r);
          if (i == j) {
            ++own;
            own_flagged += doubted;
            EXPECT_FALSE(doubted) << what << ": " << r.verdict.Summary();
            continue;
          }
          ++foreign;
          caught += doubted;
          const bool can = r.mismatch.Identity().checkable;
          checkable += can;
          if (can && !doubted) {
            ++missed;
            fmt::print("missed: {}: waviness r {:.2f}, {:.1f}x its noise\n",
                       what,
                       r.mismatch.waviness_correlation,
                       r.mismatch.waviness_to_noise);
          } else if (!doubted) {
            unsaid += !SaysUncheckable(r);
            EXPECT_TRUE(SaysUncheckable(r)) << what;
          }
        }
      }
    }
  }
  fmt::print(
      "own scans flagged: {} of {}; other specimens' scans flagged: {} of {} "
      "({} checkable by the waviness, {} of these missed); not flagged and "
      "not said uncheckable: {}\n",
      own_flagged,
      own,
      caught,
      foreign,
      checkable,
      missed,
      unsaid);
  // Measured: 144 of 144 flagged, 0 of 109 checkable by the waviness
  // missed. With the centre judged by the track's outline alone (a move
  // beyond 0.25 of its width; the sphere's reversals on the end walls not
  // asked to agree on a smaller one), 130 and 3: this specimen's outline
  // lies up to 0.13 of the width off where the stroke ran on this
  // simulator (a depth trend along the stroke), so the outline alone
  // cannot judge less. Held near that, so that a weaker check fails.
  EXPECT_GE(caught, 140);
  EXPECT_LE(missed, 1);
}

}  // namespace
}  // namespace wearscar::fusion
