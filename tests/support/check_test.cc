#include "wearscar/support/check.h"

#include <gtest/gtest.h>

namespace wearscar::support {
namespace {

// With checks on (debug and sanitizer builds) a broken precondition aborts
// naming the file, the condition and the message; in release builds the
// condition is not even evaluated.
TEST(Check, AbortsWithTheConditionWhenChecksAreOnElseCostsNothing) {
  int evaluated = 0;
  WEARSCAR_CHECK(++evaluated > 0, "holds");
#if defined(WEARSCAR_CHECKS) || !defined(NDEBUG)
  EXPECT_EQ(evaluated, 1);
  EXPECT_DEATH(WEARSCAR_CHECK(evaluated == 2, "two channels of one length"),
               "check_test.cc:[0-9]+: precondition failed: evaluated == 2 "
               "\\(two channels of one length\\)");
#else
  EXPECT_EQ(evaluated, 0);
  WEARSCAR_CHECK(evaluated == 2, "not evaluated, no abort");
#endif
}

}  // namespace
}  // namespace wearscar::support
