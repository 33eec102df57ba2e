#include "wearscar/samples/virtual_tribometer.h"

#include <gtest/gtest.h>

#include <set>

#include "wearscar/force/cycles.h"

namespace wearscar::samples {
namespace {

SimulationOptions Small(const std::string& name) {
  SimulationOptions o = PaperCase(name);
  o.cycles = 20;
  o.scan_cols = 256;
  o.scan_rows = 192;
  o.scan_pitch_mm = 0.03;
  return o;
}

TEST(VirtualTribometer, TwelvePaperCasesWithDistinctSeeds) {
  const auto cases = PaperCases();
  ASSERT_EQ(cases.size(), 12u);
  std::set<std::uint64_t> seeds;
  for (const auto& c : cases) {
    seeds.insert(c.seed);
    std::string why;
    EXPECT_TRUE(c.IsValid(&why)) << c.name << ": " << why;
  }
  EXPECT_EQ(seeds.size(), 12u);
  EXPECT_THROW(PaperCase("B-XX-Y"), std::invalid_argument);
}

TEST(VirtualTribometer, DeterministicForASeed) {
  const SimulatedTest a = Simulate(Small("S-RT-R"));
  const SimulatedTest b = Simulate(Small("S-RT-R"));
  EXPECT_EQ(a.record.tangential_n, b.record.tangential_n);
  EXPECT_TRUE((a.scan.valid == b.scan.valid).all());
  SimulationOptions o = Small("S-RT-R");
  o.seed += 1;
  EXPECT_NE(Simulate(o).record.tangential_n, a.record.tangential_n);
}

TEST(VirtualTribometer, PaperTestConditions) {
  const SimulatedTest t = Simulate(Small("B-RT-R"));
  const auto& r = t.record;
  EXPECT_EQ(r.size(), 21 * 2000);  // cycles + 1 periods at 2 kHz
  EXPECT_NEAR(r.x_mm.maxCoeff(), 2.85, 0.002);
  EXPECT_NEAR(r.x_mm.minCoeff(), -2.85, 0.002);
  // The slow control holds the mean normal force at 30 N: within 0.15 N
  // while the track still deepens fast (cycle 20), 0.02 N later.
  EXPECT_NEAR(r.normal_n.tail(4000).mean(), 30.0, 0.15);
  // Resolution of the channels (4.5 mN, 15 mN).
  const double q = r.tangential_n[1234] / 0.0045;
  EXPECT_NEAR(q, std::round(q), 1e-6);
  const force::CycleSet set = force::SegmentCycles(r.x_mm);
  EXPECT_EQ(set.cycles.size(), 20u);
  EXPECT_EQ(t.truth.mu_per_cycle.size(), 20);
}

TEST(VirtualTribometer, SprucePressesHarderThanBeechAcrossRings) {
  // The paper: P varies < 1 N on beech, < 2 N on spruce; spruce RT-R has
  // the larger fluctuation of Q.
  auto ranges = [](const std::string& name) {
    SimulationOptions o = Small(name);
    o.cycles = 100;
    const SimulatedTest t = Simulate(o);
    const Eigen::VectorXd p = t.record.normal_n.tail(4000);
    return p.maxCoeff() - p.minCoeff();
  };
  const double beech = ranges("B-RT-R"), spruce = ranges("S-RT-R");
  EXPECT_LT(beech, 1.0);
  EXPECT_LT(spruce, 2.0);
  EXPECT_GT(spruce, beech);
}

TEST(VirtualTribometer, OnlySRlRIsUnexplainedByConstruction) {
  for (const auto& o : PaperCases(true)) {
    SimulationOptions s = o;
    s.cycles = 20;
    s.scan_cols = s.scan_rows = 32;
    EXPECT_EQ(Simulate(s).truth.explained_by_wear_scar, o.name != "S-RL-R")
        << o.name;
  }
  for (const auto& o : PaperCases(false)) {
    SimulationOptions s = o;
    s.cycles = 20;
    s.scan_cols = s.scan_rows = 32;
    EXPECT_TRUE(Simulate(s).truth.explained_by_wear_scar) << o.name;
  }
}

TEST(VirtualTribometer, ScanShowsTrackAtKnownDepthOnKnownPlane) {
  const SimulationOptions o = Small("B-RT-T");
  const SimulatedTest t = Simulate(o);
  // Corner pixel: unworn, on the plane (noise 0.8 um).
  const auto& h = t.scan.height_mm;
  const double expected = o.plane_z0_mm + o.plane_dzdx * 5 * o.scan_pitch_mm +
                          o.plane_dzdy * 5 * o.scan_pitch_mm;
  if (t.scan.valid(5, 5)) {
    EXPECT_NEAR(h(5, 5), expected, 0.004);
  }
  // Centre of the track: depth below the plane near the truth.
  const int col =
      static_cast<int>(std::round(t.truth.scan_center_x_mm / o.scan_pitch_mm));
  const int row =
      static_cast<int>(std::round(t.truth.scan_center_y_mm / o.scan_pitch_mm));
  const double plane = o.plane_z0_mm + o.plane_dzdx * col * o.scan_pitch_mm +
                       o.plane_dzdy * row * o.scan_pitch_mm;
  const double truth_depth =
      t.truth.worn_depth_mm[t.truth.worn_depth_mm.size() / 2];
  EXPECT_NEAR(plane - h(row, col), truth_depth, 0.01);
}

}  // namespace
}  // namespace wearscar::samples
