#include "simulator_tools.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "wearscar/support/numbers.h"

namespace wearscar::samples::internal {

using support::kPi;

Eigen::VectorXd GaussianSmooth(const Eigen::VectorXd& v, double sigma_samples) {
  if (sigma_samples < 0.5) return v;
  const int h = static_cast<int>(std::ceil(3 * sigma_samples));
  Eigen::VectorXd kernel(2 * h + 1);
  for (int j = -h; j <= h; ++j) {
    kernel[j + h] = std::exp(-0.5 * j * j / (sigma_samples * sigma_samples));
  }
  kernel /= kernel.sum();
  Eigen::VectorXd out(v.size());
  const Eigen::Index n = v.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    double s = 0;
    for (int j = -h; j <= h; ++j) {
      const Eigen::Index k = std::clamp<Eigen::Index>(i + j, 0, n - 1);
      s += kernel[j + h] * v[k];
    }
    out[i] = s;
  }
  return out;
}

void BlurInPlace(scan::HeightMap::Heights* image, double sigma_px) {
  if (sigma_px < 0.3) return;
  const int h = static_cast<int>(std::ceil(3 * sigma_px));
  std::vector<float> kernel(2 * h + 1);
  float sum = 0;
  for (int j = -h; j <= h; ++j) {
    kernel[j + h] =
        static_cast<float>(std::exp(-0.5 * j * j / (sigma_px * sigma_px)));
    sum += kernel[j + h];
  }
  for (float& k : kernel) k /= sum;
  const Eigen::Index rows = image->rows(), cols = image->cols();
  scan::HeightMap::Heights tmp(rows, cols);
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < cols; ++c) {
      float acc = 0;
      for (int j = -h; j <= h; ++j) {
        acc += kernel[j + h] *
               (*image)(r, std::clamp<Eigen::Index>(c + j, 0, cols - 1));
      }
      tmp(r, c) = acc;
    }
  }
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < cols; ++c) {
      float acc = 0;
      for (int j = -h; j <= h; ++j) {
        acc += kernel[j + h] *
               tmp(std::clamp<Eigen::Index>(r + j, 0, rows - 1), c);
      }
      (*image)(r, c) = acc;
    }
  }
}

Eigen::VectorXd Texture(const Eigen::VectorXd& x, Rng& rng) {
  Eigen::VectorXd t = Eigen::VectorXd::Zero(x.size());
  const int kWaves = 8;
  for (int w = 0; w < kWaves; ++w) {
    const double wavelength = 0.3 + 1.2 * rng.Uniform();
    const double phase = 2 * kPi * rng.Uniform();
    const double amp = rng.Normal();
    t += amp * (2 * kPi * x.array() / wavelength + phase).sin().matrix();
  }
  const double mean = t.mean();
  const double sd = std::sqrt((t.array() - mean).square().mean());
  return sd > 0 ? Eigen::VectorXd((t.array() - mean) / sd) : t;
}

Eigen::VectorXd RingPhase(const Eigen::VectorXd& x,
                          double period,
                          double width_cv,
                          double offset_mm,
                          Rng& widths) {
  Eigen::VectorXd p(x.size());
  if (width_cv == 0) {
    for (Eigen::Index i = 0; i < x.size(); ++i)
      p[i] = std::fmod(x[i] - offset_mm + 100 * period, period) / period;
    return p;
  }
  auto next = [&] {
    return period * std::max(0.3, 1 + width_cv * widths.Normal());
  };
  double begin = offset_mm - period * std::ceil((offset_mm - x[0]) / period);
  double width = next();
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    while (x[i] >= begin + width) {
      begin += width;
      width = next();
    }
    p[i] = std::clamp((x[i] - begin) / width, 0.0, std::nextafter(1.0, 0.0));
  }
  return p;
}

std::pair<double, double> StrokeMoments(double amplitude_mm,
                                        const Eigen::VectorXd& x,
                                        const Eigen::VectorXd& v) {
  double m = 0, s2 = 0;
  int n = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (std::abs(x[i]) <= amplitude_mm) m += v[i], ++n;
  }
  m /= n;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (std::abs(x[i]) <= amplitude_mm) s2 += (v[i] - m) * (v[i] - m);
  }
  return {m, std::sqrt(s2 / n)};
}

}  // namespace wearscar::samples::internal
