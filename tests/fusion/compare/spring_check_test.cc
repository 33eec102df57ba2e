// The spring check on track histories built by hand: P/S and the
// friction's path of every cycle, the groove grown from nothing, half of it
// there at the start, or all of it there from the first cycle, with and
// without an elastic part and with springs of other stiffnesses.

#include "wearscar/fusion/spring_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace wearscar::fusion {
namespace {

struct Rig {
  double stiffness_ratio = 1.0;  // the rig's over the one used
  double elastic = 0.0;          // the elastic part's scale
  double groove_at_start = 0.0;  // 1: all of it there from the first cycle
  double noise_mm = 0.0003;
};

double Worn(double x) {
  return 0.02 * std::sin(2 * M_PI * x / 1.6) - 0.01 * x * x;
}
// Deeper where the wood is softer, as the wear is, but of its own shape
// (the wood's stiffness, not its wear): r = 0.8 with the worn track's rings.
double Elastic(double x) {
  return 0.02 * (0.8 * std::sin(2 * M_PI * x / 1.6) +
                 0.6 * std::cos(2 * M_PI * x / 0.7));
}

// P/S = ratio (g(c) worn + elastic) + noise; the friction's path g(c) worn
// + noise + a line (an offset in Q, integrated), g rising from
// groove_at_start to 1 with a time constant of 40 cycles.
TrackHistory History(int cycles, const Rig& rig) {
  TrackHistory h;
  const int bins = 57;
  for (int b = 0; b < bins; ++b) h.x_mm.push_back(-2.8 + 0.1 * b);
  h.cycles = cycles;
  h.height_mm.assign(static_cast<size_t>(cycles) * 2 * bins, NAN);
  h.friction_height_mm.assign(static_cast<size_t>(cycles) * bins, NAN);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, rig.noise_mm);
  auto growth = [&](int c) {
    const double g = 1 - std::exp(-(c + 1) / 40.0);
    const double last = 1 - std::exp(-cycles / 40.0);
    return rig.groove_at_start + (1 - rig.groove_at_start) * g / last;
  };
  for (int c = 0; c < cycles; ++c) {
    const double offset = 0.002 * n(rng) / rig.noise_mm;
    for (int b = 0; b < bins; ++b) {
      const double x = h.x_mm[b];
      const double path = growth(c) * Worn(x);
      for (int d = 0; d < 2; ++d) {
        h.height_mm[h.Index(c, d, b)] =
            rig.stiffness_ratio * (path + rig.elastic * Elastic(x)) + n(rng);
      }
      // The two directions slid over the middle of the stroke only.
      if (b > 2 && b < bins - 3)
        h.friction_height_mm[h.FrictionIndex(c, b)] =
            path + n(rng) + offset * x;
    }
  }
  return h;
}

SpringCheck Check(const Rig& rig, int cycles = 200) {
  return CheckSpring(
      History(cycles, rig), 0, cycles - 50, cycles - 1, 10.0, {});
}

TEST(SpringCheck, AGrooveGrownFromNothingWithTheRightSpringAgrees) {
  const SpringCheck c = Check(Rig{});
  ASSERT_TRUE(c.judged);
  EXPECT_TRUE(c.changing_groove.Held()) << c.changing_groove.evidence;
  EXPECT_NEAR(c.stiffness_ratio, 1.0, 0.03);
  EXPECT_NEAR(c.elastic_share, 0.0, 0.03);
  EXPECT_FALSE(c.contradicted);
  EXPECT_FALSE(c.elastic);
  EXPECT_FALSE(c.undecided);
}

// The share is the elastic part's projection on the compared cycles' P/S
// profile over the worn track's at the end (the last tenth of the
// cycles): computed here from the noise-free parts.
TEST(SpringCheck, AnElasticPartThatDoesNotFollowTheGrowthIsItsShare) {
  const Rig rig{1.0, 0.5, 0.0, 0.0003};
  const TrackHistory quiet = History(200, Rig{1.0, 0.5, 0.0, 0.0});
  const TrackHistory worn = History(200, Rig{1.0, 0.0, 0.0, 0.0});
  const size_t bins = quiet.x_mm.size();
  std::vector<double> w(bins), e(bins), end(bins);
  for (size_t b = 0; b < bins; ++b) {
    for (int c = 150; c < 200; ++c)
      w[b] += quiet.height_mm[quiet.Index(c, 0, b)] / 50;
    for (int c = 180; c < 200; ++c)
      end[b] += worn.height_mm[worn.Index(c, 0, b)] / 20;
    e[b] = 0.5 * Elastic(quiet.x_mm[b]);
  }
  // Each less its line in x, over the bins the friction's path holds.
  auto detrend = [&](std::vector<double> v) {
    double mx = 0, mv = 0, sxx = 0, sxv = 0;
    int n = 0;
    for (size_t b = 3; b < bins - 3; ++b) mx += worn.x_mm[b], mv += v[b], ++n;
    mx /= n, mv /= n;
    for (size_t b = 3; b < bins - 3; ++b) {
      sxx += std::pow(worn.x_mm[b] - mx, 2);
      sxv += (worn.x_mm[b] - mx) * (v[b] - mv);
    }
    for (size_t b = 3; b < bins - 3; ++b)
      v[b] -= mv + sxv / sxx * (worn.x_mm[b] - mx);
    return v;
  };
  const std::vector<double> dw = detrend(w), de = detrend(e),
                            dend = detrend(end);
  double ew = 0, endw = 0;
  for (size_t b = 3; b < bins - 3; ++b)
    ew += de[b] * dw[b], endw += dend[b] * dw[b];
  const SpringCheck c = Check(rig);
  ASSERT_TRUE(c.judged);
  EXPECT_TRUE(c.changing_groove.Held());
  EXPECT_GT(ew / endw, 0.15);
  EXPECT_NEAR(c.elastic_share, ew / endw, 0.03);
  EXPECT_NEAR(c.stiffness_ratio, 1.0, 0.05);
  EXPECT_TRUE(c.elastic);
  EXPECT_FALSE(c.contradicted);
  EXPECT_NE(c.DescribeElastic("the spring displacement")
                .find("the spring displacement carries an elastic part"),
            std::string::npos);
}

