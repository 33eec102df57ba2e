// The spring check on track histories built by hand: a worn profile that
// grows from nothing, with and without an elastic part that is there from
// the first cycle, against a scan whose amplitude ratio is given.

#include "wearscar/fusion/spring_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace wearscar::fusion {
namespace {

// h(x, c) = growth(c) * worn(x) + elastic * worn2(x) + noise, where worn2
// follows worn at r = 0.8 (the wood's stiffness, not its wear), growth
// rising as 1 - exp(-c / 40) over `cycles`.
TrackHistory History(int cycles, double elastic, double noise_mm) {
  TrackHistory h;
  const int bins = 57;
  for (int b = 0; b < bins; ++b) h.x_mm.push_back(-2.8 + 0.1 * b);
  h.cycles = cycles;
  h.height_mm.assign(static_cast<size_t>(cycles) * 2 * bins, NAN);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, noise_mm);
  auto growth = [&](int c) { return 1 - std::exp(-(c + 1) / 40.0); };
  for (int c = 0; c < cycles; ++c) {
    for (int d = 0; d < 2; ++d) {
      for (int b = 0; b < bins; ++b) {
        const double x = h.x_mm[b];
        const double worn = 0.02 * std::sin(2 * M_PI * x / 1.6) - 0.01 * x * x;
        const double stiff = 0.02 * (0.8 * std::sin(2 * M_PI * x / 1.6) +
                                     0.6 * std::cos(2 * M_PI * x / 0.7));
        h.height_mm[h.Index(c, d, b)] =
            growth(c) / growth(cycles - 1) * worn + elastic * stiff + n(rng);
      }
    }
  }
  return h;
}

Alignment Ratio(double ratio) {
  Alignment a;
  a.amplitude_ratio = ratio;
  a.amplitude_ratio_low = ratio * 0.99;
  a.amplitude_ratio_high = ratio * 1.01;
  return a;
}

TEST(SpringCheck, AWornTrackGrownFromNothingHasNoElasticShare) {
  const TrackHistory h = History(200, 0.0, 0.0005);
  SpringCheck c;
  EstimateElasticShare(h, 150, 199, SpringCheckOptions(), &c);
  ASSERT_TRUE(c.judged);
  EXPECT_NEAR(c.elastic_share, 0.0, 0.02);
  EXPECT_FALSE(c.elastic);
}

// The share is the elastic part's projection on the compared cycles'
// profile: computed here from the noise-free parts.
TEST(SpringCheck, AnElasticPartThereFromTheFirstCycleIsItsShare) {
  const TrackHistory h = History(200, 0.5, 0.0005);
  const TrackHistory worn = History(200, 0.0, 0.0);
  const TrackHistory elastic_only = History(1, 0.5, 0.0);
  double ew = 0, ww = 0, me = 0, mw = 0;
  const size_t bins = h.x_mm.size();
  std::vector<double> w(bins), e(bins);
  for (size_t b = 0; b < bins; ++b) {
    // The compared cycles' mean profile (150-199, both directions alike).
    for (int c = 150; c < 200; ++c) w[b] += worn.height_mm[worn.Index(c, 0, b)];
    e[b] = elastic_only.height_mm[elastic_only.Index(0, 0, b)] -
           History(1, 0.0, 0.0).height_mm[b];
    w[b] = w[b] / 50 + e[b];
    me += e[b] / bins, mw += w[b] / bins;
  }
  for (size_t b = 0; b < bins; ++b) {
    ew += (e[b] - me) * (w[b] - mw);
    ww += (w[b] - mw) * (w[b] - mw);
  }
  SpringCheck c;
  EstimateElasticShare(h, 150, 199, SpringCheckOptions(), &c);
  ASSERT_TRUE(c.judged);
  EXPECT_NEAR(c.elastic_share, ew / ww, 0.02);
  EXPECT_GT(ew / ww, 0.1);
  EXPECT_TRUE(c.elastic);
}

// P/S 2.5x the scanned track with no elastic part: the stiffness 2.5x the
// one used, contradicted; the same history at the ratio 1.05 is not, nor
// is a ratio the elastic share explains.
TEST(SpringCheck, AScaleWithoutAnElasticPartIsTheStiffness) {
  const TrackHistory h = History(200, 0.0, 0.0005);
  const Alignment wrong = Ratio(2.5);
  const SpringCheck c = CheckSpring(h, &wrong, 150, 199, 10.0, {});
  EXPECT_TRUE(c.contradicted);
  EXPECT_NEAR(c.ImpliedStiffness(), 25.0 / c.growth, 0.5);
  EXPECT_NE(c.Describe("given").find("not the 10 N/mm given"),
            std::string::npos)
      << c.Describe("given");
  const Alignment right = Ratio(1.05);
  EXPECT_FALSE(CheckSpring(h, &right, 150, 199, 10.0, {}).contradicted);
  const Alignment soft = Ratio(0.5);
  EXPECT_TRUE(CheckSpring(h, &soft, 150, 199, 10.0, {}).contradicted);
  EXPECT_FALSE(CheckSpring(h, nullptr, 150, 199, 10.0, {}).contradicted);
}

TEST(SpringCheck, TooFewCyclesAreNotJudged) {
  SpringCheck c;
  EstimateElasticShare(History(4, 0.0, 0.0005), 0, 3, {}, &c);
  EXPECT_FALSE(c.judged);
  std::string why;
  SpringCheckOptions o;
  o.early_cycles = 2;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("early_cycles"), std::string::npos);
}

}  // namespace
}  // namespace wearscar::fusion
