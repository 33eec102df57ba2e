#include "wearscar/scan/track_ends.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

namespace wearscar::scan {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The circle's height over its parabola at u from its lowest point,
// R - sqrt(R^2 - u^2) - u^2 / 2R (about u^4 / 8R^3: 3 um at 0.95 mm under
// a 3.25 mm sphere, which would move the reversal by 0.015 mm), taken off
// the wall with the reversal of the pass before.
double Excess(double u, double r) {
  const double u2 = std::min(u * u, r * r);
  return r - std::sqrt(r * r - u2) - u2 / (2 * r);
}

// One wall: `outward` is +1 at the high end, -1 at the low end. The depth
// beyond the reversal e is d0 - (s - e)^2 / 2R (less the circle's excess
// over its parabola), so the height less s^2 / 2R is linear in s with
// slope -e / R: a straight-line fit gives e, refined over passes.
TrackEnd FitWall(const WearProfile& p,
                 double depth,
                 int outward,
                 const TrackEndOptions& o) {
  TrackEnd end;
  const Eigen::Index n = p.s_mm.size();
  const double r = o.sphere_radius_mm;
  // The outermost point at half the groove's depth: on the wall.
  Eigen::Index half = -1;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index i = outward > 0 ? k : n - 1 - k;
    if (std::isfinite(p.height_mm[i]) && -p.height_mm[i] >= 0.5 * depth)
      half = i;
  }
  if (half < 0) return end;
  // The wall reaches the surface within sqrt(2 R depth) of that point; the
  // profile must show its lip (else the field cut it).
  const double reach = std::sqrt(2 * r * depth);
  double e = p.s_mm[half];
  for (int pass = 0; pass < 5; ++pass) {
    double s1 = 0, y1 = 0, ss = 0, sy = 0;
    int m = 0;
    bool lip = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double s = p.s_mm[i], h = p.height_mm[i];
      if (!std::isfinite(h) || outward * (s - e) < 0 ||
          outward * (s - p.s_mm[half]) > reach)
        continue;
      if (-h < 0.15 * depth) {
        lip = true;
        continue;
      }
      if (-h > 0.85 * depth && pass > 0) continue;
      const double y = h - Excess(s - e, r) - s * s / (2 * r);
      s1 += s, y1 += y, ss += s * s, sy += s * y, ++m;
    }
    if (!lip || m < o.min_points) return TrackEnd{};
    const double slope = (m * sy - s1 * y1) / (m * ss - s1 * s1);
    if (!std::isfinite(slope)) return TrackEnd{};
    if (pass == 0) {
      // The first pass starts from the half-depth point, which lies beyond
      // the reversal: move back by the wall's run to half depth.
      e = p.s_mm[half] - outward * std::sqrt(r * depth);
      continue;
    }
    e = -r * slope;
    end.points = m;
    const double a = (y1 - slope * s1) / m;
    double rss = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double s = p.s_mm[i], h = p.height_mm[i];
      if (!std::isfinite(h) || outward * (s - e) < 0 || -h < 0.15 * depth ||
          -h > 0.85 * depth || outward * (s - p.s_mm[half]) > reach)
        continue;
      const double d = h - Excess(s - e, r) - s * s / (2 * r) - (a + slope * s);
      rss += d * d;
    }
    end.residual_to_depth = std::sqrt(rss / m) / depth;
  }
  if (!(end.residual_to_depth <= o.max_residual_to_depth)) return TrackEnd{};
  end.position_mm = e;
  return end;
}

}  // namespace

TrackEnds FitTrackEnds(const WearProfile& p, const TrackEndOptions& o) {
  TrackEnds ends;
  const Eigen::Index n = p.s_mm.size();
  if (n < 2 * o.min_points || !(o.sphere_radius_mm > 0)) return ends;
  double lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (std::isfinite(p.height_mm[i]))
      lo = std::min(lo, p.s_mm[i]), hi = std::max(hi, p.s_mm[i]);
  }
  std::vector<double> central;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (std::isfinite(p.height_mm[i]) &&
        std::abs(p.s_mm[i] - 0.5 * (lo + hi)) < 0.25 * (hi - lo))
      central.push_back(-p.height_mm[i]);
  }
  ends.depth_mm = Median(central);
  if (!(ends.depth_mm > 0)) return ends;
  ends.low = FitWall(p, ends.depth_mm, -1, o);
  ends.high = FitWall(p, ends.depth_mm, +1, o);
  return ends;
}

}  // namespace wearscar::scan
