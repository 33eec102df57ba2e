#include "wearscar/force/cycles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "wearscar/force/cof.h"
#include "wearscar/force/slope.h"

namespace wearscar::force {
namespace {

// A Coulomb test with a Jenkins element: Q follows x with stiffness k_t until
// it reaches +-mu P. x(t) from `drive`.
template <typename Drive>
ForceRecord JenkinsRecord(Drive drive,
                          double rate,
                          double periods,
                          double mu,
                          double noise_mm = 0.0,
                          unsigned seed = 7,
                          double p_wave_n = 0.0) {
  const Eigen::Index n = static_cast<Eigen::Index>(periods * rate);
  ForceRecord r;
  r.time_s.resize(n);
  r.x_mm.resize(n);
  r.tangential_n.resize(n);
  r.normal_n.resize(n);
  std::mt19937 gen(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  double q = 0, xp = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = i / rate;
    const double x = drive(t);
    // P may vary along the stroke (a wavy track under a pure Coulomb law).
    const double p = 30.0 + p_wave_n * std::sin(2 * M_PI * x / 1.6);
    if (i) q += 150.0 * (x - xp);
    q = std::clamp(q, -mu * p, mu * p);
    xp = x;
    r.time_s[i] = t;
    r.x_mm[i] = x + noise_mm * noise(gen);
    r.tangential_n[i] = q;
    r.normal_n[i] = p;
  }
  return r;
}

double Sine(double t) { return 2.85 * std::sin(2 * M_PI * t); }
double Triangle(double t) {
  const double p = std::fmod(t + 0.25, 1.0);
  return p < 0.5 ? -2.85 + 11.4 * p : 2.85 - 11.4 * (p - 0.5);
}

TEST(SegmentCycles, SineWithNoiseGivesCompleteCyclesOnly) {
  // 10.5 periods starting at x = 0 going up: minima at 0.75, 1.75, ...,
  // 9.75 s, so 9 complete cycles; the partial ends are dropped.
  const ForceRecord r = JenkinsRecord(Sine, 2000, 10.5, 0.12, 0.01);
  const CycleSet set = SegmentCycles(r.x_mm);
  ASSERT_EQ(set.cycles.size(), 9u);
  EXPECT_NEAR(set.cycles[0].forward.begin, 1500, 60);  // t = 0.75 s
  EXPECT_NEAR(set.cycles[0].reverse.begin, 2500, 60);  // t = 1.25 s
  EXPECT_GT(set.leading_samples_dropped, 1400);
  EXPECT_GT(set.trailing_samples_dropped, 1400);
  EXPECT_NEAR(set.stroke_mm, 5.7, 0.1);
  for (const Cycle& c : set.cycles) {
    EXPECT_EQ(c.forward.end, c.reverse.begin);
    EXPECT_NEAR(c.reverse.end - c.forward.begin, 2000, 60);
  }
}

// The x range of the complete cycles, found once by SegmentCycles: the
// finite samples between the first cycle's start and the last's end (not
// the dropped ends, not a NaN gap); another x with the same cycles is
// passed over afresh.
TEST(SegmentCycles, KeepsTheCyclesXRangeForTheXItSegmented) {
  ForceRecord r = JenkinsRecord(Sine, 2000, 10.5, 0.12, 0.01);
  const Eigen::Index b = 1500, e = 19500;  // about the complete cycles
  r.x_mm[3000] = std::nan("");
  const CycleSet set = SegmentCycles(r.x_mm);
  double lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index i = set.cycles.front().forward.begin;
       i < set.cycles.back().reverse.end;
       ++i) {
    if (std::isfinite(r.x_mm[i]))
      lo = std::min(lo, r.x_mm[i]), hi = std::max(hi, r.x_mm[i]);
  }
  EXPECT_NEAR(set.cycles.front().forward.begin, b, 60);
  EXPECT_NEAR(set.cycles.back().reverse.end, e, 60);
  EXPECT_EQ(set.x_range_of, r.x_mm.data());
  EXPECT_EQ(CyclesXRange(r.x_mm, set), std::make_pair(lo, hi));
  EXPECT_NEAR(hi, 2.85, 0.05);
  // A copy of x with one value moved beyond the others: not the x the
  // set was segmented from, so its own range.
  Eigen::VectorXd other = r.x_mm;
  other[10000] = 7.5;
  other[0] = -9.0;  // before the first complete cycle: not counted
  EXPECT_EQ(CyclesXRange(other, set), std::make_pair(lo, 7.5));
  // An infinite x is no extent either.
  other[12001] = -INFINITY;
  other[12002] = INFINITY;
  EXPECT_EQ(CyclesXRange(other, set), std::make_pair(lo, 7.5));
}

// The robust stroke is the 1% and 99% order statistics of the finite x
// (ranks q (n - 1)), exactly: found from a sample's bracket, they are the
// values a sort of every finite x gives, with NaN gaps, x quantised to
// the LVDT's 1 um (ties at the ranks) and past 2 M samples (read every
// 2nd).
TEST(SegmentCycles, TheRobustStrokeIsTheOrderStatisticsOfX) {
  std::mt19937 gen(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (const auto& [n, quantum] : {std::pair<long, double>{6000, 0.0},
                                   {200000, 0.001},
                                   {1200000, 0.0},
                                   {2500000, 0.001}}) {
    Eigen::VectorXd x(n);
    for (long i = 0; i < n; ++i) {
      double v = 2.85 * std::sin(2 * M_PI * i / 2000.0) + 0.05 * noise(gen);
      if (i % 5000 == 17) v = 40.0 * noise(gen);  // wild samples
      if (quantum > 0) v = quantum * std::round(v / quantum);
      x[i] = i % 997 == 3 ? std::nan("") : v;
    }
    const long stride = n > (1 << 21) ? 2 : 1;
    std::vector<double> finite;
    for (long i = 0; i < n; i += stride) {
      if (std::isfinite(x[i])) finite.push_back(x[i]);
    }
    std::sort(finite.begin(), finite.end());
    const auto at = [&](double q) {
      return finite[static_cast<size_t>(q * (finite.size() - 1))];
    };
    const CycleSet set = SegmentCycles(x);
    EXPECT_EQ(set.stroke_mm, at(0.99) - at(0.01)) << n;
  }
}

TEST(SegmentCycles, TriangularDriveWithoutSpuriousReversals) {
  const ForceRecord r = JenkinsRecord(Triangle, 1000, 6.2, 0.1, 0.02);
  const CycleSet set = SegmentCycles(r.x_mm);
  ASSERT_EQ(set.cycles.size(), 5u);
  for (const Cycle& c : set.cycles)
    EXPECT_NEAR(c.reverse.end - c.forward.begin, 1000, 40);
}

TEST(SegmentCycles, FewerThanTwoCyclesIsAnError) {
  const ForceRecord r = JenkinsRecord(Sine, 500, 2.2, 0.1);
  try {
    SegmentCycles(r.x_mm, {}, "short.csv");
    FAIL();
  } catch (const ForceError& e) {
    EXPECT_NE(
        std::string(e.what()).find("short.csv: found 1 complete cycle(s)"),
        std::string::npos)
        << e.what();
  }
}

// A record growing as a follower reads it: the cycles ExtendCycles adds to
// those of the samples so far are those of the whole record, boundaries
// and gross slip to the sample; with no new cycle the known come back, and
// with cycles from another record none (segment afresh).
TEST(ExtendCycles, GivesTheWholeRecordsCyclesFromTheNewSamplesAlone) {
  for (const bool triangle : {false, true}) {
    const ForceRecord whole =
        triangle ? JenkinsRecord(Triangle, 1000, 9.3, 0.1, 0.02)
                 : JenkinsRecord(Sine, 2000, 9.3, 0.12, 0.01);
    CycleSet expected = SegmentCycles(whole.x_mm);
    FindGrossSlip(whole, &expected);
    auto first_rows = [&](Eigen::Index n) {
      ForceRecord r;
      r.time_s = whole.time_s.head(n);
      r.x_mm = whole.x_mm.head(n);
      r.tangential_n = whole.tangential_n.head(n);
      r.normal_n = whole.normal_n.head(n);
      return r;
    };
    const Eigen::Index per_cycle = whole.size() / 9;
    ForceRecord grown = first_rows(3 * per_cycle + per_cycle / 3);
    CycleSet set = SegmentCycles(grown.x_mm);
    FindGrossSlip(grown, &set);
    for (const Eigen::Index n : {4 * per_cycle,
                                 4 * per_cycle + 7,
                                 6 * per_cycle + per_cycle / 2,
                                 whole.size()}) {
      grown = first_rows(n);
      set = ExtendCycles(grown, set);
      ASSERT_FALSE(set.cycles.empty()) << n;
    }
    ASSERT_EQ(set.cycles.size(), expected.cycles.size());
    for (size_t c = 0; c < set.cycles.size(); ++c) {
      EXPECT_EQ(set.cycles[c].index, static_cast<int>(c));
      for (int d = 0; d < 2; ++d) {
        const HalfCycle& a = d ? set.cycles[c].reverse : set.cycles[c].forward;
        const HalfCycle& b =
            d ? expected.cycles[c].reverse : expected.cycles[c].forward;
        EXPECT_EQ(a.begin, b.begin) << "cycle " << c;
        EXPECT_EQ(a.end, b.end) << "cycle " << c;
        EXPECT_EQ(a.slip_begin, b.slip_begin) << "cycle " << c;
        EXPECT_EQ(a.slip_end, b.slip_end) << "cycle " << c;
      }
    }
    EXPECT_EQ(set.x_min_mm, expected.x_min_mm);
    EXPECT_EQ(set.x_max_mm, expected.x_max_mm);
    EXPECT_EQ(set.trailing_samples_dropped, expected.trailing_samples_dropped);
    // Nothing new: the known cycles.
    EXPECT_EQ(ExtendCycles(whole, set).cycles.size(), set.cycles.size());
  }
  // Cycles of another record, ending where this one has no minimum.
  const ForceRecord other = JenkinsRecord(Sine, 1000, 6.4, 0.1);
  CycleSet shifted = SegmentCycles(other.x_mm);
  shifted.cycles.resize(2);
  shifted.cycles.back().reverse.end += 150;
  EXPECT_TRUE(ExtendCycles(other, shifted).cycles.empty());
}

TEST(GrossSlip, WindowStartsWhereStickEnds) {
  // Stick lasts 2 mu P / k_t = 0.048 mm of travel after each reversal.
  const ForceRecord r = JenkinsRecord(Sine, 2000, 4.5, 0.12);
  CycleSet set = SegmentCycles(r.x_mm);
  FindGrossSlip(r, &set);
  for (const Cycle& c : set.cycles) {
    for (const HalfCycle* h : {&c.forward, &c.reverse}) {
      EXPECT_FALSE(h->slip_fallback);
      const double travel = std::abs(r.x_mm[h->slip_begin] - r.x_mm[h->begin]);
      EXPECT_GT(travel, 0.048 * 0.99);
      EXPECT_LT(travel, 0.048 + 0.03);
      // Every sample in the window slides at +-mu P.
      for (Eigen::Index i = h->slip_begin; i < h->slip_end; ++i) {
        ASSERT_NEAR(h->direction * r.tangential_n[i], 0.12 * 30, 1e-9);
      }
    }
  }
}

// A worn track whose wall near +A is steep (k = 0.3, falling off over
// 0.6 mm; mu 0.12): after the stick at that reversal Q climbs on with the
// slope, P dk/dx, as it slides. The stick still lasts about 0.05 mm; the
// 20-80% run of the climb reaches 0.4 mm into the slide, and taken as the
// stick it put the slip's start 1.1 mm from the reversal.
TEST(GrossSlip, ASteepWallAtTheStrokeEndDoesNotDelayTheSlip) {
  const double mu = 0.12, p = 30.0, rate = 2000;
  const auto k = [](double x) { return 0.3 * std::exp(-(2.85 - x) / 0.6); };
  const Eigen::Index n = static_cast<Eigen::Index>(4.5 * rate);
  ForceRecord r;
  r.time_s.resize(n);
  r.x_mm.resize(n);
  r.tangential_n.resize(n);
  r.normal_n.resize(n);
  double q = 0, xp = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = i / rate, x = Sine(t);
    // The tilted contact's sliding bounds, Q = P (k + s mu) / (1 - s mu k).
    const double upper = p * (k(x) + mu) / (1 - mu * k(x));
    const double lower = p * (k(x) - mu) / (1 + mu * k(x));
    if (i) q += 150.0 * (x - xp);
    q = std::clamp(q, lower, upper);
    xp = x;
    r.time_s[i] = t;
    r.x_mm[i] = x;
    r.tangential_n[i] = q;
    r.normal_n[i] = p;
  }
  CycleSet set = SegmentCycles(r.x_mm);
  FindGrossSlip(r, &set);
  ASSERT_GE(set.cycles.size(), 3u);
  for (const Cycle& c : set.cycles) {
    for (const HalfCycle* h : {&c.forward, &c.reverse}) {
      EXPECT_FALSE(h->slip_fallback);
      const double travel = std::abs(r.x_mm[h->slip_begin] - r.x_mm[h->begin]);
      EXPECT_LT(travel, 0.1) << "direction " << h->direction;
      // Slides from there on: Q on its sliding bound.
      const double x = r.x_mm[h->slip_begin + 5];
      const double bound = h->direction > 0 ? p * (k(x) + mu) / (1 - mu * k(x))
                                            : p * (k(x) - mu) / (1 + mu * k(x));
      EXPECT_NEAR(r.tangential_n[h->slip_begin + 5], bound, 1e-9);
    }
  }
}

TEST(ClassicCof, CoulombLoopGivesMuByMeanAndEnergyWithDeltaG) {
  const double mu = 0.12;
  const ForceRecord r = JenkinsRecord(Sine, 2000, 4.5, mu);
  CycleSet set = SegmentCycles(r.x_mm);
  FindGrossSlip(r, &set);
  const auto cof = ComputeClassicCof(r, set);
  ASSERT_EQ(cof.size(), set.cycles.size());
  for (const CycleCof& c : cof) {
    EXPECT_NEAR(c.mu_mean, mu, 1e-9);
    // E_d = 4 mu P delta_g exactly for a Jenkins loop; delta_max overshoots
    // by the stick travel: mu_Ed(delta_max) = mu (A - mu P / k_t) / A.
    EXPECT_NEAR(c.mu_energy_g, mu, 2e-4);
    EXPECT_NEAR(c.delta_g_mm, 2.85 - mu * 30 / 150, 2e-3);
    EXPECT_NEAR(c.mu_energy_max, mu * (2.85 - mu * 30 / 150) / 2.85, 2e-4);
    EXPECT_NEAR(c.q_max_n, mu * 30, 1e-9);
  }
}

TEST(ClassicCof, PRangeAndQpCorrelationTellCoulombFromWearScar) {
  // Pure Coulomb with P varying along the stroke: Q = mu P follows P.
  const ForceRecord r =
      JenkinsRecord(Sine, 2000, 4.5, 0.12, 0.0, 7, /*p_wave_n=*/0.6);
  CycleSet set = SegmentCycles(r.x_mm);
  FindGrossSlip(r, &set);
  for (const CycleCof& c : ComputeClassicCof(r, set)) {
    EXPECT_NEAR(c.p_range_n, 1.2, 0.01);
    EXPECT_GT(c.qp_correlation, 0.99);
  }
  // Wear-scar interaction: Q = P (k + s mu) / (1 - s mu k) with P = P0 - S d
  // and k = d'(x) for a track d(x) = a sin(2 pi x / L); the fluctuations of
  // Q follow the slope, a quarter wave away from P: little correlation.
  ForceRecord w = r;
  const double s_n_per_mm = 10.19, a = 0.03, len = 1.6, mu = 0.12;
  double q = 0;
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    const double x = w.x_mm[i];
    const double p = 30 - s_n_per_mm * a * std::sin(2 * M_PI * x / len);
    const double k = a * 2 * M_PI / len * std::cos(2 * M_PI * x / len);
    const double upper = p * (k + mu) / (1 - mu * k);
    const double lower = p * (k - mu) / (1 + mu * k);
    if (i) q += 150.0 * (w.x_mm[i] - w.x_mm[i - 1]);
    q = std::clamp(q, lower, upper);
    w.tangential_n[i] = q;
    w.normal_n[i] = p;
  }
  CycleSet ws = SegmentCycles(w.x_mm);
  FindGrossSlip(w, &ws);
  for (const CycleCof& c : ComputeClassicCof(w, ws)) {
    EXPECT_NEAR(c.p_range_n, 2 * s_n_per_mm * a, 0.01);
    EXPECT_LT(std::abs(c.qp_correlation), 0.35) << c.cycle;
  }
}

