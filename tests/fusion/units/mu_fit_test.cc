// mu-hat per slope source as analysis units (mu_fit_unit.cc): k from P/S
// ("mu_fit_spring"), from the depth channel ("mu_fit_depth", where the
// profile's decision takes it) and from the scan ("mu_fit_scan"). The
// comparison and the products read them (TestResult::ForceFits and
// ScanSlopeFits); the fits are those the force side alone gives.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "common/histories.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"

namespace wearscar::fusion {
namespace {

double MeanOver(const std::vector<MuFit>& fits, int first, int last) {
  double sum = 0;
  int n = 0;
  for (int c = first; c <= last; ++c) {
    if (fits[c].converged) sum += fits[c].mu_hat, ++n;
  }
  return sum / n;
}

std::set<std::string> UnitsListed(const TestProducts& p) {
  std::set<std::string> kinds;
  for (const auto& u : p.result["units"]) kinds.insert(u["kind"]);
  return kinds;
}

TEST(MuFitUnits, EachSlopeSourceIsAUnitTheComparisonAndProductsRead) {
  const sim::SimulatedTest t = sim::HistoryCase("B-RT-R", 1.0, 0, 60);
  const TestResult r = AnalyzeTest(t.record, t.scan, sim::WithoutLugre());
  const SpringFits* spring = r.units.Find<SpringFits>();
  const ScanFits* scan = r.units.Find<ScanFits>();
  ASSERT_NE(spring, nullptr);
  ASSERT_NE(scan, nullptr);
  EXPECT_EQ(r.units.Find<DepthFits>(), nullptr);  // no depth channel
  EXPECT_EQ(&r.ForceFits(), static_cast<const SlopeFits*>(spring));
  EXPECT_EQ(&r.ScanSlopeFits(), scan);
  const int n = static_cast<int>(r.force.cycles.cycles.size());
  ASSERT_EQ(static_cast<int>(spring->cycles.size()), n);
  ASSERT_EQ(static_cast<int>(scan->cycles.size()), n);
  // The fits the force side alone gives (AnalyzeForce, no units).
  const ForceFitted alone = AnalyzeForce(t.record, r.options.ForceSide());
  for (int c = 0; c < n; ++c)
    EXPECT_EQ(spring->cycles[c].mu_hat, alone.fits.cycles[c].mu_hat) << c;
  // The comparison's mu-hat is theirs over the compared cycles.
  const MismatchReport& m = r.mismatch;
  EXPECT_NEAR(m.mu_force.mean,
              MeanOver(spring->cycles, m.first_cycle, m.last_cycle),
              1e-12);
  EXPECT_NEAR(m.mu_scan.mean,
              MeanOver(scan->cycles, m.first_cycle, m.last_cycle),
              1e-12);
  // cycles.csv's columns and result.json's list.
  const TestProducts p =
      MakeTestProducts("B-RT-R", t.record, r, r.options, {{}, false});
  const Table* cycles = p.Find("cycles.csv");
  ASSERT_NE(cycles, nullptr);
  const int f = cycles->ColumnIndex("mu_hat_force");
  const int s = cycles->ColumnIndex("mu_hat_scan");
  for (int c = 0; c < n; ++c) {
    if (spring->cycles[c].converged) {
      EXPECT_EQ(cycles->rows[c][f], spring->cycles[c].mu_hat) << c;
    }
    if (scan->cycles[c].converged) {
      EXPECT_EQ(cycles->rows[c][s], scan->cycles[c].mu_hat) << c;
    }
  }
  const std::set<std::string> kinds = UnitsListed(p);
  EXPECT_TRUE(kinds.count("mu_fit_spring"));
  EXPECT_TRUE(kinds.count("mu_fit_scan"));
  EXPECT_FALSE(kinds.count("mu_fit_depth"));
}

// A dead weight with a depth channel: the decision takes the depth, whose
// unit fits mu-hat with it; P/S's fits, which the decision read, are kept
// beside and not quoted.
TEST(MuFitUnits, TheDepthChannelTheDecisionTakesHasItsOwnUnit) {
  samples::SimulationOptions o = samples::PaperCase("B-RT-R", false);
  o.cycles = 60;
  o.rig = samples::Rig::kDeadWeight;
  o.depth_channel = true;
  const sim::SimulatedTest t = sim::Simulate(o);
  const TestResult r = AnalyzeTest(t.record, std::nullopt, sim::WithoutLugre());
  ASSERT_TRUE(r.profile.FromDepth()) << r.profile.reason;
  const DepthFits* depth = r.units.Find<DepthFits>();
  ASSERT_NE(depth, nullptr);
  ASSERT_NE(r.units.Find<SpringFits>(), nullptr);
  EXPECT_EQ(&r.ForceFits(), static_cast<const SlopeFits*>(depth));
  EXPECT_EQ(r.units.Find<ScanFits>(), nullptr);  // no scan
  double truth = 0;
  for (int c = r.mismatch.first_cycle; c <= r.mismatch.last_cycle; ++c)
    truth += t.truth.mu_per_cycle[c];
  truth /= r.mismatch.last_cycle - r.mismatch.first_cycle + 1;
  EXPECT_NEAR(r.mismatch.mu_force.mean, truth, 0.002);
  EXPECT_NEAR(
      r.mismatch.mu_force.mean,
      MeanOver(depth->cycles, r.mismatch.first_cycle, r.mismatch.last_cycle),
      1e-12);
  const TestProducts p =
      MakeTestProducts("B-RT-R", t.record, r, r.options, {{}, false});
  EXPECT_TRUE(UnitsListed(p).count("mu_fit_depth"));
}

}  // namespace
}  // namespace wearscar::fusion
