#include "wearscar/support/numbers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wearscar::support {
namespace {

TEST(Numbers, NaNIsMissingInfIsBeyondEveryNumberPiIsTheDoubleNearestPi) {
  EXPECT_TRUE(std::isnan(kNaN));
  EXPECT_FALSE(kNaN == kNaN);
  EXPECT_TRUE(std::isinf(kInf) && kInf > 0);
  EXPECT_GT(kInf, std::numeric_limits<double>::max());
  EXPECT_EQ(kPi, std::acos(-1.0));
  EXPECT_NEAR(std::sin(kPi), 0.0, 2e-16);
}

}  // namespace
}  // namespace wearscar::support