TEST(Slope, RecoversKnownPathSlopeFromNormalForce) {
  // P = 30 + S a sin(2 pi x / L): k = (2 pi a / L) cos(2 pi x / L).
  const double s = 10.19, a = 0.02, len = 1.6;
  const int n = 4000;
  Eigen::VectorXd x(n), p(n);
  for (int i = 0; i < n; ++i) {
    x[i] =
        2.85 * std::sin(M_PI * (i / double(n - 1) - 0.5));  // one forward half
    p[i] = 30 + s * a * std::sin(2 * M_PI * x[i] / len);
  }
  for (DerivativeMethod m : {DerivativeMethod::kMovingAverageCentral,
                             DerivativeMethod::kSavitzkyGolay}) {
    SlopeOptions o;
    o.method = m;
    o.window = m == DerivativeMethod::kSavitzkyGolay ? 21 : 10;
    o.spring_n_per_mm = s;
    const Eigen::VectorXd k = SlopeFromNormalForce(x, p, 200, n - 200, o);
    double worst = 0;
    for (int i = 200; i < n - 200; ++i) {
      const double truth = 2 * M_PI * a / len * std::cos(2 * M_PI * x[i] / len);
      worst = std::max(worst, std::abs(k[i - 200] - truth));
    }
    EXPECT_LT(worst, 2e-3) << DerivativeMethodName(m);
  }
}

