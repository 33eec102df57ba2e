// The path of a sphere riding a scanned groove (SpherePath) on analytic
// maps: a sphere-carved groove whose floor waves gently is followed; a
// valley narrower than the sphere is bridged (the path stays above the
// centreline by what the ball envelope says); rough floors average out
// across the track; unmeasured surface gives NaN, not a guess.

#include "wearscar/scan/sphere_path.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "wearscar/scan/track.h"

namespace wearscar::scan {
namespace {

constexpr double kR = 3.25, kPitch = 0.005;

// A groove carved by a sphere of radius kR along x at the floor depth
// d(u) (a function of the along-track u from the centre), on a map whose
// track axis is at `angle_deg`; roughness of sd `rough` independent per
// pixel.
template <typename Depth>
HeightMap Groove(Depth depth, double angle_deg, double rough = 0.0) {
  HeightMap m;
  m.dx_mm = m.dy_mm = kPitch;
  const int cols = 1600, rows = 500;
  m.Resize(rows, cols);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, rough);
  const double th = angle_deg * M_PI / 180;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double x = c * kPitch - 4.0, y = r * kPitch - 1.25;
      const double u = x * std::cos(th) + y * std::sin(th);
      const double w = -x * std::sin(th) + y * std::cos(th);
      const double floor = std::abs(u) < 3.0 ? depth(u) : 0.0;
      const double z =
          -std::max(0.0, floor - (kR - std::sqrt(kR * kR - w * w)));
      m.height_mm(r, c) =
          static_cast<float>(z + (rough > 0 ? noise(rng) : 0.0));
      m.valid(r, c) = 1;
    }
  }
  return m;
}

Track Axis(double angle_deg) {
  Track t;
  t.centre_x_mm = 4.0;
  t.centre_y_mm = 1.25;
  t.angle_deg = angle_deg;
  t.length_mm = 5.0;
  t.width_mm = 1.2;
  return t;
}

// The ball envelope of a 1-D floor: the lowest point of a sphere of
// radius kR resting on it above s.
template <typename Depth>
double Envelope(Depth depth, double s) {
  double top = -INFINITY;
  for (double u = s - 1.5; u <= s + 1.5; u += 0.0005) {
    top =
        std::max(top, -depth(u) + std::sqrt(kR * kR - (u - s) * (u - s)) - kR);
  }
  return top;
}

double At(const WearProfile& p, double s) {
  const double i = (s - p.s_mm[0]) / p.step_mm;
  const auto k = static_cast<Eigen::Index>(std::lround(i));
  return p.height_mm[k];
}

// A floor that waves at 1.6 mm with 8 um: curvature 0.12 /mm, far below
// 1/R. The sphere follows it, touching where the floor's normal points at
// its centre: up to R k^2 / 2 (1.6 um) above the floor below it, its
// slope the floor's at the contact, R k ahead (0.1 mm): the envelope.
TEST(SpherePath, AGentleWavinessIsFollowedAsABallDoes) {
  auto depth = [](double u) {
    return 0.1 + 0.008 * std::sin(2 * M_PI * u / 1.6);
  };
  for (double angle : {0.0, 2.5}) {
    const WearProfile p = SpherePath(Groove(depth, angle), Axis(angle));
    for (double s : {-1.5, -0.4, 0.0, 0.7, 1.9}) {
      EXPECT_NEAR(At(p, s), Envelope(depth, s), 0.0003)
          << "angle " << angle << " s " << s;
      EXPECT_NEAR(At(p, s), -depth(s), 0.002);
    }
  }
}

// A valley 0.2 mm wide and 10 um deep (curvature 2 /mm, six times 1/R):
// the sphere bridges it. At its bottom the path stays where the ball
// resting on the two shoulders is, not at the floor.
TEST(SpherePath, AValleyNarrowerThanTheSphereIsBridged) {
  auto depth = [](double u) {
    return 0.1 + 0.01 * std::exp(-0.5 * std::pow(u / 0.05, 2));
  };
  const WearProfile p = SpherePath(Groove(depth, 0.0), Axis(0.0));
  const WearProfile line = ExtractCentreline(Groove(depth, 0.0), Axis(0.0));
  // The centreline dips by 10 um; the ball envelope by what a ball of
  // radius R dips between shoulders.
  EXPECT_NEAR(At(line, 0.0), -0.11, 0.0005);
  EXPECT_NEAR(At(p, 0.0), Envelope(depth, 0.0), 0.0003);
  EXPECT_GT(At(p, 0.0), -0.1035);
  EXPECT_NEAR(At(p, 1.5), -0.1, 0.0003);
}

// Roughness of 3 um on every pixel: the centreline's band averages a few
// pixels, the sphere's contact patch the whole groove's width; the path's
// noise estimate says what is left.
TEST(SpherePath, ARoughFloorIsAveragedAcrossTheContact) {
  auto depth = [](double) { return 0.1; };
  const HeightMap rough = Groove(depth, 0.0, 0.003);
  const WearProfile p = SpherePath(rough, Axis(0.0));
  const WearProfile line = ExtractCentreline(rough, Axis(0.0));
  auto sd = [](const WearProfile& w) {
    double s = 0, s2 = 0;
    int n = 0;
    for (Eigen::Index i = 0; i < w.height_mm.size(); ++i) {
      if (std::abs(w.s_mm[i]) > 2 || !std::isfinite(w.height_mm[i])) continue;
      s += w.height_mm[i], s2 += w.height_mm[i] * w.height_mm[i], ++n;
    }
    return std::sqrt(s2 / n - (s / n) * (s / n));
  };
  EXPECT_LT(sd(p), 0.3 * sd(line));
  EXPECT_GT(line.noise_variance_mm2, 0.0);
  EXPECT_GT(p.noise_variance_mm2, 0.0);
  EXPECT_LT(p.noise_variance_mm2, line.noise_variance_mm2);
}

TEST(SpherePath, UnmeasuredSurfaceIsNaNAndOptionsAreChecked) {
  HeightMap m = Groove([](double) { return 0.1; }, 0.0);
  for (int r = 0; r < m.rows(); ++r) {
    for (int c = 780; c < 820; ++c) {
      m.height_mm(r, c) = NAN;
      m.valid(r, c) = 0;
    }
  }
  const WearProfile p = SpherePath(m, Axis(0.0));
  EXPECT_TRUE(std::isnan(At(p, 0.0)));
  EXPECT_NEAR(At(p, 1.0), -0.1, 0.0003);
  SpherePathOptions o;
  o.step_mm = 0;
  EXPECT_THROW(SpherePath(m, Axis(0.0), o), ScanError);
}

}  // namespace
}  // namespace wearscar::scan
