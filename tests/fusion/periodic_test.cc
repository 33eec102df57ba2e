// Periodic lines the drive does not make: found in Q and P,
// warned about, blamed in a failed verdict, and notched out on request.

#include "wearscar/force/periodic.h"

#include <gtest/gtest.h>

#include "common/simulated.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::fusion {
namespace {

sim::SimulatedTest Pickup(double amplitude_n, double frequency_hz) {
  samples::SimulationOptions o = samples::PaperCase("S-RT-R");
  o.cycles = 200;
  o.effects.pickup_n = amplitude_n;
  o.effects.pickup_hz = frequency_hz;
  return sim::Simulate(o);
}

TEST(PeriodicLines, FindsAPickUpLockedToTheDriveOrNotAndNoneOnACleanTest) {
  EXPECT_TRUE(force::FindPeriodicLines(Pickup(0, 50).record, 1.0).empty());
  for (double f : {50.0, 60.03}) {
    const auto lines = force::FindPeriodicLines(Pickup(0.03, f).record, 1.0);
    ASSERT_EQ(lines.size(), 1u) << f;
    EXPECT_NEAR(lines[0].frequency_hz, f, 0.01);
    EXPECT_NEAR(lines[0].q_amplitude_n, 0.03, 0.003);
    EXPECT_NEAR(lines[0].p_amplitude_n, 0.03, 0.003);
    EXPECT_EQ(lines[0].drive_harmonic, f == 50.0 ? 50 : 0);
  }
}

TEST(PeriodicLines, NotchRemovesTheLineAndLittleElse) {
  sim::SimulatedTest t = Pickup(0.03, 50);
  const sim::SimulatedTest clean = Pickup(0, 50);
  const auto [q, p] = force::NotchLine(&t.record, 50.0);
  EXPECT_NEAR(q, 0.03, 0.003);
  EXPECT_NEAR(p, 0.03, 0.003);
  EXPECT_TRUE(force::FindPeriodicLines(t.record, 1.0).empty());
  // What is left differs from the clean record by about the noise's share
  // at 50 Hz, far below the line.
  const double rms =
      std::sqrt((t.record.tangential_n - clean.record.tangential_n)
                    .array()
                    .square()
                    .mean());
  EXPECT_LT(rms, 0.005);
}

// A locked 50 Hz pick-up (at the drive's harmonic it stands still along
// the stroke and reads as the track's slope in P) kept with --notch none
// fails the verdict of a clean test, which says its excess may come from
// the line; by default the line found is removed before the analysis, said
// first, and the test is explained with the clean test's mu-hat; a notch
// given removes it as well.
TEST(PeriodicLines, ALineFoundIsRemovedSaidFirstUnlessKept) {
  const sim::SimulatedTest t = Pickup(0.03, 50);
  FuseOptions f;
  f.fit_lugre = false;
  f.notch_found_lines = false;  // --notch none
  const TestResult kept = AnalyzeTest(t.record, t.scan, f);
  ASSERT_FALSE(kept.verdict.explained);
  ASSERT_EQ(kept.units.Get<std::vector<force::PeriodicLine>>().size(), 1u);
  bool said = false;
  for (const auto& reason : kept.verdict.reasons)
    said =
        said || reason.find("periodic line at 50.00 Hz") != std::string::npos;
  EXPECT_TRUE(said);

  f.notch_found_lines = true;  // the default
  const TestResult found = AnalyzeTest(t.record, t.scan, f);
  EXPECT_TRUE(found.verdict.explained) << found.verdict.Summary();
  ASSERT_FALSE(found.warnings.empty());
  EXPECT_EQ(found.warnings.front().rfind("a periodic line at 50.00 Hz", 0), 0u)
      << found.warnings.front();
  EXPECT_NE(found.warnings.front().find("removed from Q and P before the "
                                        "analysis, as --notch 50.00 would"),
            std::string::npos);
  // The line of the record as read is still listed, and what was removed
  // is in the options the result ran with (the diagnosis removes it too).
  EXPECT_EQ(found.units.Get<std::vector<force::PeriodicLine>>().size(), 1u);
  ASSERT_EQ(found.options.notch_hz.size(), 1u);
  EXPECT_NEAR(found.options.notch_hz[0], 50.0, 0.01);
  EXPECT_NE(found.assumptions.back().find("notched (lines found in the "
                                          "record; --notch none keeps them)"),
            std::string::npos)
      << found.assumptions.back();
  // mu-hat as on the same test without the line, within its interval.
  const TestResult clean = AnalyzeTest(Pickup(0, 50).record, t.scan, f);
  const auto& q = found.mismatch.mu_force;
  EXPECT_NEAR(q.mean, clean.mismatch.mu_force.mean, 0.5 * (q.high - q.low));

  f.notch_hz = {50.0};
  const TestResult n = AnalyzeTest(t.record, t.scan, f);
  EXPECT_TRUE(n.verdict.explained) << n.verdict.Summary();
  EXPECT_NE(n.assumptions.back().find("notched (--notch)"), std::string::npos);
  for (const std::string& w : n.warnings)
    EXPECT_EQ(w.find("removed from Q and P"), std::string::npos) << w;
}

}  // namespace
}  // namespace wearscar::fusion
