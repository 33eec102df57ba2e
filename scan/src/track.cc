#include "wearscar/scan/track.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace wearscar::scan {
namespace {

constexpr double kPi = 3.14159265358979323846;

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = static_cast<size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

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

Track FindTrack(const HeightMap& map, const TrackOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw ScanError("track options: " + why);
  Track t;
  const int rows = static_cast<int>(map.rows()),
            cols = static_cast<int>(map.cols());
  if (options.manual) {
    t.manual = true;
    t.center_x_mm = options.center_x_mm;
    t.center_y_mm = options.center_y_mm;
    t.angle_deg = options.angle_deg;
    t.length_mm = options.manual_length_mm > 0
                      ? options.manual_length_mm
                      : std::hypot(cols * map.dx_mm, rows * map.dy_mm);
    t.message = "placed by hand";
    return t;
  }
  // Depth below the reference, invalid = 0, smoothed.
  cv::Mat depth(rows, cols, CV_32F);
  std::vector<double> depths;
  depths.reserve(static_cast<size_t>(rows) * cols / 4 + 1);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const float d = map.valid(r, c) ? -map.height_mm(r, c) : 0.0f;
      depth.at<float>(r, c) = d;
      if ((r * cols + c) % 4 == 0 && map.valid(r, c)) depths.push_back(d);
    }
  }
  if (options.smoothing_sigma_px > 0) {
    cv::GaussianBlur(depth, depth, cv::Size(0, 0), options.smoothing_sigma_px);
  }
  const double threshold = std::max(
      options.min_depth_mm, options.depth_fraction * Percentile(depths, 0.995));
  cv::Mat mask;
  cv::threshold(depth, mask, threshold, 255, cv::THRESH_BINARY);
  mask.convertTo(mask, CV_8U);
  if (options.morphology_px > 1) {
    const cv::Mat k = cv::getStructuringElement(
        cv::MORPH_ELLIPSE,
        cv::Size(options.morphology_px, options.morphology_px));
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, k);
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, k);
  }
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(
      mask, labels, stats, centroids, 8, CV_32S);
  // PCA of each component's pixels (in mm): keep the largest elongated one.
  int best = -1;
  double best_area = 0;
  std::vector<Eigen::Matrix2d> cov(n, Eigen::Matrix2d::Zero());
  std::vector<Eigen::Vector2d> mean(n, Eigen::Vector2d::Zero());
  std::vector<double> count(n, 0.0);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int l = labels.at<int>(r, c);
      if (l == 0) continue;
      const Eigen::Vector2d p(c * map.dx_mm, r * map.dy_mm);
      mean[l] += p;
      cov[l] += p * p.transpose();
      count[l] += 1;
    }
  }
  std::vector<double> elongation(n, 0.0);
  std::vector<Eigen::Vector2d> axis(n);
  for (int l = 1; l < n; ++l) {
    if (count[l] < 10) continue;
    mean[l] /= count[l];
    const Eigen::Matrix2d c = cov[l] / count[l] - mean[l] * mean[l].transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(c);
    const double lo = std::max(es.eigenvalues()[0], 1e-30),
                 hi = es.eigenvalues()[1];
    elongation[l] = std::sqrt(hi / lo);
    axis[l] = es.eigenvectors().col(1);
    const double area = count[l];
    if (elongation[l] >= options.min_elongation && area > best_area) {
      best = l;
      best_area = area;
    }
  }
  if (best < 0) {
    throw NoTrackError(fmt::format(
        "{}: no worn track found: no elongated depression deeper than {:.4f} "
        "mm (length/width >= "
        "{}); place it by hand (centre and angle) or lower the depth threshold",
        map.metadata.source,
        threshold,
        options.min_elongation));
  }
  Eigen::Vector2d a = axis[best];
  if (a.x() < 0 || (a.x() == 0 && a.y() < 0)) a = -a;  // angle in (-90, 90]
  t.angle_deg = std::atan2(a.y(), a.x()) * 180.0 / kPi;
  t.center_x_mm = mean[best].x();
  t.center_y_mm = mean[best].y();
  t.elongation = elongation[best];
  t.pixels = static_cast<int>(count[best]);
  // Extents along and across the axis; depth and volume from the raw map.
  std::vector<double> along, across;
  double max_depth = 0, volume = 0;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (labels.at<int>(r, c) != best) continue;
      const Eigen::Vector2d d =
          Eigen::Vector2d(c * map.dx_mm, r * map.dy_mm) - mean[best];
      along.push_back(d.dot(a));
      across.push_back(-d.x() * a.y() + d.y() * a.x());
      if (map.valid(r, c)) {
        const double z = -map.height_mm(r, c);
        max_depth = std::max(max_depth, z);
        volume += std::max(0.0, z) * map.dx_mm * map.dy_mm;
      }
    }
  }
  // Re-centre along the axis on the middle of the extent.
  const double lo = Percentile(along, 0.002), hi = Percentile(along, 0.998);
  t.length_mm = hi - lo;
  const double shift = 0.5 * (lo + hi);
  t.center_x_mm += shift * a.x();
  t.center_y_mm += shift * a.y();
  t.width_mm = Percentile(across, 0.995) - Percentile(across, 0.005);
  t.max_depth_mm = max_depth;
  t.volume_mm3 = volume;
  {
    const double step = std::min(map.dx_mm, map.dy_mm);
    double sum = 0;
    int n_ok = 0;
    for (double s = -0.4 * t.length_mm; s <= 0.4 * t.length_mm; s += step) {
      const double z = SampleBilinear(
          map, t.center_x_mm + s * a.x(), t.center_y_mm + s * a.y());
      if (!std::isfinite(z)) continue;
      sum += -z;
      ++n_ok;
    }
    t.mean_depth_mm = n_ok > 0 ? sum / n_ok : std::nan("");
  }
  // Roughness outside the track (every 4th valid pixel away from it).
  {
    std::vector<double> outside;
    outside.reserve(depths.size());
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        if ((r * cols + c) % 4 != 0 || !map.valid(r, c) ||
            mask.at<unsigned char>(r, c) != 0)
          continue;
        outside.push_back(map.height_mm(r, c));
      }
    }
    if (outside.size() >= 10) {
      const double median = Percentile(outside, 0.5);
      for (double& v : outside) v = std::abs(v - median);
      t.roughness_mm = 1.4826 * Percentile(outside, 0.5);
    }
    t.depth_to_roughness =
        t.roughness_mm > 0 ? t.mean_depth_mm / t.roughness_mm : std::nan("");
  }
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
  for (int i = 0; i < n; ++i) {
    const double s = s0 + i * step;
    double sum = 0;
    int k = 0;
    for (int j = -m; j <= m; ++j) {
      const double w = m > 0 ? (0.5 * band) * j / m : 0.0;
      const double u = along ? s : fixed, v = along ? fixed + w : s;
      const double x = t.center_x_mm + u * ax - v * ay;
      const double y = t.center_y_mm + u * ay + v * ax;
      const double h = SampleBilinear(map, x, y);
      if (std::isfinite(h)) {
        sum += h;
        ++k;
      }
    }
    p.s_mm[i] = s;
    p.height_mm[i] = k > 0 ? sum / k : std::nan("");
    p.valid_samples[i] = k;
  }
  return p;
}

}  // namespace

WearProfile ExtractCentreline(const HeightMap& map,
                              const Track& track,
                              const ProfileOptions& options) {
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
