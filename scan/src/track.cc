#include "wearscar/scan/track.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "wearscar/support/check.h"
#include "wearscar/support/numbers.h"
#include "wearscar/support/robust_stats.h"

namespace wearscar::scan {
namespace {

using support::kPi;

using support::Percentile;

}  // namespace

bool TrackOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (smoothing_sigma_px < 0) return fail("smoothing_sigma_px must be >= 0");
  if (!(min_depth_mm > 0)) return fail("min_depth_mm must be > 0");
  if (!(depth_fraction > 0 && depth_fraction < 1))
    return fail("depth_fraction must be in (0, 1)");
  if (morphology_px < 0) return fail("morphology_px must be >= 0");
  if (!(min_elongation >= 1)) return fail("min_elongation must be >= 1");
  if (!(depth_quantile > 0.5 && depth_quantile <= 1))
    return fail("depth_quantile must be in (0.5, 1]");
  if (min_component_px < 3) return fail("min_component_px must be >= 3");
  if (!(length_quantile >= 0 && length_quantile < 0.5 && width_quantile >= 0 &&
        width_quantile < 0.5))
    return fail("length_quantile and width_quantile must be in [0, 0.5)");
  if (!(confident_depth_to_roughness >= 0 && confident_elongation >= 1))
    return fail("track confidence limits out of range");
  return true;
}

bool ProfileOptions::IsValid(std::string* why) const {
  if (!(step_mm == 0 || (step_mm >= 1e-6 && step_mm <= 10)) ||
      !(band_width_mm >= 0 && band_width_mm <= 100) ||
      !(extend_mm >= 0 && extend_mm <= 100)) {
    if (why) {
      *why =
          "the centreline step must be 0 (the pitch) or 1e-6 to 10 mm, the "
          "band 0 to 100 mm, the extension 0 to 100 mm";
    }
    return false;
  }
  return true;
}

double SampleBilinear(const HeightMap& map, double x_mm, double y_mm) {
  const double fc = x_mm / map.dx_mm, fr = y_mm / map.dy_mm;
  if (!(fc >= 0) || !(fr >= 0)) return std::nan("");
  const Eigen::Index c = static_cast<Eigen::Index>(fc),
                     r = static_cast<Eigen::Index>(fr);
  if (c + 1 >= map.cols() || r + 1 >= map.rows()) {
    // Exactly on the last row/column.
    if (c < map.cols() && r < map.rows() && fc == c && fr == r &&
        map.valid(r, c)) {
      return map.height_mm(r, c);
    }
    return std::nan("");
  }
  if (!map.valid(r, c) || !map.valid(r, c + 1) || !map.valid(r + 1, c) ||
      !map.valid(r + 1, c + 1)) {
    return std::nan("");
  }
  const double u = fc - c, v = fr - r;
  return (1 - u) * (1 - v) * map.height_mm(r, c) +
         u * (1 - v) * map.height_mm(r, c + 1) +
         (1 - u) * v * map.height_mm(r + 1, c) +
         u * v * map.height_mm(r + 1, c + 1);
}

namespace {

Track ManualTrack(const HeightMap& map, const TrackOptions& options) {
  Track t;
  t.manual = true;
  t.centre_x_mm = options.centre_x_mm;
  t.centre_y_mm = options.centre_y_mm;
  t.angle_deg = options.angle_deg;
  t.length_mm =
      options.manual_length_mm > 0
          ? options.manual_length_mm
          : std::hypot(map.cols() * map.dx_mm, map.rows() * map.dy_mm);
  t.message = "placed by hand";
  return t;
}

// Pixels deeper than the threshold, smoothed first and cleaned by an
// opening and a closing; `threshold` and `depths` (every 4th valid pixel's
// depth) are returned for the message and the roughness.
cv::Mat DeepPixels(const HeightMap& map,
                   const TrackOptions& options,
                   double* threshold,
                   std::vector<double>* depths) {
  const int rows = static_cast<int>(map.rows()),
            cols = static_cast<int>(map.cols());
  cv::Mat depth(rows, cols, CV_32F);
  depths->reserve(static_cast<size_t>(rows) * cols / 4 + 1);
  for (int r = 0; r < rows; ++r) {
    const float* height = &map.height_mm(r, 0);
    const std::uint8_t* valid = &map.valid(r, 0);
    float* out = depth.ptr<float>(r);
    // Every 4th pixel of the whole map in row-major order.
    for (int c = 0; c < cols; ++c) {
      out[c] = valid[c] ? -height[c] : 0.0f;
    }
    for (int c = (4 - (r * cols) % 4) % 4; c < cols; c += 4) {
      if (valid[c]) depths->push_back(out[c]);
    }
  }
  if (options.smoothing_sigma_px > 0) {
    cv::GaussianBlur(depth, depth, cv::Size(0, 0), options.smoothing_sigma_px);
  }
  *threshold =
      std::max(options.min_depth_mm,
               options.depth_fraction *
                   Percentile(std::move(*depths), options.depth_quantile));
  // 255 where deeper than the threshold, straight into bytes.
  cv::Mat mask;
  cv::compare(depth, *threshold, mask, cv::CMP_GT);
  if (options.morphology_px > 1) {
    const cv::Mat k = cv::getStructuringElement(
        cv::MORPH_ELLIPSE,
        cv::Size(options.morphology_px, options.morphology_px));
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, k);
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, k);
  }
  return mask;
}

