#include "wearscar/fusion/fit_mu.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::fusion {
namespace {

// Q measured exactly as the wear-scar model predicts on a wavy path.
CycleSamples ModelSamples(double mu, double noise_n, unsigned seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> noise(0.0, noise_n);
  CycleSamples s;
  for (SlipSamples* d : {&s.forward, &s.reverse}) {
    d->direction = d == &s.forward ? +1 : -1;
    const int n = 800;
    d->q_n.resize(n);
    d->p_n.resize(n);
    d->k.resize(n);
    d->x_mm.resize(n);
    for (int i = 0; i < n; ++i) {
      const double x = -2.5 + 5.0 * i / (n - 1);
      d->x_mm[i] = x;
      d->k[i] = 0.1 * std::cos(2 * M_PI * x / 1.6);
      d->p_n[i] = 30 + 0.5 * std::sin(2 * M_PI * x / 1.6);
      d->q_n[i] =
          WearScarTangentialForce(d->p_n[i], d->k[i], mu, d->direction) +
          noise(gen);
    }
  }
  return s;
}

TEST(WearScarModel, EqualsTangentOfTiltedAngle) {
  // Q_w = P tan(theta + s atan mu) with k = tan theta.
  const double p = 30, k = 0.07, mu = 0.12;
  for (int s : {+1, -1}) {
    EXPECT_NEAR(WearScarTangentialForce(p, k, mu, s),
                p * std::tan(std::atan(k) + s * std::atan(mu)),
                1e-12);
  }
  EXPECT_DOUBLE_EQ(WearScarTangentialForce(p, 0.0, mu, +1),
                   mu * p);  // Coulomb for k = 0
}

TEST(FitMu, RecoversKnownMuExactlyWithoutNoise) {
  for (double mu : {0.05, 0.12, 0.3, 0.7}) {
    const MuFit f = FitMu(ModelSamples(mu, 0.0, 1));
    EXPECT_TRUE(f.converged) << f.BriefReport();
    EXPECT_NEAR(f.mu_hat, mu, 1e-6) << f.BriefReport();
    EXPECT_LT(f.cost, 1e-5);  // J ~ 19 |mu - mu_true| here; tolerance 1e-7
    EXPECT_FALSE(f.at_bound);
    EXPECT_EQ(f.samples, 1600);
  }
}

TEST(FitMu, RecoversMuUnderNoiseAndReportsCost) {
  const MuFit f = FitMu(ModelSamples(0.12, 0.2, 3));
  EXPECT_NEAR(f.mu_hat, 0.12, 2e-3);
  EXPECT_GT(f.cost, 0.02);
  EXPECT_LT(f.cost, 0.2);
}

TEST(FitMu, ReportsWhenTheMinimumSitsOnABound) {
  FitMuOptions o;
  o.mu_max = 0.08;
  const MuFit f = FitMu(ModelSamples(0.12, 0.0, 1), o);
  EXPECT_TRUE(f.at_bound);
  EXPECT_NEAR(f.mu_hat, 0.08, 1e-5);
}

TEST(FitMu, TooFewSamplesIsReportedNotGuessed) {
  CycleSamples s;
  const MuFit f = FitMu(s);
  EXPECT_FALSE(f.converged);
  EXPECT_EQ(f.message, "too few gross-slip samples");
}

TEST(FitMu, CostCurveHasItsMinimumAtMuHat) {
  const CycleSamples s = ModelSamples(0.2, 0.05, 5);
  const Eigen::VectorXd grid = Eigen::VectorXd::LinSpaced(1001, 0.0, 1.0);
  const Eigen::VectorXd j = CostCurve(s, grid);
  Eigen::Index best;
  j.minCoeff(&best);
  EXPECT_NEAR(grid[best], FitMu(s).mu_hat, 1e-3);
}

TEST(AnalyzeForce, RecoversSimulatedMuPerCycleOnBeechRtR) {
  samples::SimulationOptions o = samples::PaperCase("B-RT-R");
  o.cycles = 80;
  const samples::SimulatedTest t = samples::Simulate(o);
  AnalysisOptions a;
  a.running_in_cycles = 30;
  const ForceAnalysis r = AnalyzeForce(t.record, a);
  ASSERT_EQ(r.cycles.cycles.size(), 80u);
  double worst = 0;
  for (int c = 30; c < 80; ++c) {
    worst = std::max(worst,
                     std::abs(r.fit_force[c].mu_hat - t.truth.mu_per_cycle[c]));
  }
  EXPECT_LT(worst, 0.004);
  EXPECT_LT(r.cost.mean, 0.4);  // explained (paper's threshold)
}

TEST(AnalyzeForce, LargeElasticPartRaisesJAboveThreshold) {
  samples::SimulationOptions o = samples::PaperCase("S-RL-R");
  o.cycles = 80;
  const ForceAnalysis r =
      AnalyzeForce(samples::Simulate(o).record, AnalysisOptions{});
  EXPECT_GT(r.cost.mean, 0.4);
}

}  // namespace
}  // namespace wearscar::fusion