// P/S 2.5x the path grown from nothing: the stiffness 2.5x the one used,
// with the elastic part beside it split off; 0.5x likewise.
TEST(SpringCheck, AScaleOfAGrowingGrooveIsTheStiffness) {
  for (const double ratio : {2.5, 0.5}) {
    const SpringCheck c = Check(Rig{ratio, 0.0, 0.0, 0.0003});
    EXPECT_TRUE(c.contradicted) << ratio;
    EXPECT_NEAR(c.ImpliedStiffness(), 10 * ratio, 0.3 * ratio) << ratio;
    EXPECT_FALSE(c.elastic) << ratio;
    EXPECT_NE(c.Describe("given").find("not the 10 N/mm given"),
              std::string::npos)
        << c.Describe("given");
    // The growth decided it: a value, not a bound.
    EXPECT_FALSE(c.UpperBoundOnly()) << ratio;
    EXPECT_EQ(c.Describe("given").find("at most"), std::string::npos);
    EXPECT_EQ(c.Describe("given").find("cannot tell"), std::string::npos);
  }
  const SpringCheck e = Check(Rig{2.0, 0.5, 0.0, 0.0003});
  EXPECT_TRUE(e.contradicted);
  EXPECT_TRUE(e.elastic);
  EXPECT_NEAR(e.stiffness_ratio, 2.0, 0.1);
}

// Half of the groove there at the start still grows enough to split.
TEST(SpringCheck, HalfAGrooveAtTheStartStillSplits) {
  const SpringCheck c = Check(Rig{1.0, 0.0, 0.5, 0.0003});
  EXPECT_TRUE(c.changing_groove.Held()) << c.changing_groove.evidence;
  EXPECT_NEAR(c.stiffness_ratio, 1.0, 0.05);
  EXPECT_FALSE(c.contradicted);
  EXPECT_FALSE(c.elastic) << c.elastic_share;
  const SpringCheck s = Check(Rig{2.5, 0.0, 0.5, 0.0003});
  EXPECT_TRUE(s.contradicted);
  EXPECT_NEAR(s.ImpliedStiffness(), 25, 2.5);
}

// All of the groove there from the first cycle (a pre-worn specimen, a
// resumed test): no growth to split on. P/S equal to the path agrees;
// below it is a stiffness (at most); above it a stiffness and an elastic
// part cannot be told apart, and never is the whole of P/S called elastic
// nor the spring 0 N/mm.
TEST(SpringCheck, AGrooveThereFromTheStartIsJudgedOnItsRatioAlone) {
  const SpringCheck same = Check(Rig{1.0, 0.0, 1.0, 0.0003});
  ASSERT_TRUE(same.judged);
  EXPECT_TRUE(same.changing_groove.Failed());
  EXPECT_NE(same.changing_groove.evidence.find("its noise"), std::string::npos);
  EXPECT_NEAR(same.path_ratio, 1.0, 0.02);
  EXPECT_FALSE(same.contradicted);
  EXPECT_FALSE(same.elastic);
  EXPECT_FALSE(same.undecided);
  EXPECT_TRUE(std::isnan(same.elastic_share));

  const SpringCheck soft = Check(Rig{0.5, 0.0, 1.0, 0.0003});
  EXPECT_TRUE(soft.contradicted);
  EXPECT_NEAR(soft.ImpliedStiffness(), 5.0, 0.2);
  // Only bounded: an elastic part, which the unchanging groove cannot
  // split off, would lower the stiffness further; said as such.
  EXPECT_TRUE(soft.UpperBoundOnly());
  EXPECT_NE(soft.Describe("assumed").find("at most 5"), std::string::npos)
      << soft.Describe("assumed");
  EXPECT_NE(soft.Describe("assumed").find(
                "cannot tell a spring of 5 N/mm from a softer one"),
            std::string::npos)
      << soft.Describe("assumed");

  for (const Rig& r :
       {Rig{2.5, 0.0, 1.0, 0.0003}, Rig{1.0, 0.5, 1.0, 0.0003}}) {
    const SpringCheck c = Check(r);
    EXPECT_TRUE(c.undecided);
    EXPECT_FALSE(c.contradicted);
    EXPECT_FALSE(c.elastic);
    EXPECT_GT(c.ImpliedStiffness(), 12.0);
    EXPECT_EQ(c.DescribeUndecided("given").rfind("cannot tell a spring of", 0),
              0u)
        << c.DescribeUndecided("given");
  }
}

TEST(SpringCheck, TooFewCyclesOrNoSharedShapeAreNotJudged) {
  EXPECT_FALSE(Check(Rig{}, 5).judged);
  TrackHistory h = History(100, Rig{});
  for (double& f : h.friction_height_mm) f = std::isfinite(f) ? 0.0 : f;
  const SpringCheck c = CheckSpring(h, 0, 50, 99, 10.0, {});
  EXPECT_FALSE(c.judged);
  EXPECT_FALSE(c.contradicted);
  std::string why;
  SpringCheckOptions o;
  o.max_split_width = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("max_split_width"), std::string::npos);
}

}  // namespace
}  // namespace wearscar::fusion
