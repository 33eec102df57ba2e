// Error bars: mu-hat's standard error per cycle against the spread of
// mu-hat over repeated noise, the intervals of a mean of correlated
// per-cycle values against a known mean, and the per-test interval's
// coverage of the simulator's truth at its calibrated noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <tuple>

#include "common/simulated.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/fit_mu.h"
#include "wearscar/fusion/forward_model.h"
#include "wearscar/fusion/fuse.h"

namespace wearscar::fusion {
namespace {

// Q as the wear-scar model predicts on a wavy path, with white noise.
CycleSamples NoisySamples(double mu, double noise_n, std::mt19937* gen) {
  std::normal_distribution<double> noise(0.0, noise_n);
  CycleSamples s;
  for (SlipSamples* d : {&s.forward, &s.reverse}) {
    d->direction = d == &s.forward ? +1 : -1;
    const int n = 1000;
    d->q_n.resize(n);
    d->p_n.resize(n);
    d->k.resize(n);
    d->x_mm.resize(n);
    for (int i = 0; i < n; ++i) {
      const double x = -2.5 + 5.0 * i / (n - 1);
      d->x_mm[i] = d->direction * x;
      d->k[i] = 0.08 * std::cos(2 * M_PI * x / 1.6);
      d->p_n[i] = 30 + 0.5 * std::sin(2 * M_PI * x / 1.6);
      d->q_n[i] =
          WearScarTangentialForce(d->p_n[i], d->k[i], mu, d->direction) +
          noise(*gen);
    }
  }
  return s;
}

// White noise of 0.05 N on 2 x 1000 samples: the standard error equals
// the spread of mu-hat over 2000 repeats within 10% (measured 0.96), agrees
// with the least-squares value sigma / sqrt(sum g^2) within 10%, and mu-hat
// +- 1.96 se holds the true mu in 92-98% of them (measured 93.8%).
TEST(StandardError, MatchesTheSpreadOfMuHatUnderWhiteNoise) {
  const double mu = 0.12, sigma = 0.05;
  std::mt19937 gen(7);
  double sum = 0, sum2 = 0, se_sum = 0;
  int inside = 0;
  const int repeats = 2000;
  double g2 = 0;
  for (int r = 0; r < repeats; ++r) {
    const CycleSamples s = NoisySamples(mu, sigma, &gen);
    if (r == 0) {
      for (const SlipSamples* d : {&s.forward, &s.reverse}) {
        for (Eigen::Index i = 0; i < d->k.size(); ++i) {
          const double den = 1 - d->direction * mu * d->k[i];
          const double g = d->p_n[i] * (1 + d->k[i] * d->k[i]) / (den * den);
          g2 += g * g;
        }
      }
    }
    const MuFit f = FitMu(s);
    ASSERT_TRUE(f.converged) << f.BriefReport();
    ASSERT_TRUE(std::isfinite(f.standard_error));
    sum += f.mu_hat;
    sum2 += f.mu_hat * f.mu_hat;
    se_sum += f.standard_error;
    inside += std::abs(f.mu_hat - mu) <= 1.96 * f.standard_error;
  }
  const double spread = std::sqrt((sum2 - sum * sum / repeats) / (repeats - 1));
  const double se = se_sum / repeats;
  EXPECT_NEAR(se / spread, 1.0, 0.1) << "se " << se << ", spread " << spread;
  EXPECT_NEAR(se * std::sqrt(g2) / sigma, 1.0, 0.1);
  EXPECT_GE(inside, 0.92 * repeats) << "se " << se << ", spread " << spread
                                    << ", ls " << sigma / std::sqrt(g2);
  EXPECT_LE(inside, 0.98 * repeats);
}

TEST(StandardError, IsZeroForAnExactFit) {
  std::mt19937 gen(1);
  const MuFit f = FitMu(NoisySamples(0.2, 0.0, &gen));
  ASSERT_TRUE(f.converged);
  EXPECT_LT(f.standard_error, 1e-6);
}

// Independent cycles (correlation 1) give 1.96 se / sqrt(n); errors common
// to all cycles give 1.96 se, one effective cycle.
TEST(SummariseWithErrors, IndependentAndCommonErrorsAnalytically) {
  const std::vector<double> v(25, 0.1), se(25, 0.01);
  const Statistic a = SummariseWithErrors(v, se, 0, 24, 1);
  EXPECT_NEAR(a.high - a.mean, 1.96 * 0.01 / 5, 1e-12);
  EXPECT_NEAR(a.effective_count, 25, 1e-9);
  const Statistic c = SummariseWithErrors(v, se, 0, 24, 25);
  // Triangular correlation over 25 cycles: sum rho = 25 + 2 sum (1 - d/25).
  double sum_rho = 25;
  for (int d = 1; d < 25; ++d) sum_rho += 2 * (25 - d) * (1 - d / 25.0);
  EXPECT_NEAR(c.high - c.mean, 1.96 * 0.01 * std::sqrt(sum_rho) / 25, 1e-12);
  EXPECT_NEAR(c.effective_count, 25 * 25 / sum_rho, 1e-9);
  // A cycle without an error: no interval.
  std::vector<double> missing = se;
  missing[3] = std::nan("");
  EXPECT_TRUE(std::isnan(SummariseWithErrors(v, missing, 0, 24, 1).low));
}

// Errors that are moving averages of W white draws have exactly the
// triangular correlation 1 - |d| / W: over 2000 series of 80 cycles the
// interval holds the known mean in 93-97% of them.
TEST(SummariseWithErrors, CoversTheMeanOfMovingAverageErrors) {
  std::mt19937 gen(11);
  std::normal_distribution<double> z(0.0, 1.0);
  const int n = 80, w = 11, series = 2000;
  int inside = 0;
  for (int t = 0; t < series; ++t) {
    std::vector<double> draws(n + w);
    for (double& d : draws) d = z(gen);
    std::vector<double> v(n), se(n);
    for (int c = 0; c < n; ++c) {
      double e = 0;
      for (int j = 0; j < w; ++j) e += draws[c + j];
      se[c] = 0.002 * (1 + 0.5 * (c % 3));  // unequal errors
      v[c] = 0.3 + se[c] * e / std::sqrt(w);
    }
    const Statistic s = SummariseWithErrors(v, se, 0, n - 1, w);
    inside += s.low <= 0.3 && 0.3 <= s.high;
  }
  EXPECT_GE(inside, 0.93 * series);
  EXPECT_LE(inside, 0.97 * series);
}

// An AR(1) scatter (r = 0.6) about a drifting line: the interval of the
// mean holds the line's mean over the cycles in 90-98% of 2000 series,
// and the effective count is about n (1 - r) / (1 + r) = 25.
TEST(SummariseSeries, CoversTheMeanOfAutocorrelatedScatterAboutATrend) {
  std::mt19937 gen(5);
  std::normal_distribution<double> z(0.0, 1.0);
  const int n = 100, series = 2000;
  const double r = 0.6;
  int inside = 0;
  double n_eff = 0;
  for (int t = 0; t < series; ++t) {
    std::vector<double> v(n);
    double e = z(gen) / std::sqrt(1 - r * r);
    for (int c = 0; c < n; ++c) {
      e = r * e + z(gen);
      v[c] = 0.2 + 0.0004 * (c - (n - 1) / 2.0) + 0.003 * e;
    }
    const Statistic s = SummariseSeries(v, 0, n - 1);
    inside += s.low <= 0.2 && 0.2 <= s.high;
    n_eff += s.effective_count;
  }
  EXPECT_GE(inside, 0.90 * series);
  EXPECT_LE(inside, 0.98 * series);
  EXPECT_NEAR(n_eff / series, n * (1 - r) / (1 + r), 5.0);
}

// A paper case as the coverage studies run it: 100 cycles at 1 kHz, no
// elastic part, a small scan (unused: k from P).
sim::SimulatedTest ShortTest(const std::string& name,
                             double noise,
                             std::uint64_t seed) {
  samples::SimulationOptions o = samples::PaperCase(name);
  o.cycles = 100;
  o.sampling_rate_hz = 1000;
  o.elastic_mm = 0;
  o.noise_scale = noise;
  o.scan_cols = 32;
  o.scan_rows = 24;
  o.scan_pitch_mm = 0.25;
  o.seed = seed;
  return sim::Simulate(o);
}

// Errors in variables: the noise in the ensemble's k biases mu-hat low by
// about 3 mu var(k noise). At four times the calibrated noise (S-RT-T, 100
// cycles at 1 kHz, 24 seeds) the bias is several times the scatter of its
// mean without the correction and within it with the correction (measured:
// -0.00067 and +0.00011, the scatter of the mean 0.00006).
TEST(KNoiseBias, IsRemovedFromMuHat) {
  double with = 0, without = 0, spread = 0, removed = 0;
  const int seeds = 24;
  for (int seed = 1; seed <= seeds; ++seed) {
    const sim::SimulatedTest t = ShortTest("S-RT-T", 4, 7000 + seed);
    for (bool correct : {false, true}) {
      FuseOptions fo;
      fo.fit_lugre = false;
      fo.analysis.friction.correct_k_noise_bias = correct;
      const TestResult r = AnalyzeTest(t.record, std::nullopt, fo);
      double error = 0;
      int n = 0;
      for (int c = r.mismatch.first_cycle; c <= r.mismatch.last_cycle; ++c) {
        const MuFit& f = r.ForceFits().cycles[c];
        if (!f.converged) continue;
        error += f.mu_hat - t.truth.mu_per_cycle[c];
        ++n;
      }
      ASSERT_GT(n, 40);
      error /= n;
      (correct ? with : without) += error / seeds;
      if (correct) {
        spread += error * error / seeds;
        removed += r.ForceFits().k_noise_correction / seeds;
      }
    }
  }
  const double se = std::sqrt(spread / seeds);
  RecordProperty("bias_without", std::to_string(without));
  RecordProperty("bias_with", std::to_string(with));
  EXPECT_LT(without, -4 * se) << "without " << without << ", se " << se;
  EXPECT_LT(std::abs(with), 2.5 * se) << "with " << with << ", se " << se;
  EXPECT_NEAR(removed, with - without, 0.05 * (with - without));
}

// The ensemble k's noise from its odd and even halves follows the sensor
// noise (twice the noise, twice the rms) and leaves out the track's change
// between cycles, which the noise split's template counts as noise on a
// fast-wearing track (S-RT-R, 100 cycles at 1 kHz; measured 0.0105 and
// 0.0208 per sample, the split 0.0199 at noise 1).
TEST(KNoiseBias, NoiseFromTheEnsemblesHalvesFollowsTheSensorNoise) {
  double halves[2] = {}, split[2] = {};
  for (int i = 0; i < 2; ++i) {
    const sim::SimulatedTest t = ShortTest("S-RT-R", i + 1, 7001);
    FuseOptions fo;
    fo.fit_lugre = false;
    const TestResult r = AnalyzeTest(t.record, std::nullopt, fo);
    halves[i] = r.ForceFits().k_ensemble_noise_rms;
    split[i] = r.ForceFits().k_noise_rms;
  }
  RecordProperty("halves_noise1", std::to_string(halves[0]));
  RecordProperty("halves_noise2", std::to_string(halves[1]));
  RecordProperty("split_noise1", std::to_string(split[0]));
  EXPECT_NEAR(halves[1] / halves[0], 2.0, 0.2);
  EXPECT_GT(split[0], 1.5 * halves[0]);
}

class Coverage
    : public ::testing::TestWithParam<std::tuple<const char*, double>> {};

// The simulator at its calibrated noise (1) and twice it, 100 seeds, 100
// cycles at 1 kHz, no elastic part, k from P: the per-test interval of
// mu-hat after running-in holds the mean of the true mu over the same
// cycles in 90-98% of the seeds, and the per-cycle intervals hold the
// cycle's true mu in at least 93% of the cycles. (Measured on all twelve
// paper cases: 89-97% per test, 98-99% per cycle; docs/method.md "Error bars".)
TEST_P(Coverage, PerTestIntervalHoldsTheTruth) {
  const auto [name, noise] = GetParam();
  int inside = 0, tests = 0;
  long cycles_inside = 0, cycles = 0;
  for (int seed = 1; seed <= 100; ++seed) {
    const sim::SimulatedTest t = ShortTest(name, noise, 5000 + seed);
    FuseOptions fo;
    fo.fit_lugre = false;
    const TestResult r = AnalyzeTest(t.record, std::nullopt, fo);
    const MismatchReport& m = r.mismatch;
    double truth = 0;
    int n = 0;
    for (int c = m.first_cycle; c <= m.last_cycle; ++c) {
      const MuFit& f = r.ForceFits().cycles[c];
      if (!f.converged) continue;
      const double mu = t.truth.mu_per_cycle[c];
      truth += mu;
      ++n;
      cycles_inside += std::abs(f.mu_hat - mu) <= 1.96 * f.standard_error;
      ++cycles;
    }
    ASSERT_GT(n, 40);
    truth /= n;
    ASSERT_TRUE(std::isfinite(m.mu_force.low));
    inside += m.mu_force.low <= truth && truth <= m.mu_force.high;
    ++tests;
  }
  EXPECT_GE(inside, 90) << name << " noise " << noise;
  EXPECT_LE(inside, 98) << name << " noise " << noise;
  EXPECT_GE(cycles_inside, 0.93 * cycles) << name << " noise " << noise;
}

INSTANTIATE_TEST_SUITE_P(CalibratedNoise,
                         Coverage,
                         ::testing::Values(std::make_tuple("B-RT-R", 1.0),
                                           std::make_tuple("S-RT-R", 2.0)),
                         [](const auto& p) {
                           std::string n = std::get<0>(p.param);
                           n.erase(std::remove(n.begin(), n.end(), '-'),
                                   n.end());
                           return n + "Noise" +
                                  std::to_string(
                                      static_cast<int>(std::get<1>(p.param)));
                         });

}  // namespace
}  // namespace wearscar::fusion
