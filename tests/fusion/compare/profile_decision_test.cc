#include "wearscar/fusion/profile_decision.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "wearscar/fusion/error.h"

namespace wearscar::fusion {
namespace {

// Figures given, and which of them the decision asked for.
struct FakeEvidence : ProfileEvidence {
  bool depth = false, scan = false, fitted = true;
  double significance = 20, spring_depth = NAN, depth_friction = NAN,
         ratio = NAN, path_ratio = NAN;
  std::set<std::string> asked;

  bool HasDepthChannel() const override { return depth; }
  std::string DepthColumn() const override { return "Penetration Depth"; }
  bool DepthIsPenetration() const override { return true; }
  bool HasScan() const override { return scan; }
  bool ForceSlopeFitted() const override { return fitted; }
  double PSlopeSignificance() override {
    asked.insert("significance");
    return significance;
  }
  int FittedCycles() override { return 200; }
  int CorrelatedCycles() override { return 5; }
  double SpringDepthAgreement() override {
    asked.insert("spring-depth");
    return spring_depth;
  }
  double DepthAgreement() override {
    asked.insert("depth-friction");
    return depth_friction;
  }
  double SpringPathRatio() override {
    asked.insert("path ratio");
    return path_ratio;
  }
  double SpringAmplitudeRatio() override {
    asked.insert("ratio");
    return ratio;
  }
};

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A spring rig whose P varies: P/S, and nothing else is computed (no
// alignment with the scan for the decision, no depth profile).
TEST(DecideProfile, ASpringWhosePVariesAsksForNothingElse) {
  FakeEvidence e;
  e.scan = true;
  const ProfileDecision d = DecideProfile(&e, FuseOptions{});
  EXPECT_EQ(d.used, ProfileSource::kSpring);
  EXPECT_EQ(d.given, ProfileSource::kAuto);
  EXPECT_EQ(e.asked, std::set<std::string>{"significance"});
  EXPECT_EQ(d.p_slope_significance, 20);
  EXPECT_TRUE(std::isnan(d.spring_amplitude_ratio));
  EXPECT_TRUE(Has(d.reason,
                  "profile from the spring, P/S: P's repeatable "
                  "slope is 20.0 standard errors"))
      << d.reason;
  EXPECT_EQ(d.SlopeName(), "k from P");
}

// P insignificant and P/S far flatter than the scanned track: the
// friction's profile; flatter by less than dead_weight_ratio only.
TEST(DecideProfile, ADeadWeightWithAScanTakesTheFriction) {
  FakeEvidence e;
  e.scan = true;
  e.significance = 1.2;
  e.ratio = 0.1;
  const ProfileDecision d = DecideProfile(&e, FuseOptions{});
  EXPECT_EQ(d.used, ProfileSource::kFriction);
  EXPECT_EQ(d.spring_amplitude_ratio, 0.1);
  EXPECT_TRUE(Has(d.reason,
                  "P/S varies 0.10x the scanned profile (below "
                  "0.20): a dead-weight"))
      << d.reason;
  EXPECT_FALSE(d.ForceSlopeJudged());
  e.ratio = 0.5;
  EXPECT_EQ(DecideProfile(&e, FuseOptions{}).used, ProfileSource::kSpring);
  // The thresholds are the options': P at 5 standard errors is noise when
  // 10 are asked for.
  e.ratio = 0.1;
  e.significance = 5;
  FuseOptions o;
  EXPECT_EQ(DecideProfile(&e, o).used, ProfileSource::kSpring);
  o.dead_weight_significance = 10;
  EXPECT_EQ(DecideProfile(&e, o).used, ProfileSource::kFriction);
}

// Where the friction shows the path, P/S is judged against it, not
// against the scan (whose ratio rests on its alignment): a spring rig on a
// faint track keeps its spring whatever a scan of another specimen says,
// and a dead weight is told by P/S against the friction's path alone.
TEST(DecideProfile, TheFrictionsPathDecidesADeadWeightBeforeTheScan) {
  FakeEvidence e;
  e.scan = true;
  e.significance = 2.3;
  e.ratio = 0.08;  // a misaligned scan
  e.path_ratio = 1.02;
  ProfileDecision d = DecideProfile(&e, FuseOptions{});
  EXPECT_EQ(d.used, ProfileSource::kSpring);
  EXPECT_EQ(d.spring_amplitude_ratio, 1.02);
  EXPECT_TRUE(d.ratio_against_friction);
  EXPECT_EQ(e.asked.count("ratio"), 0u);
  e.path_ratio = 0.03;
  d = DecideProfile(&e, FuseOptions{});
  EXPECT_EQ(d.used, ProfileSource::kFriction);
  EXPECT_TRUE(Has(d.reason,
                  "P/S varies 0.03x the path the friction shows (below "
                  "0.20): a dead-weight"))
      << d.reason;
}

// A depth channel: taken when P is noise, or when P varies but not with
// the depth (Q's crosstalk); turned over when it runs against the
// friction's profile.
TEST(DecideProfile, ADepthChannelWhenPIsNotTheTrack) {
  FakeEvidence e;
  e.depth = true;
  e.significance = 0.8;
  e.depth_friction = -0.9;
  ProfileDecision d = DecideProfile(&e, FuseOptions{});
  EXPECT_EQ(d.used, ProfileSource::kDepth);
  EXPECT_EQ(d.depth_sign, -1.0);
  EXPECT_EQ(d.depth_column, "Penetration Depth");
  EXPECT_FALSE(e.asked.count("spring-depth"));
  EXPECT_TRUE(Has(d.reason, "it runs the other way, so it was turned over"))
      << d.reason;
  EXPECT_EQ(d.SlopeName(), "k from the depth");

  e.significance = 30;
  e.depth_friction = 0.95;
  e.spring_depth = 0.2;
  d = DecideProfile(&e, FuseOptions{});
  EXPECT_EQ(d.used, ProfileSource::kDepth);
  EXPECT_EQ(d.depth_sign, 1.0);
  EXPECT_TRUE(Has(d.reason, "P's variation is not the track's")) << d.reason;

  e.spring_depth = -0.97;  // a spring's P follows the depth (either sign)
  d = DecideProfile(&e, FuseOptions{});
  EXPECT_EQ(d.used, ProfileSource::kSpring);
  EXPECT_EQ(d.spring_depth_agreement, -0.97);
}

// A source given is used as given (its words say so); one the data cannot
// give is refused naming the option.
TEST(DecideProfile, AGivenSourceIsUsedOrRefused) {
  FakeEvidence e;
  FuseOptions o;
  o.profile_from = ProfileSource::kDepth;
  try {
    DecideProfile(&e, o);
    FAIL() << "no error";
  } catch (const FusionError& err) {
    EXPECT_TRUE(Has(err.what(),
                    "--profile-from depth, but the force file "
                    "has no depth channel"))
        << err.what();
  }
  o.profile_from = ProfileSource::kFriction;
  EXPECT_THROW(DecideProfile(&e, o), FusionError);
  e.scan = true;
  ProfileDecision d = DecideProfile(&e, o);
  EXPECT_EQ(d.used, ProfileSource::kFriction);
  EXPECT_EQ(d.given, ProfileSource::kFriction);
  EXPECT_TRUE(Has(d.reason, "--profile-from friction")) << d.reason;
  o.profile_from = ProfileSource::kSpring;
  e.significance = 0.5;
  e.ratio = 0.01;
  d = DecideProfile(&e, o);
  EXPECT_EQ(d.used, ProfileSource::kSpring);
  EXPECT_FALSE(e.asked.count("ratio"));
  EXPECT_TRUE(Has(d.reason, "(--profile-from spring)")) << d.reason;
}

}  // namespace
}  // namespace wearscar::fusion
