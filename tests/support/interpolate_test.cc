#include "wearscar/support/interpolate.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wearscar::support {
namespace {

TEST(InterpolateAtIndex, ExactOnSamplesLinearBetween) {
  Eigen::VectorXd v(4);
  v << 1.0, 3.0, std::nan(""), 10.0;
  EXPECT_EQ(InterpolateAtIndex(v, 0.0), 1.0);
  EXPECT_EQ(InterpolateAtIndex(v, 1.0), 3.0);  // whatever its neighbour holds
  EXPECT_DOUBLE_EQ(InterpolateAtIndex(v, 0.25), 1.5);
  EXPECT_TRUE(std::isnan(InterpolateAtIndex(v, 1.5)));
  EXPECT_EQ(InterpolateAtIndex(v, 3.0), 10.0);  // the last sample
}

// Outside the samples the nearest pair's line goes on (the caller decides
// what to do there).
TEST(InterpolateAtIndex, OutsideTheSamplesExtendsTheEndSegments) {
  Eigen::VectorXd v(3);
  v << 0.0, 2.0, 3.0;
  EXPECT_DOUBLE_EQ(InterpolateAtIndex(v, -0.5), -1.0);
  EXPECT_DOUBLE_EQ(InterpolateAtIndex(v, 2.5), 3.5);
}

}  // namespace
}  // namespace wearscar::support