// A connected component by PCA of its pixels (in mm).
struct Component {
  int label = -1;
  double pixels = 0, elongation = 0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();  // angle in (-90, 90]
};

// The largest component at least min_elongation long for its width, or
// one with label -1.
Component LargestElongated(const HeightMap& map,
                           const cv::Mat& labels,
                           int n,
                           const TrackOptions& options) {
  std::vector<Eigen::Matrix2d> cov(n, Eigen::Matrix2d::Zero());
  std::vector<Eigen::Vector2d> mean(n, Eigen::Vector2d::Zero());
  std::vector<double> count(n, 0.0);
  for (int r = 0; r < labels.rows; ++r) {
    for (int c = 0; c < labels.cols; ++c) {
      const int l = labels.at<int>(r, c);
      if (l == 0) continue;
      const Eigen::Vector2d p(c * map.dx_mm, r * map.dy_mm);
      mean[l] += p;
      cov[l] += p * p.transpose();
      count[l] += 1;
    }
  }
  Component best;
  for (int l = 1; l < n; ++l) {
    if (count[l] < options.min_component_px) continue;
    const Eigen::Vector2d m = mean[l] / count[l];
    const Eigen::Matrix2d c = cov[l] / count[l] - m * m.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(c);
    const double lo = std::max(es.eigenvalues()[0], 1e-30),
                 hi = es.eigenvalues()[1];
    const double elongation = std::sqrt(hi / lo);
    if (elongation >= options.min_elongation && count[l] > best.pixels) {
      best = {l, count[l], elongation, m, es.eigenvectors().col(1)};
    }
  }
  Eigen::Vector2d& a = best.axis;
  if (a.x() < 0 || (a.x() == 0 && a.y() < 0)) a = -a;
  return best;
}

// Length, width (between quantiles of the pixels' positions along and
// across the axis), the centre moved to the middle of the length, maximum
// depth and volume from the levelled heights.
void MeasureExtent(const HeightMap& map,
                   const cv::Mat& labels,
                   const Component& k,
                   const TrackOptions& options,
                   Track* t) {
  std::vector<double> along, across;
  along.reserve(static_cast<size_t>(k.pixels));
  across.reserve(static_cast<size_t>(k.pixels));
  double max_depth = 0, volume = 0;
  const Eigen::Vector2d& a = k.axis;
  for (int r = 0; r < labels.rows; ++r) {
    for (int c = 0; c < labels.cols; ++c) {
      if (labels.at<int>(r, c) != k.label) continue;
      t->reaches_edge = t->reaches_edge || r == 0 || c == 0 ||
                        r == labels.rows - 1 || c == labels.cols - 1;
      const Eigen::Vector2d d =
          Eigen::Vector2d(c * map.dx_mm, r * map.dy_mm) - k.mean;
      along.push_back(d.dot(a));
      across.push_back(-d.x() * a.y() + d.y() * a.x());
      if (map.valid(r, c)) {
        const double z = -map.height_mm(r, c);
        max_depth = std::max(max_depth, z);
        volume += std::max(0.0, z) * map.dx_mm * map.dy_mm;
      }
    }
  }
  const auto [lo, hi] = support::Percentiles(
      std::move(along), options.length_quantile, 1 - options.length_quantile);
  t->length_mm = hi - lo;
  const double shift = 0.5 * (lo + hi);
  t->centre_x_mm = k.mean.x() + shift * a.x();
  t->centre_y_mm = k.mean.y() + shift * a.y();
  const auto [left, right] = support::Percentiles(
      std::move(across), options.width_quantile, 1 - options.width_quantile);
  t->width_mm = right - left;
  t->max_depth_mm = max_depth;
  t->volume_mm3 = volume;
}

