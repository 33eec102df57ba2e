#include "wearscar/fusion/fit_mu.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "common/simulated.h"
#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/ensemble.h"
#include "wearscar/fusion/forward_model.h"

namespace wearscar::fusion {
namespace {

// Q measured exactly as the wear-scar model predicts on a wavy path.
CycleSamples ModelSamples(double mu, double noise_n, unsigned seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> noise(0.0, noise_n);
  CycleSamples s;
  for (SlipSamples *d : {&s.forward, &s.reverse}) {
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

// With noise J is smooth at its minimum, and Newton's method from the
// first-order estimate reaches it in a few steps (the grid and Brent, its
// fallback, take about 25 evaluations): mu-hat is where a grid 1e-6 fine
// finds the least J.
TEST(FitMu, NewtonsStepsReachTheMinimumOfJ) {
  for (double mu : {0.05, 0.2, 0.6}) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const CycleSamples s = ModelSamples(mu, 0.05, seed);
      const MuFit f = FitMu(s);
      ASSERT_TRUE(f.converged) << f.BriefReport();
      EXPECT_LE(f.iterations, 6) << f.BriefReport();
      const Eigen::VectorXd grid =
          Eigen::VectorXd::LinSpaced(2001, f.mu_hat - 1e-3, f.mu_hat + 1e-3);
      const Eigen::VectorXd j = CostCurve(s, grid);
      Eigen::Index best;
      const double least = j.minCoeff(&best);
      EXPECT_NEAR(grid[best], f.mu_hat, 2e-6) << mu << " " << seed;
      EXPECT_LE(f.cost, least + 1e-12);
      EXPECT_NEAR(f.mu_hat, mu, 5e-3);
    }
  }
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
  const sim::SimulatedTest t = sim::Simulate(o);
  AnalysisOptions a;
  a.running_in_cycles = 30;
  const ForceFitted r = AnalyzeForce(t.record, a);
  ASSERT_EQ(r.cycles.cycles.size(), 80u);
  double worst = 0;
  for (int c = 30; c < 80; ++c) {
    worst = std::max(
        worst, std::abs(r.fits.cycles[c].mu_hat - t.truth.mu_per_cycle[c]));
  }
  EXPECT_LT(worst, 0.004);
  EXPECT_LT(r.fits.cost.mean, 0.4);  // explained (paper's threshold)
}

// A simulated case of `cycles` cycles, segmented with its gross slip, for
// FitFriction with k from P.
struct SegmentedCase {
  SegmentedCase(const std::string &name, int cycles) {
    samples::SimulationOptions o = samples::PaperCase(name);
    o.cycles = cycles;
    test = sim::Simulate(o);
    set = force::SegmentCycles(test.record.x_mm);
    force::FindGrossSlip(test.record, &set, AnalysisOptions{}.slip);
  }
  FrictionFits Fit(const FrictionFitOptions &o) const {
    return FitFriction(test.record, set, SlopeSource::kForce, o);
  }
  sim::SimulatedTest test;
  force::CycleSet set;
};

// On two threads the second half of the cycles is fitted beside the first
// with an ensemble of its own: every number of every cycle's fit, and the
// noise split over all of them, the same as on one.
TEST(FitFriction, TwoThreadsGiveTheFitsOfOne) {
  const SegmentedCase t("S-RT-R", 90);
  FrictionFitOptions one = AnalysisOptions{}.friction, two = one;
  two.threads = 2;
  const FrictionFits f1 = t.Fit(one), f2 = t.Fit(two);
  ASSERT_EQ(f1.cycles.size(), 90u);
  ASSERT_EQ(f2.cycles.size(), 90u);
  for (size_t c = 0; c < f1.cycles.size(); ++c) {
    const MuFit &x = f1.cycles[c], &y = f2.cycles[c];
    ASSERT_TRUE(x.converged) << c;
    EXPECT_EQ(x.mu_hat, y.mu_hat) << c;
    EXPECT_EQ(x.cost, y.cost) << c;
    EXPECT_EQ(x.samples, y.samples) << c;
    EXPECT_EQ(x.standard_error, y.standard_error) << c;
    EXPECT_EQ(x.cost_floor, y.cost_floor) << c;
    EXPECT_EQ(x.cost_excess, y.cost_excess) << c;
    EXPECT_NEAR(x.mu_hat, t.test.truth.mu_per_cycle[c], 0.01) << c;
  }
  EXPECT_EQ(f1.k_ensemble_noise_rms, f2.k_ensemble_noise_rms);
  EXPECT_EQ(f1.k_noise_correction, f2.k_noise_correction);
  // (k's split runs beside the misfit's with two threads.)
  EXPECT_EQ(f1.k_signal_rms, f2.k_signal_rms);
  EXPECT_EQ(f1.k_noise_rms, f2.k_noise_rms);
  EXPECT_TRUE(std::isfinite(f2.k_signal_rms) && f2.k_signal_rms > 0);
  // The scan's slope (here a wavy track of the stroke's length): its
  // halves on two threads give every fit of one.
  PlateProfile scan;
  scan.x_mm = Eigen::VectorXd::LinSpaced(2001, -5, 5);
  scan.k = (2 * scan.x_mm.array()).sin() * 0.01;
  const FrictionFits s1 =
      FitFriction(t.test.record, t.set, SlopeSource::kScan, one, &scan);
  const FrictionFits s2 =
      FitFriction(t.test.record, t.set, SlopeSource::kScan, two, &scan);
  ASSERT_EQ(s2.cycles.size(), 90u);
  int converged = 0;
  for (size_t c = 0; c < s1.cycles.size(); ++c) {
    const MuFit &x = s1.cycles[c], &y = s2.cycles[c];
    EXPECT_EQ(x.converged, y.converged) << c;
    converged += y.converged;
    if (!x.converged) continue;
    EXPECT_EQ(x.mu_hat, y.mu_hat) << c;
    EXPECT_EQ(x.cost, y.cost) << c;
    EXPECT_EQ(x.cost_floor, y.cost_floor) << c;
  }
  EXPECT_GT(converged, 80);
  one.threads = 0;
  std::string why;
  EXPECT_FALSE(one.IsValid(&why));
  EXPECT_NE(why.find("threads"), std::string::npos) << why;
}

// Without the noise split (a live window splits against earlier windows)
// the fits and the bias correction are those with it, to the bit; only
// the split's figures are left NaN.
TEST(FitFriction, WithoutTheNoiseSplitTheFitsAreTheSame) {
  const SegmentedCase t("B-RL-R", 40);
  FrictionFitOptions split = AnalysisOptions{}.friction, none = split;
  none.split_noise = false;
  const FrictionFits f1 = t.Fit(split), f2 = t.Fit(none);
  ASSERT_EQ(f1.cycles.size(), f2.cycles.size());
  int converged = 0;
  for (size_t c = 0; c < f1.cycles.size(); ++c) {
    const MuFit &x = f1.cycles[c], &y = f2.cycles[c];
    EXPECT_EQ(x.converged, y.converged) << c;
    if (!x.converged) continue;
    ++converged;
    EXPECT_EQ(x.mu_hat, y.mu_hat) << c;
    EXPECT_EQ(x.cost, y.cost) << c;
    EXPECT_EQ(x.standard_error, y.standard_error) << c;
    EXPECT_TRUE(std::isfinite(x.cost_floor)) << c;
    EXPECT_TRUE(std::isnan(y.cost_floor)) << c;
    EXPECT_TRUE(std::isnan(y.cost_excess)) << c;
  }
  EXPECT_GE(converged, 30);
  EXPECT_NE(f1.k_noise_correction, 0.0);
  EXPECT_EQ(f1.k_noise_correction, f2.k_noise_correction);
  EXPECT_TRUE(std::isfinite(f1.k_noise_rms));
  EXPECT_TRUE(std::isnan(f2.k_noise_rms));
}

TEST(RunningIn, EndsWhereTheTransientFallsInsideTheBand) {
  // 0.11 + 0.04 exp(-c / 20) with a slow drift and scatter: the transient
  // drops below the 0.005 band at c = 20 ln 8 = 41.6.
  std::mt19937 gen(5);
  std::normal_distribution<double> noise(0, 0.0005);
  std::vector<double> v;
  for (int c = 0; c < 300; ++c)
    v.push_back(0.11 + 0.04 * std::exp(-c / 20.0) + 2e-5 * c + noise(gen));
  const RunningIn r = DetectRunningIn(v, 0.005);
  EXPECT_TRUE(r.detected);
  EXPECT_NEAR(r.cycles, 42, 4) << r.rule;
  EXPECT_NEAR(r.steady_slope, 2e-5, 5e-6);
  EXPECT_DOUBLE_EQ(r.tolerance, 0.005);
  // No transient: no running-in. Too few cycles: none, and said so.
  std::vector<double> flat(100, 0.12);
  EXPECT_EQ(DetectRunningIn(flat, 0.005).cycles, 0);
  const RunningIn few = DetectRunningIn({0.2, 0.15, 0.12}, 0.005);
  EXPECT_FALSE(few.detected);
  EXPECT_NE(few.rule.find("too few"), std::string::npos);
}

TEST(RunningIn, DetectedOnTheSimulatorNearTheTrueTransient) {
  // B-RT-R: mu = 0.110 + 0.04 exp(-n / 30) + drift; the transient is inside
  // 0.005 from n = 30 ln 8 = 62.
  samples::SimulationOptions o = samples::PaperCase("B-RT-R");
  o.cycles = 200;
  o.scan_cols = o.scan_rows = 32;
  const ForceFitted r =
      AnalyzeForce(sim::Simulate(o).record, AnalysisOptions{});
  EXPECT_TRUE(r.running_in.detected);
  EXPECT_NEAR(r.running_in.cycles, 62, 12) << r.running_in.rule;
}

TEST(AnalyzeForce, LargeElasticPartRaisesJAboveThreshold) {
  samples::SimulationOptions o = samples::PaperCase("S-RL-R");
  o.cycles = 80;
  const ForceFitted r =
      AnalyzeForce(sim::Simulate(o).record, AnalysisOptions{});
  EXPECT_GT(r.fits.cost.mean, 0.4);
}

// The reverse direction on a thread of its own: the same split.
void ExpectTheSameSplitThreaded(
    const CycleBins &bins,
    const std::vector<std::array<double, 2>> &total,
    int sep,
    const RepeatabilityOptions &o,
    const std::vector<std::array<RepeatSplit, 2>> &split) {
  const auto threaded = SplitRepeatable(bins, total, sep, o, true);
  ASSERT_EQ(threaded.size(), split.size());
  for (std::size_t i = 0; i < split.size(); ++i) {
    for (int d = 0; d < 2; ++d) {
      EXPECT_EQ(threaded[i][d].total, split[i][d].total);
      EXPECT_TRUE(
          threaded[i][d].repeat == split[i][d].repeat ||
          (std::isnan(threaded[i][d].repeat) && std::isnan(split[i][d].repeat)))
          << i << " " << d;
      EXPECT_EQ(threaded[i][d].samples, split[i][d].samples);
    }
  }
}

// The noise split's template, slid along the cycles, is the template summed
// afresh: for every cycle, the ends of the test included, its repeat is
// the cycle's sums times the mean of the t nearest cycles at distance sep
// or more (as balanced as the ends allow), as Window sums them; none where
// no cycle is that far.
TEST(SplitRepeatable, TheSlidTemplateIsTheTemplateSummedAfresh) {
  PlateGrid grid;
  grid.bin_mm = 0.1;
  grid.bins = 40;
  const int first = 3, last = 62;
  CycleBins bins(grid, first, last, /*with_x=*/false);
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> along(0.0, 4.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int c = first; c <= last; ++c) {
    for (int dir : {+1, -1}) {
      for (int i = 0; i < 200; ++i) {
        const double x = along(gen);
        // Magnitudes that differ by orders from cycle to cycle.
        bins.Add(c,
                 dir,
                 x,
                 std::sin(x) * (1 + 0.01 * c) +
                     noise(gen) * std::pow(10.0, c % 5 - 2));
      }
    }
  }
  const int n = last - first + 1;
  const std::vector<std::array<double, 2>> total(n, {1.0, 2.0});
  int compared = 0, none = 0;
  for (int sep : {1, 3, 6, 40}) {
    for (int t : {2, 10, 25}) {
      RepeatabilityOptions o;
      o.template_cycles = t;
      const auto split = SplitRepeatable(bins, total, sep, o);
      ASSERT_EQ(static_cast<int>(split.size()), n);
      ExpectTheSameSplitThreaded(bins, total, sep, o, split);
      for (int c = first; c <= last; ++c) {
        int left = t / 2, right = t - t / 2;
        const int room_left = std::max(0, c - sep - first + 1);
        const int room_right = std::max(0, last - (c + sep) + 1);
        if (left > room_left) right += left - room_left, left = room_left;
        if (right > room_right) {
          left = std::min(room_left, left + right - room_right);
          right = room_right;
        }
        for (int d = 0; d < 2; ++d) {
          const RepeatSplit &r = split[c - first][d];
          EXPECT_EQ(r.total, d == 0 ? 1.0 : 2.0);
          if (left + right == 0) {
            EXPECT_TRUE(std::isnan(r.repeat)) << c;
            ++none;
            continue;
          }
          const int dir = d == 0 ? +1 : -1;
          const CycleBins::Sums own = bins.Cycle(c, dir);
          const CycleBins::Sums tpl = bins.Window(dir,
                                                  c - sep - left + 1,
                                                  c + sep + right - 1,
                                                  c - sep + 1,
                                                  c + sep - 1);
          double cross = 0;
          int samples = 0;
          for (int b = 0; b < grid.bins; ++b) {
            if (own.count[b] == 0 || tpl.count[b] == 0) continue;
            cross += own.value[b] * (tpl.value[b] / tpl.count[b]);
            samples += own.count[b];
          }
          EXPECT_NEAR(r.repeat, cross, 1e-12 * (1 + std::abs(cross)))
              << "cycle " << c << " sep " << sep << " t " << t;
          EXPECT_EQ(r.samples, samples);
          ++compared;
        }
      }
    }
  }
  EXPECT_GT(compared, 500);
  EXPECT_GT(none, 0);
}

// The direction split of what repeats: a misfit the same both ways (a
// slope's) leaves no friction-like part, even where one direction slid
// alone (the first 0.6 mm: the other still turning) and where the
// directions' sample counts differ; one that changes sign with the motion
// is found whole over the bins both slid in, 4 sum w o^2. Counted over the
// bins one direction alone slid in, the even misfit read as odd there.
TEST(SplitRepeatable, TheDirectionSplitCountsOnlyWhereBothDirectionsSlid) {
  PlateGrid grid;
  grid.bin_mm = 0.1;
  grid.bins = 40;
  const int first = 0, last = 29;
  for (const double odd : {0.0, 0.5}) {
    CycleBins bins(grid, first, last, /*with_x=*/false);
    for (int c = first; c <= last; ++c) {
      for (int dir : {+1, -1}) {
        // Forward slides from 0.6 mm, with twice the reverse's samples.
        const int per_bin = dir > 0 ? 4 : 2;
        for (int b = dir > 0 ? 6 : 0; b < grid.bins; ++b) {
          const double x = (b + 0.5) * grid.bin_mm;
          for (int i = 0; i < per_bin; ++i)
            bins.Add(c, dir, x, std::sin(x) + dir * odd * std::cos(x));
        }
      }
    }
    // The direction split comes with the noise split's pass, on two
    // threads; on one, and without it, the same values to the bit.
    const std::vector<std::array<double, 2>> total(last - first + 1,
                                                   {1.0, 1.0});
    std::vector<std::array<RepeatSplit, 2>> parity, parity_one;
    const auto same =
        SplitRepeatable(bins, total, 1, RepeatabilityOptions{}, true, &parity);
    SplitRepeatable(bins, total, 1, RepeatabilityOptions{}, false, &parity_one);
    const auto alone = SplitRepeatable(bins, total, 1, RepeatabilityOptions{});
    ASSERT_EQ(parity.size(), static_cast<size_t>(last - first + 1));
    double expected = 0;
    for (int b = 6; b < grid.bins; ++b) {
      const double x = (b + 0.5) * grid.bin_mm;
      expected += 2 * std::pow(odd * std::cos(x), 2);  // w = 2
    }
    for (int c = first; c <= last; ++c) {
      const double sum = parity[c][0].repeat + parity[c][1].repeat;
      EXPECT_NEAR(sum / 4, expected, 1e-4 + 1e-4 * expected)
          << "odd " << odd << " cycle " << c;
    }
    for (int c = first; c <= last; ++c) {
      for (int d = 0; d < 2; ++d) {
        EXPECT_EQ(parity_one[c][d].repeat, parity[c][d].repeat) << c;
        EXPECT_EQ(parity_one[c][d].samples, parity[c][d].samples) << c;
        EXPECT_EQ(same[c][d].repeat, alone[c][d].repeat) << c;
        EXPECT_EQ(same[c][d].samples, alone[c][d].samples) << c;
      }
    }
  }
}

}  // namespace
}  // namespace wearscar::fusion