TEST(Slope, SavitzkyGolayWindowShiftsInwardAtTheSignalEndsOnRequest) {
  // A quadratic f = 0.3 x^2 - 0.1 x on uneven x: its slope 0.6 x - 0.1 is
  // exact for an order-2 window, at the first and last samples too, where
  // the window cannot be centred.
  const int n = 40;
  Eigen::VectorXd x(n), f(n);
  for (int i = 0; i < n; ++i) {
    x[i] = 0.05 * i + 0.01 * std::sin(1.7 * i);
    f[i] = 0.3 * x[i] * x[i] - 0.1 * x[i];
  }
  SlopeOptions o;
  o.method = DerivativeMethod::kSavitzkyGolay;
  o.window = 9;
  o.min_span_mm = 0;
  // By default the ends, where the window cannot be centred, are NaN.
  const Eigen::VectorXd centred = DerivativeAlongX(x, f, 0, n, o);
  EXPECT_TRUE(std::isnan(centred[0]));
  EXPECT_TRUE(std::isnan(centred[n - 1]));
  EXPECT_NEAR(centred[20], 0.6 * x[20] - 0.1, 1e-9);
  o.shift_window_at_ends = true;
  const Eigen::VectorXd k = DerivativeAlongX(x, f, 0, n, o);
  for (int i : {0, 1, 3, 4, 20, n - 4, n - 1}) {
    EXPECT_NEAR(k[i], 0.6 * x[i] - 0.1, 1e-9) << i;
  }
  // Shorter than one window: nothing can be fitted.
  const Eigen::VectorXd few = DerivativeAlongX(x.head(8), f.head(8), 0, 8, o);
  EXPECT_TRUE(few.array().isNaN().all());
}