// Mean depth along the central 80% of the axis.
double MeanDepthAlongAxis(const HeightMap& map,
                          const Track& t,
                          const Eigen::Vector2d& a) {
  const double step = std::min(map.dx_mm, map.dy_mm);
  double sum = 0;
  int n_ok = 0;
  for (double s = -0.4 * t.length_mm; s <= 0.4 * t.length_mm; s += step) {
    const double z = SampleBilinear(
        map, t.centre_x_mm + s * a.x(), t.centre_y_mm + s * a.y());
    if (!std::isfinite(z)) continue;
    sum += -z;
    ++n_ok;
  }
  return n_ok > 0 ? sum / n_ok : std::nan("");
}

// Roughness outside the track: the MAD-based sd of every 4th valid pixel
// away from it (0 when fewer than 10).
double RoughnessOutside(const HeightMap& map, const cv::Mat& mask) {
  std::vector<double> outside;
  for (int r = 0; r < mask.rows; ++r) {
    for (int c = 0; c < mask.cols; ++c) {
      if ((r * mask.cols + c) % 4 != 0 || !map.valid(r, c) ||
          mask.at<unsigned char>(r, c) != 0)
        continue;
      outside.push_back(map.height_mm(r, c));
    }
  }
  if (outside.size() < 10) return 0.0;
  const double median = Percentile(outside, 0.5);
  for (double& v : outside) v = std::abs(v - median);
  return 1.4826 * Percentile(outside, 0.5);
}

}  // namespace

Track FindTrack(const HeightMap& map, const TrackOptions& options) {
  WEARSCAR_CHECK(map.IsConsistent(), "FindTrack needs a consistent map");
  std::string why;
  if (!options.IsValid(&why)) throw ScanError("track options: " + why);
  if (options.manual) return ManualTrack(map, options);
  double threshold = 0;
  std::vector<double> depths;
  const cv::Mat mask = DeepPixels(map, options, &threshold, &depths);
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(
      mask, labels, stats, centroids, 8, CV_32S);
  const Component best = LargestElongated(map, labels, n, options);
  if (best.label < 0) {
    throw NoTrackError(fmt::format(
        "{}: no worn track found: no elongated depression deeper than {:.4f} "
        "mm (length/width >= "
        "{}); place it by hand (--track-x, --track-y, --track-angle) or lower "
        "the depth threshold (--min-depth; in Python min_depth=)",
        map.metadata.source,
        threshold,
        options.min_elongation));
  }
  Track t;
  t.angle_deg = std::atan2(best.axis.y(), best.axis.x()) * 180.0 / kPi;
  t.elongation = best.elongation;
  t.pixels = static_cast<int>(best.pixels);
  MeasureExtent(map, labels, best, options, &t);
  t.mean_depth_mm = MeanDepthAlongAxis(map, t, best.axis);
  t.roughness_mm = RoughnessOutside(map, mask);
  t.depth_to_roughness =
      t.roughness_mm > 0 ? t.mean_depth_mm / t.roughness_mm : std::nan("");
  t.message = fmt::format(
      "found: {} px, elongation {:.1f}, depth threshold {:.4f} mm, "
      "mean depth {:.1f}x the roughness",
      t.pixels,
      t.elongation,
      threshold,
      t.depth_to_roughness);
  if (!(t.depth_to_roughness >= options.confident_depth_to_roughness) ||
      t.elongation < options.confident_elongation) {
    t.low_confidence = true;
    t.message += fmt::format(
        "; low confidence (expected a depth of at least {}x the roughness "
        "and an elongation of at least {}): it may be texture, not a wear "
        "track",
        options.confident_depth_to_roughness,
        options.confident_elongation);
  }
  return t;
}

