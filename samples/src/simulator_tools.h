#pragma once
// The virtual tribometer's tools: a portable random stream, a function on
// a uniform grid, Gaussian smoothing, random texture.

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <utility>

#include "wearscar/scan/height_map.h"
#include "wearscar/support/interpolate.h"
#include "wearscar/support/numbers.h"

namespace wearscar::samples::internal {

// Deterministic across platforms: mt19937_64's output is fixed by the
// standard; the distributions are written here (std:: ones are not).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  double Uniform() {  // [0, 1)
    return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
  }
  double Normal() {  // Box-Muller
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = Uniform();
    while (u1 <= 0.0) u1 = Uniform();
    const double u2 = Uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2 * support::kPi * u2);
    has_spare_ = true;
    return r * std::cos(2 * support::kPi * u2);
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// A function of the plate coordinate sampled on a uniform grid, linearly
// interpolated; values beyond the grid are clamped.
struct Grid {
  double x0 = 0, step = 1;
  Eigen::VectorXd v;
  double operator()(double x) const {
    const double t = (x - x0) / step;
    const Eigen::Index n = v.size();
    if (t <= 0) return v[0];
    if (t >= static_cast<double>(n - 1)) return v[n - 1];
    return support::InterpolateAtIndex(v, t);
  }
  Grid Derivative() const {
    Grid d{x0, step, Eigen::VectorXd::Zero(v.size())};
    for (Eigen::Index i = 1; i + 1 < v.size(); ++i) {
      d.v[i] = (v[i + 1] - v[i - 1]) / (2 * step);
    }
    d.v[0] = d.v[1];
    d.v[v.size() - 1] = d.v[v.size() - 2];
    return d;
  }
};

Eigen::VectorXd GaussianSmooth(const Eigen::VectorXd& v, double sigma_samples);

// Separable Gaussian blur of an image, edges clamped.
void BlurInPlace(scan::HeightMap::Heights* image, double sigma_px);

// Smooth random texture: a sum of sinusoids with wavelengths 0.3-1.5 mm,
// unit standard deviation.
Eigen::VectorXd Texture(const Eigen::VectorXd& x, Rng& rng);

// Each point's phase within its growth ring, in [0, 1): rings of `period`
// mm, a boundary `offset_mm` after a multiple of it; with `width_cv` each
// ring's width varies about the period (sd over the mean, drawn from
// `widths`), one year's growth unlike the next, so that two specimens of
// one wood differ in where their rings fall, not only in phase.
Eigen::VectorXd RingPhase(const Eigen::VectorXd& x,
                          double period,
                          double width_cv,
                          double offset_mm,
                          Rng& widths);

// Mean and sd of v over the stroke (|x| <= amplitude_mm).
std::pair<double, double> StrokeMoments(double amplitude_mm,
                                        const Eigen::VectorXd& x,
                                        const Eigen::VectorXd& v);

}  // namespace wearscar::samples::internal