TEST(Slope, MovingAverageMatchesDefinition) {
  Eigen::VectorXd v(6);
  v << 1, 2, 3, 4, 5, 100;
  const Eigen::VectorXd m = MovingAverage(v, 3);
  EXPECT_DOUBLE_EQ(m[0], 1.5);
  EXPECT_DOUBLE_EQ(m[2], 3.0);
  EXPECT_DOUBLE_EQ(m[5], 52.5);
}

}  // namespace
}  // namespace wearscar::force

namespace wearscar::force {
namespace {

TEST(Slope, SpansInTimeAreThePapersSamplesAt2kHzAndScaleWithTheRate) {
  const SlopeOptions o;  // 5 ms smoothing, +-0.5 ms difference
  const SlopeOptions at2k = o.ForSamplingRate(2000);
  EXPECT_EQ(at2k.window, 10);
  EXPECT_EQ(at2k.half_width, 1);
  const SlopeOptions at10k = o.ForSamplingRate(10000);
  EXPECT_EQ(at10k.window, 50);
  EXPECT_EQ(at10k.half_width, 5);
  const SlopeOptions at100 = o.ForSamplingRate(100);
  EXPECT_EQ(at100.window, 1);  // never below one sample
  EXPECT_EQ(at100.half_width, 1);
  // Given in samples, they stay.
  SlopeOptions given;
  given.window = 7;
  given.half_width = 2;
  EXPECT_EQ(given.ForSamplingRate(10000).window, 7);
  EXPECT_EQ(given.ForSamplingRate(10000).half_width, 2);
  // Savitzky-Golay windows are odd.
  SlopeOptions sg;
  sg.method = DerivativeMethod::kSavitzkyGolay;
  EXPECT_EQ(sg.ForSamplingRate(2000).window, 11);
  EXPECT_NE(at2k.Describe().find("moving average 10 samples"),
            std::string::npos);
}

TEST(Slope, TheSameStretchOfStrokeAtFiveTimesTheRate) {
  // A sine drive over a wavy path, P = S f(x) + white noise of the same sd
  // per sample at 2 kHz and 10 kHz. Spans in samples (the paper's 10 and 1)
  // leave five times less x per stencil at 10 kHz and a noisier slope;
  // spans in time keep the stretch, and the slope's error falls.
  const double spring = 10.19;
  auto path = [](double x) { return 0.02 * std::sin(2 * M_PI * x / 1.6); };
  auto slope = [](double x) {
    return 0.02 * 2 * M_PI / 1.6 * std::cos(2 * M_PI * x / 1.6);
  };
  auto rms_error = [&](double rate, const SlopeOptions& o) {
    const int n = static_cast<int>(rate);  // one period
    Eigen::VectorXd x(n), p(n);
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.02);
    for (int i = 0; i < n; ++i) {
      x[i] = 2.85 * std::sin(2 * M_PI * i / rate - M_PI / 2);  // -A .. A
      p[i] = 30 + spring * path(x[i]) + noise(rng);
    }
    const SlopeOptions r = o.ForSamplingRate(rate);
    const Eigen::Index b = n / 10, e = n / 2 - n / 10;  // mid-stroke, up
    const Eigen::VectorXd k = SlopeFromNormalForce(x, p, b, e, r);
    double s = 0;
    for (Eigen::Index i = b; i < e; ++i)
      s += std::pow(k[i - b] - slope(x[i]), 2);
    return std::sqrt(s / (e - b));
  };
  SlopeOptions in_time;
  SlopeOptions in_samples;
  in_samples.window = 10;
  in_samples.half_width = 1;
  const double t2 = rms_error(2000, in_time);
  const double t10 = rms_error(10000, in_time);
  const double s10 = rms_error(10000, in_samples);
  EXPECT_NEAR(rms_error(2000, in_samples), t2, 1e-12);  // the same at 2 kHz
  EXPECT_LT(t10, 0.6 * t2);
  EXPECT_LT(t10, 0.2 * s10);
}

}  // namespace
}  // namespace wearscar::force