namespace {

constexpr double kMaxProfileSamples = 1e7;

WearProfile SampleLine(const HeightMap& map,
                       const Track& t,
                       double s0,
                       double s1,
                       double step,
                       bool along,
                       double fixed,
                       double band) {
  WearProfile p;
  p.step_mm = step;
  p.band_width_mm = band;
  // Bounded before any cast: a profile of more than kMaxProfileSamples
  // points, or a band of more than as many pixels, is a wrong size.
  const double count = std::floor((s1 - s0) / step) + 1;
  const double pitch = std::min(map.dx_mm, map.dy_mm);
  const double across = band > 0 ? std::round(band / pitch) : 0.0;
  if (!(count <= kMaxProfileSamples) || !(across <= kMaxProfileSamples)) {
    throw ScanError(fmt::format(
        "{}: a profile of {:.4g} mm in steps of {:.4g} mm over a band of "
        "{:.4g} mm needs {:.4g} x {:.4g} samples; expected at most {} each "
        "(check the step, the band and the pixel size)",
        map.metadata.source,
        s1 - s0,
        step,
        band,
        count,
        2 * across + 1,
        kMaxProfileSamples));
  }
  const int n = std::max(1, static_cast<int>(count));
  p.s_mm.resize(n);
  p.height_mm.resize(n);
  p.valid_samples.resize(n);
  const double th = t.angle_deg * kPi / 180.0;
  const double ax = std::cos(th), ay = std::sin(th);
  const int m = band > 0 ? std::max(1, static_cast<int>(across)) : 0;
  Eigen::VectorXd halves[2] = {Eigen::VectorXd::Constant(n, std::nan("")),
                               Eigen::VectorXd::Constant(n, std::nan(""))};
  for (int i = 0; i < n; ++i) {
    const double s = s0 + i * step;
    double sum = 0, half_sum[2] = {0, 0};
    int k = 0, half_k[2] = {0, 0};
    for (int j = -m; j <= m; ++j) {
      const double w = m > 0 ? (0.5 * band) * j / m : 0.0;
      const double u = along ? s : fixed, v = along ? fixed + w : s;
      const double x = t.centre_x_mm + u * ax - v * ay;
      const double y = t.centre_y_mm + u * ay + v * ax;
      const double h = SampleBilinear(map, x, y);
      if (std::isfinite(h)) {
        sum += h;
        ++k;
        if (j != 0) half_sum[j > 0] += h, ++half_k[j > 0];
      }
    }
    p.s_mm[i] = s;
    p.height_mm[i] = k > 0 ? sum / k : std::nan("");
    p.valid_samples[i] = k;
    for (int e = 0; e < 2; ++e) {
      if (half_k[e] > 0) halves[e][i] = half_sum[e] / half_k[e];
    }
  }
  if (m > 0) p.noise_variance_mm2 = HalvesNoiseVariance(halves[0], halves[1]);
  return p;
}

}  // namespace

double HalvesNoiseVariance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double sum = 0, sum2 = 0;
  int n = 0;
  for (Eigen::Index i = 0; i < std::min(a.size(), b.size()); ++i) {
    const double d = a[i] - b[i];
    if (!std::isfinite(d)) continue;
    sum += d, sum2 += d * d, ++n;
  }
  if (n < 2) return 0.0;
  return std::max(0.0, sum2 / n - (sum / n) * (sum / n)) / 4;
}

WearProfile ExtractCentreline(const HeightMap& map,
                              const Track& track,
                              const ProfileOptions& options) {
  WEARSCAR_CHECK(map.IsConsistent(),
                 "ExtractCentreline needs a consistent map");
  std::string why;
  if (!options.IsValid(&why)) throw ScanError("profile options: " + why);
  const double step =
      options.step_mm > 0 ? options.step_mm : std::min(map.dx_mm, map.dy_mm);
  const double half = 0.5 * track.length_mm + options.extend_mm;
  return SampleLine(
      map, track, -half, half, step, true, 0.0, options.band_width_mm);
}

WearProfile ExtractCrossSection(const HeightMap& map,
                                const Track& track,
                                double s_mm,
                                double half_width_mm,
                                double step_mm) {
  const double step = step_mm > 0 ? step_mm : std::min(map.dx_mm, map.dy_mm);
  return SampleLine(
      map, track, -half_width_mm, half_width_mm, step, false, s_mm, 0.0);
}

}  // namespace wearscar::scan
