#include "wearscar/scan/sphere_path.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "wearscar/support/check.h"

namespace wearscar::scan {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxCells = 5e7;  // the resampled surface's size bound
constexpr float kNone = -std::numeric_limits<float>::infinity();  // unmeasured

}  // namespace

bool SpherePathOptions::IsValid(std::string* why) const {
  if (!(radius_mm >= 0 && radius_mm < 1000) || !(step_mm > 0 && step_mm < 10) ||
      !(extend_mm >= 0 && extend_mm < 100) ||
      !(min_reach_mm > 0 && min_reach_mm < 100)) {
    if (why) {
      *why =
          "sphere path: radius_mm must be in [0, 1000), step_mm in (0, 10), "
          "extend_mm in [0, 100), min_reach_mm in (0, 100)";
    }
    return false;
  }
  return true;
}

namespace {

// The track's frame on the path's grid: u along (nu columns from u0), w
// across (nw rows about the axis, contiguous within a column).
struct Frame {
  int nu = 0, nw = 0, mw = 0, mu = 0;
  double u0 = 0, h = 0;
};

// The surface resampled in the frame (kNone where unmeasured).
std::vector<float> Resample(const HeightMap& map,
                            const Track& track,
                            const Frame& f) {
  const double th = track.angle_deg * kPi / 180.0;
  const double ax = std::cos(th), ay = std::sin(th);
  std::vector<float> surface(static_cast<size_t>(f.nu) * f.nw, kNone);
  for (int i = 0; i < f.nu; ++i) {
    const double u = f.u0 + i * f.h;
    for (int j = 0; j < f.nw; ++j) {
      const double w = (j - f.mw) * f.h;
      const double z = SampleBilinear(map,
                                      track.centre_x_mm + u * ax - w * ay,
                                      track.centre_y_mm + u * ay + w * ax);
      if (std::isfinite(z))
        surface[static_cast<size_t>(i) * f.nw + j] = float(z);
    }
  }
  return surface;
}

// Across the track the sphere's contact patch spans the groove it carved
// (conformal: the surface less the sphere's cross-section is level there),
// and the patch's elastic give averages the roughness it presses on: per
// column, the mean of z(u, w) + sqrt(r^2 - w^2) - r over the measured w
// (NaN where less than a third was measured); with the two halves' means,
// whose difference is its noise.
std::vector<double> RestHeights(const std::vector<float>& surface,
                                const Frame& f,
                                double r,
                                Eigen::VectorXd halves[2]) {
  std::vector<double> rest(static_cast<size_t>(f.nu), std::nan(""));
  for (int e = 0; e < 2; ++e) halves[e] = Eigen::VectorXd::Constant(f.nu, NAN);
  for (int i = 0; i < f.nu; ++i) {
    double sum = 0, half_sum[2] = {0, 0};
    int seen = 0, half_seen[2] = {0, 0};
    for (int j = 0; j < f.nw; ++j) {
      const float z = surface[static_cast<size_t>(i) * f.nw + j];
      if (z == kNone) continue;
      const double w = (j - f.mw) * f.h;
      const double v = z + std::sqrt(r * r - w * w) - r;
      sum += v;
      ++seen;
      if (j != f.mw) half_sum[j > f.mw] += v, ++half_seen[j > f.mw];
    }
    if (3 * seen >= f.nw) rest[i] = sum / seen;
    for (int e = 0; e < 2; ++e) {
      if (half_seen[e] > 0) halves[e][i] = half_sum[e] / half_seen[e];
    }
  }
  return rest;
}

// Along the track the sphere bridges what curves tighter than 1/r: the
// lowest point at s is max over u of the rest height plus sqrt(r^2 - (u -
// s)^2) - r (a rigid ball's envelope); NaN unless measured under the
// centre and over a third of the reach.
void Envelope(const std::vector<double>& rest,
              const Frame& f,
              double r,
              double half,
              WearProfile* p) {
  std::vector<double> cap(static_cast<size_t>(2 * f.mu + 1));
  for (int du = -f.mu; du <= f.mu; ++du)
    cap[du + f.mu] = std::sqrt(r * r - f.h * f.h * du * du) - r;
  const int n = static_cast<int>(std::floor(2 * half / f.h)) + 1;
  p->s_mm.resize(n);
  p->height_mm.resize(n);
  p->valid_samples.resize(n);
  for (int k = 0; k < n; ++k) {
    double top = -INFINITY;
    int seen = 0;
    for (int du = -f.mu; du <= f.mu; ++du) {
      const double z = rest[k + f.mu + du];
      if (!std::isfinite(z)) continue;
      top = std::max(top, z + cap[du + f.mu]);
      ++seen;
    }
    p->s_mm[k] = -half + k * f.h;
    p->valid_samples[k] = seen;
    p->height_mm[k] = std::isfinite(rest[k + f.mu]) && 3 * seen >= 2 * f.mu + 1
                          ? top
                          : std::nan("");
  }
}

}  // namespace

WearProfile SpherePath(const HeightMap& map,
                       const Track& track,
                       const SpherePathOptions& o) {
  WEARSCAR_CHECK(map.IsConsistent(), "SpherePath needs a consistent map");
  std::string why;
  if (!o.IsValid(&why)) throw ScanError(why);
  const double r = o.radius_mm, h = o.step_mm;
  const double reach =
      std::clamp(0.5 * track.width_mm, o.min_reach_mm, 0.9 * std::max(r, h));
  const double half = 0.5 * track.length_mm + o.extend_mm;
  const double nu = std::floor(2 * (half + reach) / h) + 1;
  const double nw = 2 * std::floor(reach / h) + 1;
  if (!(nu * nw <= kMaxCells)) {
    throw ScanError(fmt::format(
        "{}: a sphere path over {:.4g} mm in steps of {:.4g} mm needs "
        "{:.4g} surface samples; expected at most {:.4g} (check the pixel "
        "size and the track)",
        map.metadata.source,
        2 * half,
        h,
        nu * nw,
        kMaxCells));
  }
  Frame f;
  f.nu = static_cast<int>(nu), f.nw = static_cast<int>(nw);
  f.mw = f.nw / 2, f.mu = static_cast<int>(std::floor(reach / h));
  f.h = h, f.u0 = -half - f.mu * h;
  Eigen::VectorXd halves[2];
  const std::vector<double> rest =
      RestHeights(Resample(map, track, f), f, r, halves);
  WearProfile p;
  p.step_mm = h;
  p.band_width_mm = 2 * reach;
  p.noise_variance_mm2 = HalvesNoiseVariance(halves[0], halves[1]);
  Envelope(rest, f, r, half, &p);
  return p;
}

}  // namespace wearscar::scan
