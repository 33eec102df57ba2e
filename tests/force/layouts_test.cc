// The registry of tribometer layouts: every entry's example is read as
// that layout, names stay unique, and the generic layout takes the rest.

#include "wearscar/force/layouts.h"

#include <gtest/gtest.h>

#include <set>

#include "wearscar/force/read_force.h"

namespace wearscar::force {
namespace {

TEST(ForceLayouts, EachExampleReadsAsItsOwnLayout) {
  std::set<std::string> names;
  for (const ForceLayout& l : ForceLayouts()) {
    SCOPED_TRACE(l.name);
    EXPECT_TRUE(names.insert(l.name).second) << "a name used twice";
    EXPECT_FALSE(l.instruments.empty());
    EXPECT_FALSE(l.extensions.empty());
    const ForceRecord r = ReadForceText(l.example, l.name + " example");
    EXPECT_EQ(r.metadata.layout, l.name);
    EXPECT_GE(r.size(), 4);
    // Every example holds a stroke in mm and a load in N once converted.
    EXPECT_GT(r.x_mm.maxCoeff() - r.x_mm.minCoeff(), 0.2);
    EXPECT_NEAR(r.normal_n.mean(), 30.0, 0.5);
    EXPECT_EQ(FindForceLayout(l.name), &l);
  }
  EXPECT_EQ(FindForceLayout("no such layout"), nullptr);
  EXPECT_EQ(ForceLayouts().back().name, "delimited");
}

// The Rtec example restarts its clock with the recipe step: joined into
// one increasing clock, as its registry entry says.
TEST(ForceLayouts, TheRtecClockRestartsWithItsStepAndIsJoined) {
  const ForceLayout* rtec = FindForceLayout("rtec");
  ASSERT_NE(rtec, nullptr);
  EXPECT_EQ(rtec->clock, ClockRule::kRestartsWithStep);
  const ForceRecord r = ReadForceText(rtec->example, "rtec");
  EXPECT_EQ(r.metadata.clock_restarts_joined, 1);
  for (Eigen::Index i = 1; i < r.size(); ++i)
    EXPECT_GT(r.time_s[i], r.time_s[i - 1]);
}

TEST(ForceLayouts, TheHighestScoreNamesTheLayoutTheGenericOneTakesTheRest) {
  LayoutFacts plain;
  plain.names = {"time", "x", "q", "p"};
  EXPECT_EQ(DetectForceLayout(plain).name, "delimited");
  LayoutFacts rtec = plain;
  rtec.names = {"recipestep", "timestamp", "daq.fx", "daq.fz"};
  EXPECT_EQ(DetectForceLayout(rtec).name, "rtec");
  LayoutFacts bruker = plain;
  bruker.units_row = true;
  bruker.units = {"g", "g", "mm"};
  EXPECT_EQ(DetectForceLayout(bruker).name, "bruker");
  bruker.units = {"deg", "kg", "mm"};  // a units row, but no gram-force
  EXPECT_EQ(DetectForceLayout(bruker).name, "delimited");
}

TEST(ForceLayouts, ExtensionsOverEveryLayoutOnceEach) {
  const std::vector<std::string> e = ForceExtensions();
  EXPECT_EQ(e.front(), ".csv");
  EXPECT_EQ(std::set<std::string>(e.begin(), e.end()).size(), e.size());
  for (const char* x : {".csv", ".txt", ".tsv", ".dat"})
    EXPECT_NE(std::find(e.begin(), e.end(), x), e.end()) << x;
}

// A column without a unit in a layout that has one for it takes the
// layout's (and says so); the generic layout infers it from plausibility.
TEST(ForceLayouts, AColumnWithoutAUnitTakesItsLayoutsUnit) {
  const std::string rtec =
      "RecipeStep,Timestamp,DAQ.Fx (N),DAQ.Fz (N),Piezo X,\n"
      "1,0.000,0.0,-30.0,0.00,\n"
      "1,0.005,3.6,-30.1,0.09,\n"
      "1,0.010,3.6,-30.2,0.18,\n"
      "1,0.015,3.6,-30.3,0.27,\n";
  const ForceRecord r = ReadForceText(rtec, "rtec-no-unit.csv");
  EXPECT_EQ(r.metadata.channel_units[1], "mm");
  bool said = false;
  for (const std::string& w : r.metadata.warnings)
    said |= w.find(
                "'Piezo X' states no unit: taken as mm (the rtec "
                "layout's unit") != std::string::npos;
  EXPECT_TRUE(said) << ::testing::PrintToString(r.metadata.warnings);
}

}  // namespace
}  // namespace wearscar::force
