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

// A locked 50 Hz pick-up fails the verdict of a clean test; the verdict
// says its excess may come from the line, and with the notch the test is
// explained again, the notch said among the assumptions.
TEST(PeriodicLines, VerdictBlamesTheLineAndTheNotchClearsIt) {
  const sim::SimulatedTest t = Pickup(0.03, 50);
  FuseOptions f;
  f.fit_lugre = false;
  const TestResult r = AnalyzeTest(t.record, t.scan, f);
  ASSERT_FALSE(r.verdict.explained);
  ASSERT_EQ(r.units.Get<std::vector<force::PeriodicLine>>().size(), 1u);
  bool said = false;
  for (const auto& reason : r.verdict.reasons)
    said =
        said || reason.find("periodic line at 50.00 Hz") != std::string::npos;
  EXPECT_TRUE(said);
  f.notch_hz = {50.0};
  const TestResult n = AnalyzeTest(t.record, t.scan, f);
  EXPECT_TRUE(n.verdict.explained) << n.verdict.Summary();
  EXPECT_TRUE(n.units.Get<std::vector<force::PeriodicLine>>().empty());
  EXPECT_NE(n.assumptions.back().find("notched (--notch)"), std::string::npos);
}

}  // namespace
}  // namespace wearscar::fusion
