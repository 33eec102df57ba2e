// The friction map mu(x, cycle): flat along x once the slope is corrected
// where the wear-scar interaction explains the loops, and the along-track
// pattern of mu when friction itself varies (simulator truth).
#include "wearscar/fusion/friction_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "common/simulated.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/track_history.h"

namespace wearscar::fusion {
namespace {

struct Mapped {
  sim::SimulatedTest test;
  TestResult result;
};

// A paper case, 200 cycles at 2 kHz, no elastic part, with the scan.
Mapped Simulate(const std::string& name,
                double noise,
                double mu_variation = 0) {
  samples::SimulationOptions o = samples::PaperCase(name);
  o.cycles = 200;
  o.elastic_mm = 0;
  o.noise_scale = noise;
  o.effects.mu_variation = mu_variation;
  o.scan_cols = 512;
  o.scan_rows = 384;
  o.scan_pitch_mm = 0.0148;
  Mapped m{sim::Simulate(o), {}};
  m.result = AnalyzeTest(m.test.record, m.test.scan, FuseOptions{});
  return m;
}

// Too few steady cycles for the noise floor (two blocks: their lag-1
// covariance cancels their variance) give none rather than a floor of 0.
TEST(FrictionMap, NoNoiseFloorFromTooFewSteadyCycles) {
  samples::SimulationOptions o = samples::PaperCase("B-RT-R");
  o.cycles = 20;
  o.scan_cols = 256;
  o.scan_rows = 192;
  o.scan_pitch_mm = 0.03;
  const sim::SimulatedTest t = sim::Simulate(o);
  FuseOptions options;
  options.analysis.running_in_cycles = 10;
  const TestResult r = AnalyzeTest(t.record, t.scan, options);
  EXPECT_TRUE(std::isfinite(r.units.Get<FrictionMap>().spatial_sd_corrected));
  EXPECT_TRUE(std::isnan(r.units.Get<FrictionMap>().spatial_sd_noise));
  EXPECT_TRUE(std::isnan(r.units.Get<FrictionMap>().spatial_sd_excess));
}

class CleanCase
    : public ::testing::TestWithParam<std::tuple<const char*, double>> {};

// Clean crossing-ring cases: the corrected map is flat within its noise
// floor while the raw one follows the track, at least 5x more variable
// (measured 100-400x). "Within the floor": the ratio of the corrected
// map's along-track sd to its floor is what a plate without any track gives
// (measured, noise 1: on a flat plate, 120 seeds, median 1.05, 95th
// percentile 1.66, largest 2.5; on these four tracks at noise 1 and 2, 21
// seeds each, median 1.00, 95th percentile 1.45, largest 1.72), so it is
// held under 2. With the fit's local quadratic for k the ratio read 1.5-6
// (a bias of span^2 times P's third derivative at the steepest flanks).
TEST_P(CleanCase, CorrectedMapIsFlatRawMapFollowsTheTrack) {
  const auto [name, noise] = GetParam();
  const Mapped m = Simulate(name, noise);
  const FrictionMap& f = m.result.units.Get<FrictionMap>();
  ASSERT_GT(f.x_mm.size(), 8u);
  EXPECT_LE(f.spatial_sd_corrected, 2.0 * f.spatial_sd_noise)
      << name << ": corrected " << f.spatial_sd_corrected << ", floor "
      << f.spatial_sd_noise;
  EXPECT_GE(f.spatial_sd_raw, 5.0 * f.spatial_sd_corrected)
      << name << ": raw " << f.spatial_sd_raw << ", corrected "
      << f.spatial_sd_corrected;
}

// The same map with the fit's quadratic for k is not flat within its
// floor on the steepest track (S-RT-R): the cubic is what makes it so.
TEST(FrictionMap, TheFitsQuadraticLeavesTheFlanksInTheMap) {
  samples::SimulationOptions o = samples::PaperCase("S-RT-R");
  o.cycles = 200;
  o.elastic_mm = 0;
  o.noise_scale = 0;
  o.scan_cols = 64;
  o.scan_rows = 48;
  o.scan_pitch_mm = 0.12;
  const sim::SimulatedTest t = sim::Simulate(o);
  FuseOptions quadratic;
  quadratic.fit_lugre = false;
  quadratic.friction_map.slope_polynomial_order = 2;
  FuseOptions cubic = quadratic;
  cubic.friction_map.slope_polynomial_order = 3;
  const FrictionMap q =
      AnalyzeTest(t.record, std::nullopt, quadratic).units.Get<FrictionMap>();
  const FrictionMap c =
      AnalyzeTest(t.record, std::nullopt, cubic).units.Get<FrictionMap>();
  EXPECT_GT(q.spatial_sd_corrected, 3 * q.spatial_sd_noise);
  EXPECT_LT(c.spatial_sd_corrected, 0.5 * q.spatial_sd_corrected);
}

INSTANTIATE_TEST_SUITE_P(
    CrossingRings,
    CleanCase,
    ::testing::Combine(
        ::testing::Values("B-RT-R", "S-RT-R", "B-RL-R", "S-RL-R"),
        ::testing::Values(1.0, 2.0)),
    [](const auto& param_info) {
      std::string n = std::get<0>(param_info.param);
      for (char& c : n)
        if (c == '-') c = '_';
      return n + "_noise" +
             std::to_string(static_cast<int>(std::get<1>(param_info.param)));
    });

// Friction varying along the track (mu_variation = 0.2 hidden): the map's
// steady pattern follows the truth, mu (factor(x) - 1) averaged over the
// same bins: correlation >= 0.8, amplitude within 20%.
class VaryingCase : public ::testing::TestWithParam<const char*> {};

TEST_P(VaryingCase, MapRecoversTheAlongTrackPatternOfMu) {
  const Mapped m = Simulate(GetParam(), 1.0, 0.2);
  const FrictionMap& f = m.result.units.Get<FrictionMap>();
  const auto& truth = m.test.truth;
  double mu_steady = 0;
  for (int c = f.first_steady_cycle; c < f.cycles; ++c)
    mu_steady += truth.mu_per_cycle[c];
  mu_steady /= f.cycles - f.first_steady_cycle;
  const size_t bins = f.x_mm.size();
  const double width = f.x_mm[1] - f.x_mm[0];
  std::vector<double> expected(bins, NAN);
  for (size_t b = 0; b < bins; ++b) {
    double sum = 0;
    int n = 0;
    for (Eigen::Index i = 0; i < truth.profile_x_mm.size(); ++i) {
      if (std::abs(truth.profile_x_mm[i] - f.x_mm[b]) <= 0.5 * width)
        sum += truth.mu_factor[i], ++n;
    }
    if (n > 0) expected[b] = mu_steady * (sum / n - 1);
  }
  // Both directions against the same truth, each about its own mean.
  double sxy = 0, sxx = 0, syy = 0;
  for (int d = 0; d < 2; ++d) {
    double mx = 0, my = 0;
    int n = 0;
    for (size_t b = 0; b < bins; ++b) {
      const double x = expected[b], y = f.steady_corrected[d * bins + b];
      if (std::isfinite(x) && std::isfinite(y)) mx += x, my += y, ++n;
    }
    ASSERT_GT(n, 6);
    mx /= n;
    my /= n;
    for (size_t b = 0; b < bins; ++b) {
      const double x = expected[b], y = f.steady_corrected[d * bins + b];
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      sxy += (x - mx) * (y - my);
      sxx += (x - mx) * (x - mx);
      syy += (y - my) * (y - my);
    }
  }
  const double correlation = sxy / std::sqrt(sxx * syy);
  const double amplitude = std::sqrt(syy / sxx);
  RecordProperty("correlation", std::to_string(correlation));
  RecordProperty("amplitude_ratio", std::to_string(amplitude));
  EXPECT_GE(correlation, 0.8) << GetParam();
  EXPECT_NEAR(amplitude, 1.0, 0.2) << GetParam();
  // And the map is no longer flat: far above its noise floor.
  EXPECT_GT(f.spatial_sd_corrected, 10 * f.spatial_sd_noise);
}

INSTANTIATE_TEST_SUITE_P(CrossingRings,
                         VaryingCase,
                         ::testing::Values("B-RT-R", "S-RT-R"),
                         [](const auto& param_info) {
                           std::string n = param_info.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

// The loops the report's viewer draws: each cycle's binned Q against the
// wear-scar model on the bins' P and k. With the simulator's true mu of
// the cycle the model meets the measured loop within 8% of its rms
// (B-RT-R at noise 1, after running-in: measured 3.9-4.5%, mostly the
// noise of k from P, which is correlated over the 0.1 mm of its derivative
// and so not averaged away in a 0.057 mm bin); with mu 0.02 off the
// squared misfit is more than 4x larger (measured 13-18x), and the reverse
// stroke's Q is negative where the forward one is positive.
TEST(FrictionMap, EachCyclesBinnedLoopMeetsTheModelWithItsMu) {
  const Mapped m = Simulate("B-RT-R", 1);
  const FrictionMap& f = m.result.units.Get<FrictionMap>();
  ASSERT_EQ(f.loop_x_mm.size(), 100u);
  ASSERT_EQ(f.loop_q_n.size(), static_cast<size_t>(f.cycles) * 2 * 100);
  const int first = m.result.force.running_in.cycles;
  for (int c = first; c < f.cycles; c += 37) {
    const double mu = m.test.truth.mu_per_cycle[c];
    double off_true = 0, off_wrong = 0, qq = 0;
    int n = 0;
    for (int d = 0; d < 2; ++d) {
      for (size_t b = 0; b < f.loop_x_mm.size(); ++b) {
        const double q = f.loop_q_n[f.LoopIndex(c, d, b)];
        const double model = f.LoopModelQ(c, d, b, mu);
        const double wrong = f.LoopModelQ(c, d, b, mu + 0.02);
        if (!std::isfinite(q) || !std::isfinite(model)) continue;
        EXPECT_EQ(q > 0, d == 0) << "cycle " << c << " bin " << b;
        off_true += (q - model) * (q - model);
        off_wrong += (q - wrong) * (q - wrong);
        qq += q * q;
        ++n;
      }
    }
    ASSERT_GT(n, 150) << "cycle " << c;
    EXPECT_LT(std::sqrt(off_true / qq), 0.08) << "cycle " << c;
    EXPECT_GT(off_wrong, 4 * off_true) << "cycle " << c;
  }
}

// Without loops (--no-figures: loop_bins 0) the map is the same map, with
// no loops for the viewer.
TEST(FrictionMap, WithoutLoopsTheMapIsTheSame) {
  const Mapped m = Simulate("B-RT-R", 1);
  const TestResult& r = m.result;
  FrictionMapOptions o;
  o.loop_bins = 0;
  const FrictionMap none = ComputeFrictionMap(m.test.record,
                                              r.force.cycles,
                                              r.options.analysis.friction,
                                              r.force.running_in.cycles,
                                              o);
  const FrictionMap& with = r.units.Get<FrictionMap>();
  ASSERT_FALSE(with.loop_q_n.empty());
  EXPECT_TRUE(none.loop_x_mm.empty());
  EXPECT_TRUE(none.loop_q_n.empty() && none.loop_p_n.empty() &&
              none.loop_k.empty());
  ASSERT_EQ(none.mu_raw.size(), with.mu_raw.size());
  for (size_t i = 0; i < with.mu_raw.size(); ++i) {
    EXPECT_TRUE(none.mu_raw[i] == with.mu_raw[i] ||
                (std::isnan(none.mu_raw[i]) && std::isnan(with.mu_raw[i])));
    EXPECT_TRUE(
        none.mu_corrected[i] == with.mu_corrected[i] ||
        (std::isnan(none.mu_corrected[i]) && std::isnan(with.mu_corrected[i])));
  }
  EXPECT_EQ(none.spatial_sd_corrected, with.spatial_sd_corrected);
}

TEST(FrictionMap, BadOptionsAreRefused) {
  FrictionMapOptions o;
  o.bin_mm = 0;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("bin_mm"), std::string::npos);
  o = FrictionMapOptions{};
  o.loop_bins = 1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("loop bins"), std::string::npos);
  o.loop_bins = 0;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  FuseOptions fo;
  fo.friction_map.bin_mm = -1;
  EXPECT_FALSE(fo.IsValid(&why));
}

}  // namespace
}  // namespace wearscar::fusion

