// Track histories other than a groove grown from the first contact, on the
// project's simulator: a record that starts late in the test (a pre-worn
// or resumed specimen, a later block of a long test), and the second part
// of a test cut in two, analysed alone.

#include "common/histories.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "wearscar/fusion/fuse.h"

namespace wearscar::fusion {
namespace {

FuseOptions Quiet() { return sim::WithoutLugre(); }

double TruthOver(const sim::SimulatedTest& t, int first, int last) {
  double sum = 0;
  for (int c = first; c <= last; ++c) sum += t.truth.mu_per_cycle[c];
  return sum / (last - first + 1);
}

// Recorded from cycle 300 of the test on: the groove there from the first
// cycle recorded, the running-in over. Explained and settled with and
// without the scan, the right spring questioned on none, mu-hat near the
// truth.
TEST(TrackHistories, ARecordThatStartsLateKeepsTheRightSpring) {
  for (const char* name : {"B-RT-R", "S-RT-T", "S-RL-R"}) {
    for (double noise : {1.0, 2.0}) {
      const sim::SimulatedTest t = sim::HistoryCase(name, noise, 300);
      for (bool scan : {false, true}) {
        const TestResult r = scan
                                 ? AnalyzeTest(t.record, t.scan, Quiet())
                                 : AnalyzeTest(t.record, std::nullopt, Quiet());
        const std::string what = std::string(name) + " noise " +
                                 std::to_string(noise) + (scan ? " scan" : "");
        EXPECT_TRUE(r.verdict.explained) << what << ": " << r.verdict.Summary();
        EXPECT_EQ(r.verdict.screen, "") << what;
        const SpringCheck& c = r.mismatch.Spring();
        EXPECT_FALSE(c.contradicted || c.undecided)
            << what << ": " << c.Describe("assumed");
        EXPECT_FALSE(c.elastic) << what;
        const MismatchReport& m = r.mismatch;
        const Statistic& mu = m.JudgesForceSlope() ? m.mu_force : m.mu_scan;
        EXPECT_NEAR(mu.mean, TruthOver(t, m.first_cycle, m.last_cycle), 0.001)
            << what;
      }
    }
  }
}

// A test of 120 cycles cut after cycle 30: its second part, analysed
// alone, is explained, and its mu-hat over its cycles lies within the 95%
// interval the whole test's cycles give over the same ones.
TEST(TrackHistories, TheSecondPartOfACutTestAgreesWithTheWhole) {
  samples::SimulationOptions o = samples::PaperCase("B-RT-R", false);
  o.cycles = 120;
  const sim::SimulatedTest whole = sim::Simulate(o);
  o.cycles = 90;
  o.record_from_cycle = 30;
  const sim::SimulatedTest part = sim::Simulate(o);
  ASSERT_EQ(part.truth.mu_per_cycle[0], whole.truth.mu_per_cycle[30]);
  const TestResult w = AnalyzeTest(whole.record, std::nullopt, Quiet());
  const TestResult p = AnalyzeTest(part.record, std::nullopt, Quiet());
  EXPECT_TRUE(p.verdict.explained) << p.verdict.Summary();
  EXPECT_FALSE(p.mismatch.Spring().contradicted ||
               p.mismatch.Spring().undecided);
  // The whole's per-cycle mu-hat over the part's compared cycles.
  const int first = p.window.first + 30, last = p.window.last + 30;
  std::vector<double> values, errors;
  for (const MuFit& f : w.ForceFits().cycles) {
    values.push_back(f.mu_hat);
    errors.push_back(f.standard_error);
  }
  const Statistic same = SummariseWithErrors(
      values, errors, first, last, w.ForceFits().correlated_cycles);
  ASSERT_TRUE(std::isfinite(same.low)) << same.mean;
  EXPECT_GE(p.mismatch.mu_force.mean, same.low);
  EXPECT_LE(p.mismatch.mu_force.mean, same.high);
}

}  // namespace
}  // namespace wearscar::fusion
