#include "wearscar/support/robust_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace wearscar::support {
namespace {

// The order statistic at floor(q (n - 1)): 0..999 shuffled gives rank
// 1 for q = 0.002 and 997 for q = 0.998.
TEST(Percentile, IsTheOrderStatisticAtFloorQTimesNMinusOne) {
  std::vector<double> v(1000);
  for (int i = 0; i < 1000; ++i) v[i] = i;
  std::shuffle(v.begin(), v.end(), std::mt19937(7));
  EXPECT_EQ(Percentile(v, 0.002), 1.0);
  EXPECT_EQ(Percentile(v, 0.998), 997.0);
  EXPECT_EQ(Percentile(v, 0.0), 0.0);
  EXPECT_EQ(Percentile(v, 1.0), 999.0);
  EXPECT_EQ(Percentile({}, 0.5), 0.0);
}

// Both quantiles from one copy are the two separate selections' values;
// equal quantiles give one value twice.
TEST(Percentiles, BothQuantilesFromOneCopyAreTheOrderStatistics) {
  std::vector<double> v(1000);
  for (int i = 0; i < 1000; ++i) v[i] = i % 37 == 0 ? 5.0 : i;  // ties
  std::shuffle(v.begin(), v.end(), std::mt19937(7));
  for (auto [a, b] : {std::pair{0.002, 0.998}, {0.1, 0.9}, {0.5, 0.5}}) {
    const auto [lo, hi] = Percentiles(v, a, b);
    EXPECT_EQ(lo, Percentile(v, a));
    EXPECT_EQ(hi, Percentile(v, b));
  }
  EXPECT_EQ(Percentiles({}, 0.1, 0.9), std::make_pair(0.0, 0.0));
}

}  // namespace
}  // namespace wearscar::support
