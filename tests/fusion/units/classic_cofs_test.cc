// The classic COFs as an analysis unit (classic_cofs_unit.cc): the core
// detects the running-in on the unit's mean method and the comparison
// takes the classic methods from it; its columns stand in cycles.csv where
// they stood before it was a unit (UnitSpec::columns), empty where it did
// not run, and its figures after running-in in result.json's
// after_running_in (UnitSpec::json_section).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/histories.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion {
namespace {

std::vector<double> MeanMethod(const ClassicCofs& cofs) {
  std::vector<double> v;
  for (const auto& c : cofs.cycles) v.push_back(c.mu_mean);
  return v;
}

int Column(const Table& t, const char* name) {
  const int i = t.ColumnIndex(name);
  EXPECT_GE(i, 0) << name;
  return i;
}

TEST(ClassicCofs, TheCoreReadsTheUnitAndTheProductsPlaceItsColumns) {
  const sim::SimulatedTest t = sim::HistoryCase("B-RT-R", 1.0, 0, 60);
  const TestResult r = AnalyzeTest(t.record, t.scan, sim::WithoutLugre());
  const ClassicCofs* cofs = r.units.Find<ClassicCofs>();
  ASSERT_NE(cofs, nullptr);
  const int n = static_cast<int>(r.force.cycles.cycles.size());
  ASSERT_EQ(static_cast<int>(cofs->cycles.size()), n);
  // The running-in is the one its mean method shows.
  const RunningIn ri = DetectRunningIn(MeanMethod(*cofs),
                                       r.options.analysis.running_in_tolerance);
  EXPECT_EQ(r.force.running_in.cycles, ri.cycles);
  EXPECT_GT(r.force.running_in.cycles, 0);  // a groove grown from nothing
  // The comparison's classic figures are its own over the compared cycles.
  const Statistic energy = [&] {
    std::vector<double> e;
    for (int c = r.mismatch.first_cycle; c <= r.mismatch.last_cycle; ++c)
      e.push_back(cofs->cycles[c].mu_energy_g);
    return SummariseSeries(e, 0, static_cast<int>(e.size()) - 1);
  }();
  EXPECT_DOUBLE_EQ(r.mismatch.mu_energy.mean, energy.mean);

  const TestProducts p =
      MakeTestProducts("B-RT-R", t.record, r, r.options, {{}, false});
  const Table* cycles = p.Find("cycles.csv");
  ASSERT_NE(cycles, nullptr);
  EXPECT_EQ(cycles->columns, TableColumns("cycles.csv"));
  // Where they stood: after the samples, the track's waviness after the
  // slip fallbacks.
  EXPECT_EQ(Column(*cycles, "mu_mean"), Column(*cycles, "samples") + 1);
  EXPECT_EQ(Column(*cycles, "QP_correlation"), Column(*cycles, "samples") + 13);
  EXPECT_EQ(Column(*cycles, "running_in"),
            Column(*cycles, "QP_correlation") + 1);
  EXPECT_EQ(Column(*cycles, "waviness_sd_mm"),
            Column(*cycles, "slip_fallback") + 1);
  const int mm = Column(*cycles, "mu_mean"), pr = Column(*cycles, "P_range_N");
  for (int c = 0; c < n; ++c) {
    EXPECT_EQ(cycles->rows[c][mm], cofs->cycles[c].mu_mean) << c;
    EXPECT_EQ(cycles->rows[c][pr], cofs->cycles[c].p_range_n) << c;
  }
  // result.json: after running-in, and the unit and its premise listed.
  const auto& after = p.result["after_running_in"];
  const Statistic mean =
      SummariseSeries(MeanMethod(*cofs), r.force.running_in.cycles, n - 1);
  EXPECT_DOUBLE_EQ(after["mu_mean"]["mean"].get<double>(), mean.mean);
  EXPECT_TRUE(after.contains("mu_energy"));
  EXPECT_FALSE(p.result.contains("classic_cofs"));
  bool listed = false, premise = false;
  for (const auto& u : p.result["units"]) listed |= u["kind"] == "classic_cofs";
  for (const auto& q : p.result["premises"]) {
    if (q["rule"] == "classic COFs")
      premise = q["state"] == (r.force.slip_fallbacks == 0 ? "held" : "failed");
  }
  EXPECT_TRUE(listed);
  EXPECT_TRUE(premise);

  // A unit that did not run leaves its columns empty; the rest stand.
  TestResult without = r;
  without.units = UnitResults();
  without.units.Put<TrackHistory>("track_history",
                                  r.units.Share<TrackHistory>());
  without.units.Put<SpringFits>("mu_fit_spring", r.units.Share<SpringFits>());
  const TestProducts q =
      MakeTestProducts("B-RT-R", t.record, without, r.options, {{}, false});
  const Table* bare = q.Find("cycles.csv");
  ASSERT_NE(bare, nullptr);
  EXPECT_EQ(bare->columns, cycles->columns);
  const int w = Column(*bare, "waviness_sd_mm");
  EXPECT_TRUE(std::isnan(bare->rows[5][mm]));
  EXPECT_EQ(bare->rows[5][w], cycles->rows[5][w]);
  EXPECT_EQ(bare->rows[5][0], 6.0);
}

}  // namespace
}  // namespace wearscar::fusion
