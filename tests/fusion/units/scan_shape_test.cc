// The scan's shape per cycle (an analysis unit, scan_shape_history.h) on
// the project's simulator: a groove grown from the first contact shows
// little of the scanned shape in the first cycles, a record that starts
// late (a pre-worn or resumed specimen) nearly all of it; the unit
// abstains, naming its premise, on a dead-weight rig and on another
// specimen's scan. The independent simulator's histories are checked by
// tests/worlds/vtrib_study.py ("scan shape" lines).

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "common/histories.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/products.h"
#include "wearscar/fusion/scan_shape_history.h"

namespace wearscar::fusion {
namespace {

using sim::WithoutLugre;

// The factor over the first cycles tells the two histories apart at noise
// 1 and 2 on both woods; over the compared cycles it is about 1 (the scan
// scaled as P/S sees it there), and the table and result.json carry it.
TEST(ScanShapeHistory, TellsAGrownGrooveFromOneThereAtTheStart) {
  for (const char* name : {"B-RT-R", "S-TL-L"}) {
    for (double noise : {1.0, 2.0}) {
      const std::string what =
          std::string(name) + " noise " + std::to_string(noise);
      const sim::SimulatedTest grown = sim::HistoryCase(name, noise, 0);
      const TestResult g =
          AnalyzeTest(grown.record, grown.scan, WithoutLugre());
      const ScanShapeHistory* gh = g.units.Find<ScanShapeHistory>();
      ASSERT_NE(gh, nullptr) << what;
      ASSERT_EQ(gh->abstained, "") << what;
      ASSERT_EQ(gh->factor.size(), g.force.cycles.cycles.size()) << what;
      EXPECT_LT(gh->first_factor, 0.5) << what;
      EXPECT_GT(gh->half_cycle, 0) << what;
      EXPECT_NEAR(gh->compared_factor, 1.0, 0.1) << what;
      EXPECT_NE(g.assumptions.back().find("the worn track grew during the "
                                          "record"),
                std::string::npos)
          << what << ": " << g.assumptions.back();

      const sim::SimulatedTest late = sim::HistoryCase(name, noise, 300);
      const TestResult l = AnalyzeTest(late.record, late.scan, WithoutLugre());
      const ScanShapeHistory& lh = l.units.Get<ScanShapeHistory>();
      ASSERT_EQ(lh.abstained, "") << what;
      EXPECT_GT(lh.first_factor, 0.8) << what;
      EXPECT_EQ(lh.half_cycle, 0) << what;
      EXPECT_NEAR(lh.compared_factor, 1.0, 0.1) << what;
      EXPECT_NE(l.assumptions.back().find(
                    "the worn track was there from the first recorded cycle"),
                std::string::npos)
          << what << ": " << l.assumptions.back();

      const TestProducts p =
          MakeTestProducts(name, late.record, l, l.options, {{}, false});
      const Table* t = p.Find("scan_shape_history.csv");
      ASSERT_NE(t, nullptr) << what;
      ASSERT_EQ(t->rows.size(), lh.factor.size());
      EXPECT_EQ(t->rows[0][0], 1.0);  // cycles from 1
      EXPECT_EQ(t->rows[0][1], lh.factor[0]);
      EXPECT_EQ(p.result["scan_shape_history"]["half_from_cycle"], 1);
      EXPECT_EQ(p.result["scan_shape_history"]["first_cycles_factor"],
                lh.first_factor);
    }
  }
}

// Where a premise fails the unit abstains and says which; no table.
TEST(ScanShapeHistory, AbstainsNamingThePremiseThatFailed) {
  samples::SimulationOptions o = samples::PaperCase("B-RT-R", false);
  o.cycles = 40;
  o.rig = samples::Rig::kDeadWeight;
  const sim::SimulatedTest dead = sim::Simulate(o);
  const TestResult d = AnalyzeTest(dead.record, dead.scan, WithoutLugre());
  const ScanShapeHistory& dh = d.units.Get<ScanShapeHistory>();
  EXPECT_NE(dh.abstained.find("P/S follows the track's height"),
            std::string::npos)
      << dh.abstained;
  EXPECT_TRUE(dh.factor.empty());
  const TestProducts p =
      MakeTestProducts("dead", dead.record, d, d.options, {{}, false});
  EXPECT_EQ(p.Find("scan_shape_history.csv"), nullptr);
  EXPECT_NE(p.result["scan_shape_history"]["abstained"], nullptr);
  bool listed = false;
  for (const auto& premise : p.result["premises"]) {
    if (premise["rule"] == "scan shape history" && premise["state"] == "failed")
      listed = true;
  }
  EXPECT_TRUE(listed);

  // Another specimen's scan (another case's track): doubted, so abstained.
  const sim::SimulatedTest own = sim::HistoryCase("B-RT-R", 1.0, 0);
  const sim::SimulatedTest other = sim::HistoryCase("S-RT-T", 1.0, 0);
  const TestResult f = AnalyzeTest(own.record, other.scan, WithoutLugre());
  ASSERT_NE(f.verdict.scan_doubt, "");
  EXPECT_NE(f.units.Get<ScanShapeHistory>().abstained.find(
                "the scan is this test's track"),
            std::string::npos)
      << f.units.Get<ScanShapeHistory>().abstained;
}

// Each unit records the choices the data may override as given and used
// (result.json's "units"): the scan shape's first cycles on a record
// shorter than its pool, the friction map's slope span below two of the
// fit's bins, LuGre's detail cycle.
TEST(Units, RecordTheirChoicesAsGivenAndUsed) {
  const sim::SimulatedTest t = sim::HistoryCase("B-RT-R", 1.0, 300, 10);
  FuseOptions o = sim::WithoutLugre();
  o.fit_lugre = true;
  o.detail_cycle = 4;
  o.friction_map.slope_span_mm = 0.005;
  const TestResult r = AnalyzeTest(t.record, t.scan, o);
  const TestProducts p =
      MakeTestProducts("B-RT-R", t.record, r, r.options, {{}, false});
  std::map<std::string, nlohmann::json> units;
  for (const nlohmann::json& u : p.result["units"]) units[u["kind"]] = u;
  const int n = static_cast<int>(r.force.cycles.cycles.size());
  ASSERT_LT(n, 15);
  const nlohmann::json& shape = units.at("scan_shape_history");
  EXPECT_EQ(shape["given"]["first_cycles"], 15);
  EXPECT_EQ(shape["used"]["first_cycles"], n);
  EXPECT_EQ(shape["why"]["first_cycles"],
            "the record has " + std::to_string(n) + " cycles");
  const nlohmann::json& map = units.at("friction_map");
  EXPECT_EQ(map["given"]["slope_span_mm"], 0.005);
  EXPECT_DOUBLE_EQ(map["used"]["slope_span_mm"].get<double>(), 0.02);
  EXPECT_EQ(p.result["friction_map"]["slope_span_mm"],
            map["used"]["slope_span_mm"]);
  EXPECT_EQ(map["given"]["slope_polynomial_order"], 3);  // the map's own
  EXPECT_EQ(map["used"]["slope_polynomial_order"], 3);
  EXPECT_FALSE(map["why"].contains("slope_polynomial_order"));
  const nlohmann::json& lugre = units.at("lugre");
  EXPECT_EQ(lugre["given"]["detail_cycle"], 5);
  EXPECT_EQ(lugre["used"]["detail_cycle"], 5);
  EXPECT_FALSE(lugre.contains("why"));
  EXPECT_FALSE(units.at("wear").contains("given"));
}

}  // namespace
}  // namespace wearscar::fusion
