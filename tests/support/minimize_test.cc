#include "wearscar/support/minimize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "wearscar/support/student_t.h"

namespace wearscar::support {
namespace {

// Brent's method finds a smooth minimum to its tolerance, where a grid of
// 11 points alone is 0.1 away, in a few evaluations.
TEST(MinimizeOnInterval, FindsASmoothMinimumToItsTolerance) {
  int calls = 0;
  const auto f = [&](double x) {
    ++calls;
    return std::cosh(x - 0.3137) + 0.5;
  };
  const ScalarMinimum m = MinimizeOnInterval(f, -1.0, 1.0, 11, 1e-9, 100);
  ASSERT_TRUE(m.found);
  EXPECT_TRUE(m.converged);
  EXPECT_NEAR(m.x, 0.3137, 1e-7);
  EXPECT_NEAR(m.value, 1.5, 1e-12);
  EXPECT_LT(m.iterations, 30);
  EXPECT_EQ(calls, 11 + m.iterations);
}

// A minimum at the interval's end is found there; a function infinite
// everywhere is "not found", never a silent zero.
TEST(MinimizeOnInterval, AnEndpointMinimumAndAnInfiniteFunction) {
  const ScalarMinimum end =
      MinimizeOnInterval([](double x) { return x; }, 2.0, 3.0, 5, 1e-8, 100);
  ASSERT_TRUE(end.found);
  EXPECT_NEAR(end.x, 2.0, 1e-6);
  const ScalarMinimum none = MinimizeOnInterval(
      [](double) { return std::numeric_limits<double>::infinity(); },
      0.0,
      1.0,
      5,
      1e-8,
      100);
  EXPECT_FALSE(none.found);
  EXPECT_FALSE(none.converged);
}

// The two-sided 95% quantiles of Student's t at tabulated degrees of
// freedom; 1.96 beyond 30, NaN below 1.
TEST(StudentT975, TabulatedQuantiles) {
  EXPECT_DOUBLE_EQ(StudentT975(1), 12.706);
  EXPECT_DOUBLE_EQ(StudentT975(10), 2.228);
  EXPECT_DOUBLE_EQ(StudentT975(30), 2.042);
  EXPECT_DOUBLE_EQ(StudentT975(31), 1.96);
  EXPECT_TRUE(std::isnan(StudentT975(0)));
}

}  // namespace
}  // namespace wearscar::support
