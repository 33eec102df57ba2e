#include "wearscar/fusion/diagnose.h"

#include <gtest/gtest.h>

#include <cmath>

#include "diagnose_simulated.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::fusion {
namespace {

struct Hidden {
  const char* label;
  const char* effect;  // the name the diagnosis must give
  double strength;     // hidden strength (the effect's first parameter)
  void (*set)(samples::HiddenEffects*, double);
};

// At the noise calibrated to the paper (1) and twice it (2).
class DiagnoseHiddenEffect
    : public ::testing::TestWithParam<std::tuple<Hidden, double>> {};

TEST_P(DiagnoseHiddenEffect, NamesItFirstShrinksTheGapAndRecoversItsStrength) {
  const Hidden h = std::get<0>(GetParam());
  samples::SimulationOptions o = samples::PaperCase("S-RT-R");
  o.noise_scale = std::get<1>(GetParam());
  h.set(&o.effects, h.strength);
  const Diagnosis d = DiagnoseSimulated(o);
  ASSERT_FALSE(d.named.empty()) << d.message << " / " << d.before.where;
  EXPECT_EQ(d.named.front(), h.effect) << d.message;
  EXPECT_EQ(d.named.size(), 1u) << d.message;
  EXPECT_LE(d.heldout_final, 0.7 * d.heldout_initial) << d.message;
  const double fitted = d.model.front().parameters.front();
  EXPECT_NEAR(fitted, h.strength, 0.25 * std::abs(h.strength)) << d.message;
}

// Moderate strengths: each adds a few tenths of a newton to Q of about 5 N.
INSTANTIATE_TEST_SUITE_P(
    Library,
    DiagnoseHiddenEffect,
    ::testing::Combine(
        ::testing::Values(
            Hidden{"ploughing",
                   "ploughing",
                   8.0,
                   [](samples::HiddenEffects* e, double v) {
                     e->ploughing_n_per_mm = v;
                   }},
            Hidden{"stribeck",
                   "velocity dependence (Stribeck)",
                   0.3,
                   [](samples::HiddenEffects* e, double v) {
                     e->stribeck_rise = v;
                   }},
            Hidden{"viscous",
                   "viscous term",
                   0.04,
                   [](samples::HiddenEffects* e, double v) {
                     e->viscous_n_s_per_mm = v;
                   }},
            Hidden{"asymmetry",
                   "direction asymmetry",
                   0.1,
                   [](samples::HiddenEffects* e, double v) {
                     e->direction_asymmetry = v;
                   }},
            Hidden{"lag",
                   "time lag of the Q channel",
                   0.003,
                   [](samples::HiddenEffects* e, double v) { e->q_lag_s = v; }},
            Hidden{"crosstalk",
                   "crosstalk of Q into P",
                   0.05,
                   [](samples::HiddenEffects* e, double v) {
                     e->crosstalk_q_into_p = v;
                   }},
            Hidden{"hook",
                   "end-of-stroke hook",
                   1.0,
                   [](samples::HiddenEffects* e, double v) { e->hook_n = v; }},
            Hidden{"mu_variation",
                   "friction varying along the track",
                   0.2,
                   [](samples::HiddenEffects* e, double v) {
                     e->mu_variation = v;
                   }}),
        ::testing::Values(1.0, 2.0)),
    [](const auto& param_info) {
      return std::string(std::get<0>(param_info.param).label) + "_noise" +
             std::to_string(static_cast<int>(std::get<1>(param_info.param)));
    });

TEST(Diagnose, ElasticPartOfTheSRlRCaseIsNamedAsCompliance) {
  const Diagnosis d =
      DiagnoseSimulated(samples::PaperCase("S-RL-R", /*elastic_in_srlr=*/true));
  ASSERT_FALSE(d.named.empty()) << d.message;
  EXPECT_EQ(d.named.front(), "elastic compliance of the track") << d.message;
  EXPECT_LE(d.heldout_final, 0.7 * d.heldout_initial) << d.message;
  EXPECT_GT(d.model.front().parameters.front(),
            0.2);  // spring sees > 1.2x the geometry
}

TEST(Diagnose, TwoHiddenEffectsAreBothNamed) {
  samples::SimulationOptions o = samples::PaperCase("B-RT-R");
  o.effects.hook_n = 1.0;
  o.effects.direction_asymmetry = 0.1;
  const Diagnosis d = DiagnoseSimulated(o);
  ASSERT_GE(d.named.size(), 2u) << d.message;
  std::vector<std::string> first_two(d.named.begin(), d.named.begin() + 2);
  std::sort(first_two.begin(), first_two.end());
  EXPECT_EQ(
      first_two,
      (std::vector<std::string>{"direction asymmetry", "end-of-stroke hook"}))
      << d.message;
  EXPECT_EQ(d.named.size(), 2u) << d.message;
}

// With no hidden effect nothing is named: at most one false discovery over
// the 12 cases (S-RL-R without its elastic part; B-RL-R keeps the small
// elastic part of its preset, which is a real effect, so it is excluded).
class DiagnoseNoEffect
    : public ::testing::TestWithParam<std::tuple<std::string, double>> {};

TEST_P(DiagnoseNoEffect, NamesNothing) {
  samples::SimulationOptions o =
      samples::PaperCase(std::get<0>(GetParam()), /*elastic_in_srlr=*/false);
  o.noise_scale = std::get<1>(GetParam());
  const Diagnosis d = DiagnoseSimulated(o);
  // Each case is its own test; together they allow the issue's one false
  // discovery over 12 only if it shows here as a failure to look at.
  EXPECT_TRUE(d.named.empty()) << std::get<0>(GetParam()) << ": " << d.message;
}

INSTANTIATE_TEST_SUITE_P(Eleven,
                         DiagnoseNoEffect,
                         ::testing::Combine(::testing::Values("B-RT-R",
                                                              "B-RT-T",
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
                           for (char& ch : n) {
                             if (ch == '-') ch = '_';
                           }
                           return n + "_noise" +
                                  std::to_string(static_cast<int>(
                                      std::get<1>(param_info.param)));
                         });

TEST(Diagnose, ResidualMapSaysWhereTheHookIs) {
  samples::SimulationOptions o = samples::PaperCase("S-RT-T");
  o.effects.hook_n = 1.5;
  const Diagnosis d = DiagnoseSimulated(o);
  // Before: the residual concentrates approaching the stroke end; after
  // naming the hook it is gone there.
  const auto& m = d.before;
  const Eigen::Index last = m.x_mm.size() - 1;
  // The outermost bins may be empty (gross slip ends at the reversal).
  const double fwd_end = m.mean_abs_n.row(0).tail(3).maxCoeff();
  const double rev_end = m.mean_abs_n.row(1).head(3).maxCoeff();
  EXPECT_GT(fwd_end, 3 * m.mean_abs_n(0, last / 2)) << m.where;
  EXPECT_GT(rev_end, 3 * m.mean_abs_n(1, last / 2)) << m.where;
  EXPECT_NE(m.where.find("approaching the stroke end"), std::string::npos);
  EXPECT_LT(d.after.mean_abs_n.row(0).tail(3).maxCoeff(), 0.5 * fwd_end)
      << d.after.where;
}

}  // namespace
}  // namespace wearscar::fusion