namespace wearscar::fusion {
namespace {

// The track's history from the spring: the waviness of P/S per cycle
// follows the simulator's truth (the sd of the sphere's path under load at
// that cycle) after running-in. Where the tracks cross the rings (waviness
// 10-50 um) within 5% in every cycle at noise 1 and 2 (measured worst
// 0.5-1.9%). Along the rings the waviness is 1-2 um, about the P sensor's
// resolution over S (0.015 N / 10.19 N/mm), pooled over 15 cycles
// (TrackHistoryOptions::pool_cycles): at the calibrated noise every cycle
// is within 10% (measured worst 1.9-8.5%, S-TL-L the largest); at twice it
// the noise in a bin mean is larger than the waviness itself and single
// cycles stray by up to 17% (S-TL-L; B-RL-L and S-RL-L 10-11%), the mean
// within 6%.
class HistoryCase
    : public ::testing::TestWithParam<std::tuple<const char*, double>> {};

TEST_P(HistoryCase, WavinessFollowsTheTruthAfterRunningIn) {
  const auto [name, noise] = GetParam();
  const Mapped m = Simulate(name, noise);
  const TrackHistory& h = m.result.units.Get<TrackHistory>();
  const auto& truth = m.test.truth.waviness_sd_mm;
  ASSERT_EQ(h.waviness_sd_mm.size(), static_cast<size_t>(truth.size()));
  double worst = 0, mean = 0;
  const int first = m.result.force.running_in.cycles;
  for (int c = first; c < h.cycles; ++c) {
    const double e = std::abs(h.waviness_sd_mm[c] / truth[c] - 1);
    worst = std::max(worst, e);
    mean += e / (h.cycles - first);
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
  RecordProperty("mean_relative_error", std::to_string(mean));
  const bool across_rings = std::string(name).back() == 'R';  // x-RT-R, x-RL-R
  const double limit = across_rings ? 0.05 : noise == 1 ? 0.10 : 0.20;
  EXPECT_LE(worst, limit) << name << ": worst " << worst;
  EXPECT_LE(mean, 0.06) << name << ": mean " << mean;
  // It grows with the wear.
  EXPECT_GT(h.final_waviness_sd_mm, 2 * h.waviness_sd_mm.front());
}

// --scan-slope-history: the scan shows the final track, so without it the
// scan-side mu-hat of S-RT-R carries the track's growth: over seeds
// 7001-7003 (200 cycles, noise 1) it is off by 0.0128 (rms) in the
// running-in and 0.0052 after it (how much depends on how each cycle's
// gross slip covers the track: the preset's own seed gives 0.0006); scaled
// by the spring's waviness per cycle it follows the truth within 0.001 in
// both (measured 0.00013 and 0.00037).
TEST(ScanSlopeHistory, TakesTheTracksGrowthOutOfTheScanSideMuHat) {
  double sum2[2][2] = {};  // [history][running-in, after]
  int count[2][2] = {};
  for (std::uint64_t seed : {7001u, 7002u, 7003u}) {
    samples::SimulationOptions o = samples::PaperCase("S-RT-R");
    o.cycles = 200;
    o.elastic_mm = 0;
    o.scan_cols = 512;
    o.scan_rows = 384;
    o.scan_pitch_mm = 0.0148;
    o.seed = seed;
    const sim::SimulatedTest t = sim::Simulate(o);
    for (int history = 0; history < 2; ++history) {
      FuseOptions fo;
      fo.fit_lugre = false;
      fo.scan_slope_history = history == 1;
      const TestResult r = AnalyzeTest(t.record, t.scan, fo);
      ASSERT_TRUE(r.scan.has_value());
      EXPECT_EQ(r.ScanSlopeFits().slope_scale.size(),
                history ? r.force.cycles.cycles.size() : 0u);
      const int first = r.force.running_in.cycles;
      ASSERT_GT(first, 10);
      for (size_t c = 0; c < r.ScanSlopeFits().cycles.size(); ++c) {
        const MuFit& f = r.ScanSlopeFits().cycles[c];
        ASSERT_TRUE(f.converged) << c;
        const int part = static_cast<int>(c) < first ? 0 : 1;
        const double e = f.mu_hat - t.truth.mu_per_cycle[c];
        sum2[history][part] += e * e;
        ++count[history][part];
      }
      if (history) {
        // Early cycles slid on a shallower track: factors below 1.
        EXPECT_LT(r.ScanSlopeFits().slope_scale.front(), 0.5);
        EXPECT_NEAR(r.ScanSlopeFits().slope_scale.back(), 1.0, 0.1);
      }
    }
  }
  double rms[2][2];
  for (int h = 0; h < 2; ++h)
    for (int part = 0; part < 2; ++part)
      rms[h][part] = std::sqrt(sum2[h][part] / count[h][part]);
  EXPECT_GT(rms[0][0], 0.005);
  EXPECT_LT(rms[1][0], 0.001);
  EXPECT_LT(rms[1][1], 0.001);
  EXPECT_LT(rms[1][1], rms[0][1] / 3);
}

INSTANTIATE_TEST_SUITE_P(Cases,
                         HistoryCase,
                         ::testing::Combine(::testing::Values("B-RT-R",
                                                              "B-RT-T",
                                                              "B-RL-R",
                                                              "B-RL-L",
                                                              "B-TL-T",
                                                              "B-TL-L",
                                                              "S-RT-R",
                                                              "S-RT-T",
                                                              "S-RL-R",
                                                              "S-RL-L",
                                                              "S-TL-T",
                                                              "S-TL-L"),
                                            ::testing::Values(1.0, 2.0)),
                         [](const auto& param_info) {
                           std::string n = std::get<0>(param_info.param);
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n + "_noise" +
                                  std::to_string(static_cast<int>(
                                      std::get<1>(param_info.param)));
                         });

}  // namespace
}  // namespace wearscar::fusion
