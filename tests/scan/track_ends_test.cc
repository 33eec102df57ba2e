// The sphere's reversals from the worn track's end walls (FitTrackEnds)
// on analytic profiles: walls that are the sphere's imprint give the
// reversals whatever the groove's depth at each end, where a threshold's
// outline moves with that depth; a wall the field cut, or one that is no
// sphere's, gives none rather than a guess.

#include "wearscar/scan/track_ends.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wearscar::scan {
namespace {

constexpr double kSphereR = 3.25, kEndsStep = 0.0074;

// A profile along the track: the groove's floor depth(u) over the stroke
// [centre - a, centre + a], beyond each reversal the sphere's circle from
// the floor's depth there, up to the surface; heights NaN beyond `field`.
template <typename Depth>
WearProfile Track(Depth depth, double centre, double a, double field = 4.5) {
  const int n = static_cast<int>(2 * field / kEndsStep);
  WearProfile p;
  p.s_mm.resize(n);
  p.height_mm.resize(n);
  p.valid_samples.setOnes(n);
  for (int i = 0; i < n; ++i) {
    const double s = -field + i * kEndsStep, u = s - centre;
    const double end = std::clamp(u, -a, a);
    const double beyond = std::abs(u) - a;
    double d = depth(end);
    if (beyond > 0)
      d -= kSphereR -
           std::sqrt(std::max(0.0, kSphereR * kSphereR - beyond * beyond));
    p.s_mm[i] = s;
    p.height_mm[i] = -std::max(0.0, d);
  }
  return p;
}

// The outline's centre at a quarter of the groove's largest depth, as a
// track's threshold finds it.
double OutlineCentre(const WearProfile& p) {
  double dmax = 0, lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < p.s_mm.size(); ++i)
    dmax = std::max(dmax, -p.height_mm[i]);
  for (int i = 0; i < p.s_mm.size(); ++i) {
    if (-p.height_mm[i] > 0.25 * dmax)
      lo = std::min(lo, p.s_mm[i]), hi = std::max(hi, p.s_mm[i]);
  }
  return 0.5 * (lo + hi);
}

TEST(TrackEnds, TheWallsGiveTheReversalsWhateverTheDepthAtEachEnd) {
  // Twice as deep at one end as at the other (a depth trend along the
  // stroke), the track 0.3 mm off the profile's centre.
  const auto trend = [](double u) { return 0.08 + 0.04 * u / 2.85; };
  const WearProfile p = Track(trend, 0.3, 2.85);
  const TrackEnds e = FitTrackEnds(p);
  ASSERT_TRUE(e.low.Found() && e.high.Found());
  EXPECT_NEAR(e.low.position_mm, 0.3 - 2.85, 0.004);
  EXPECT_NEAR(e.high.position_mm, 0.3 + 2.85, 0.004);
  EXPECT_GT(e.low.points, 20);
  EXPECT_LT(e.high.residual_to_depth, 0.01);
  // The threshold's outline is moved by the deeper end: what the walls
  // correct.
  EXPECT_GT(std::abs(OutlineCentre(p) - 0.3), 0.05);
}

TEST(TrackEnds, AWallTheFieldCutIsNotGuessed) {
  WearProfile p = Track([](double) { return 0.14; }, 0.6, 2.85, 3.9);
  // The high wall runs past the field's edge at 3.9 mm (its lip at 4.4).
  for (int i = 0; i < p.s_mm.size(); ++i) {
    if (p.s_mm[i] > 3.9) p.height_mm[i] = NAN;
  }
  const TrackEnds e = FitTrackEnds(p);
  EXPECT_TRUE(e.low.Found());
  EXPECT_NEAR(e.low.position_mm, 0.6 - 2.85, 0.004);
  EXPECT_FALSE(e.high.Found());
}

TEST(TrackEnds, AWallThatIsNoSpheresIsNotUsed) {
  // A vertical step at the ends (a torn end, a cut): too few points on it.
  WearProfile p = Track([](double) { return 0.08; }, 0.0, 2.85);
  for (int i = 0; i < p.s_mm.size(); ++i) {
    p.height_mm[i] = std::abs(p.s_mm[i]) < 2.85 ? -0.08 : 0.0;
  }
  const TrackEnds step = FitTrackEnds(p);
  EXPECT_FALSE(step.low.Found());
  EXPECT_FALSE(step.high.Found());
  // A wall of a sphere ten times as large: its curvature is not 1/R.
  WearProfile flat = Track([](double) { return 0.08; }, 0.0, 2.85);
  for (int i = 0; i < flat.s_mm.size(); ++i) {
    const double beyond = std::abs(flat.s_mm[i]) - 2.85;
    flat.height_mm[i] =
        beyond > 0 ? -std::max(0.0, 0.08 - 0.04 * beyond) : -0.08;
  }
  const TrackEnds wide = FitTrackEnds(flat);
  EXPECT_FALSE(wide.low.Found() && wide.high.Found());
  // No groove at all.
  WearProfile none = p;
  none.height_mm.setZero();
  EXPECT_FALSE(FitTrackEnds(none).low.Found());
}

}  // namespace
}  // namespace wearscar::scan
