#include "riding_path.h"

#include <algorithm>
#include <cmath>

namespace wearscar::samples::internal {

RidingPath::RidingPath(std::function<double(double, double)> worn_depth,
                       double radius_mm,
                       double half_mm,
                       double step_mm)
    : worn_depth_(std::move(worn_depth)),
      radius_(radius_mm),
      half_(half_mm),
      step_(step_mm) {}

RidingPath::RidingPath(const SimulationOptions& o, Grid shape)
    : RidingPath(
          [a = o.amplitude_mm,
           r = o.sphere_radius_mm,
           shape = std::move(shape)](double u, double amp) {
            const double du = std::abs(u) - a;
            const double d0 = amp * shape(std::clamp(u, -a, a));
            return du > 0 ? std::max(0.0,
                                     d0 - (r - std::sqrt(std::max(
                                                   0.0, r * r - du * du))))
                          : d0;
          },
          o.sphere_radius_mm,
          o.amplitude_mm + 0.5) {}

const std::pair<Grid, Grid>& RidingPath::At(double amplitude) const {
  const long key = std::lround(std::log(std::max(amplitude, 1e-9)) / 0.005);
  auto found = cache_.find(key);
  if (found != cache_.end()) return found->second;
  const double amp = std::exp(key * 0.005);
  // The surface beyond the path's ends by the sphere's reach (its cap
  // falls by the deepest worn profile's depth within it).
  const int reach = static_cast<int>(std::ceil(radius_ / step_ * 0.5));
  const int n = static_cast<int>(std::round(2 * half_ / step_)) + 1;
  std::vector<double> z(static_cast<size_t>(n + 2 * reach));
  for (size_t i = 0; i < z.size(); ++i)
    z[i] = -worn_depth_(-half_ + (static_cast<int>(i) - reach) * step_, amp);
  std::vector<double> cap(static_cast<size_t>(2 * reach + 1));
  for (int d = -reach; d <= reach; ++d)
    cap[d + reach] =
        std::sqrt(radius_ * radius_ - d * d * step_ * step_) - radius_;
  Grid path{-half_, step_, Eigen::VectorXd(n)};
  for (int i = 0; i < n; ++i) {
    double top = -INFINITY;
    for (int d = -reach; d <= reach; ++d)
      top = std::max(top, z[i + reach + d] + cap[d + reach]);
    path.v[i] = top;
  }
  Grid slope = path.Derivative();
  return cache_.emplace(key, std::make_pair(std::move(path), std::move(slope)))
      .first->second;
}

}  // namespace wearscar::samples::internal
