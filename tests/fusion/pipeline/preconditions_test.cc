// Preconditions of the public entry points (wearscar/support/check.h): a
// caller's broken invariant aborts with the condition named in debug and
// sanitizer builds; release builds compile the checks out.
#include <gtest/gtest.h>

#include "wearscar/fusion/fit_mu.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/scan/level.h"

namespace wearscar {
namespace {

#if defined(WEARSCAR_CHECKS) || !defined(NDEBUG)
constexpr bool kChecksOn = true;
#else
constexpr bool kChecksOn = false;
#endif

TEST(Preconditions, ChannelsOfDifferentLengthsAreACallersBug) {
  if (!kChecksOn) GTEST_SKIP() << "checks are compiled out of release builds";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  force::ForceRecord r;
  r.time_s = Eigen::VectorXd::LinSpaced(100, 0, 1);
  r.x_mm = Eigen::VectorXd::Zero(100);
  r.tangential_n = Eigen::VectorXd::Zero(99);  // one short
  r.normal_n = Eigen::VectorXd::Zero(100);
  EXPECT_FALSE(r.IsConsistent());
  EXPECT_DEATH(fusion::AnalyzeTest(r, std::nullopt),
               "precondition failed: record.IsConsistent\\(\\)");
}

TEST(Preconditions, AMapWhoseMaskDisagreesIsACallersBug) {
  if (!kChecksOn) GTEST_SKIP() << "checks are compiled out of release builds";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  scan::HeightMap m;
  m.height_mm.setZero(8, 8);
  m.valid.setOnes(8, 7);
  m.dx_mm = m.dy_mm = 0.01;
  EXPECT_FALSE(m.IsConsistent());
  EXPECT_DEATH(scan::LevelHeightMap(&m), "precondition failed");
}

TEST(Preconditions, SamplesOfDifferentLengthsAreACallersBug) {
  if (!kChecksOn) GTEST_SKIP() << "checks are compiled out of release builds";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  fusion::CycleSamples s;
  s.forward.q_n = Eigen::VectorXd::Ones(10);
  s.forward.p_n = Eigen::VectorXd::Ones(10);
  s.forward.k = Eigen::VectorXd::Zero(9);
  EXPECT_DEATH(fusion::FitMu(s), "FitMu needs q, p and k");
}

// What the checks guard is also what the readers guarantee: consistent
// data passes them (and the result is right).
TEST(Preconditions, ConsistentDataPasses) {
  scan::HeightMap m;
  m.height_mm.setZero(32, 48);
  for (int r = 0; r < 32; ++r)
    for (int c = 0; c < 48; ++c) m.height_mm(r, c) = 0.001f * c;
  m.dx_mm = m.dy_mm = 0.01;
  scan::SyncValidity(&m);
  ASSERT_TRUE(m.IsConsistent());
  const scan::LevelSummary l = scan::LevelHeightMap(&m);
  EXPECT_NEAR(l.dzdx(), 0.1, 1e-6);  // 0.001 mm per 0.01 mm pixel
}

}  // namespace
}  // namespace wearscar
