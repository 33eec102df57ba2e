#include "wearscar/scan/preview.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "file_io.h"
#include "wearscar/scan/level.h"
#include "wearscar/support/check.h"
#include "wearscar/support/numbers.h"
#include "wearscar/support/png.h"
#include "wearscar/support/robust_stats.h"

namespace wearscar::scan {
namespace {

using support::kPi;

}  // namespace

namespace {

std::string EncodePng(const cv::Mat& image, const std::string& source) {
  std::string why;
  std::string png = support::EncodePng(image.cols,
                                       image.rows,
                                       3,
                                       /*bgr=*/true,
                                       image.data,
                                       static_cast<long>(image.step),
                                       {},
                                       &why);
  if (png.empty()) {
    throw ScanError(
        fmt::format("{}: preview: PNG encoding failed: {}", source, why));
  }
  return png;
}

}  // namespace

bool PreviewOptions::IsValid(std::string* why) const {
  if (max_width_px < 16 ||
      !(low_percentile >= 0 && low_percentile < high_percentile &&
        high_percentile <= 1)) {
    if (why) *why = "the width must be >= 16 px and 0 <= low < high <= 1";
    return false;
  }
  return true;
}

namespace {

// The colour scale's ends: percentiles of a subsample of the valid
// heights.
std::pair<float, float> HeightRange(const HeightMap& map,
                                    const PreviewOptions& o) {
  std::vector<float> values;
  const Eigen::Index stride =
      std::max<Eigen::Index>(1, map.height_mm.size() / 200000);
  for (Eigen::Index i = 0; i < map.height_mm.size(); i += stride) {
    if (map.valid.data()[i]) values.push_back(map.height_mm.data()[i]);
  }
  float lo = -1, hi = 1;
  if (!values.empty()) {
    auto at = [&](double q) {
      const size_t k = std::min(values.size() - 1,
                                static_cast<size_t>(q * (values.size() - 1)));
      std::nth_element(values.begin(), values.begin() + k, values.end());
      return values[k];
    };
    lo = at(o.low_percentile);
    hi = at(o.high_percentile);
    if (!(hi > lo)) hi = lo + 1e-6f;
  }
  return {lo, hi};
}

// The map in viridis between lo and hi, grey where not measured.
cv::Mat Colour(const HeightMap& map, float lo, float hi) {
  const int rows = static_cast<int>(map.rows()),
            cols = static_cast<int>(map.cols());
  cv::Mat grey(rows, cols, CV_8U);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const float z = map.height_mm(r, c);
      const float t = map.valid(r, c) ? (z - lo) / (hi - lo) : 0.0f;
      grey.at<std::uint8_t>(r, c) =
          static_cast<std::uint8_t>(std::clamp(t, 0.0f, 1.0f) * 255.0f);
    }
  }
  cv::Mat image;
  cv::applyColorMap(grey, image, cv::COLORMAP_VIRIDIS);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!map.valid(r, c))
        image.at<cv::Vec3b>(r, c) = cv::Vec3b(128, 128, 128);
    }
  }
  return image;
}

// The track's outline (white), axis and centre (red) on an image of the
// map scaled by `scale`.
void DrawTrack(const HeightMap& map,
               const Track& track,
               double scale,
               cv::Mat* image) {
  const double px = scale / map.dx_mm, py = scale / map.dy_mm;
  const double th = track.angle_deg * kPi / 180.0;
  const double ax = std::cos(th), ay = std::sin(th);
  auto to_px = [&](double s, double w) {
    const double x = track.centre_x_mm + s * ax - w * ay;
    const double y = track.centre_y_mm + s * ay + w * ax;
    return cv::Point2d(x * px, y * py);
  };
  const int thick = std::max(1, image->cols / 500);
  const double hl = 0.5 * track.length_mm, hw = 0.5 * track.width_mm;
  const cv::Point2d corners[4] = {
      to_px(-hl, -hw), to_px(hl, -hw), to_px(hl, hw), to_px(-hl, hw)};
  for (int i = 0; i < 4; ++i) {
    cv::line(*image,
             corners[i],
             corners[(i + 1) % 4],
             cv::Scalar(255, 255, 255),
             thick,
             cv::LINE_AA);
  }
  cv::line(*image,
           to_px(-hl, 0),
           to_px(hl, 0),
           cv::Scalar(0, 0, 255),
           thick,
           cv::LINE_AA);
  cv::drawMarker(*image,
                 to_px(0, 0),
                 cv::Scalar(0, 0, 255),
                 cv::MARKER_CROSS,
                 12 * thick,
                 thick);
}

}  // namespace

std::string EncodeTrackPreviewPng(const HeightMap& map,
                                  const Track& track,
                                  const PreviewOptions& o) {
  WEARSCAR_CHECK(map.IsConsistent(), "a preview needs a consistent map");
  std::string why;
  if (!o.IsValid(&why)) throw ScanError("preview options: " + why);
  const int rows = static_cast<int>(map.rows()),
            cols = static_cast<int>(map.cols());
  if (rows < 2 || cols < 2 || o.max_width_px < 16) {
    throw ScanError(fmt::format(
        "{}: preview: map of {} x {} pixels (or width limit {}) too small",
        map.metadata.source,
        cols,
        rows,
        o.max_width_px));
  }
  const auto [lo, hi] = HeightRange(map, o);
  cv::Mat image = Colour(map, lo, hi);
  double scale = 1.0;
  if (cols > o.max_width_px) {
    scale = static_cast<double>(o.max_width_px) / cols;
    cv::resize(image, image, cv::Size(), scale, scale, cv::INTER_AREA);
  }
  if (track.length_mm > 0) DrawTrack(map, track, scale, &image);
  return EncodePng(image, map.metadata.source);
}

void WriteTrackPreviewPng(const HeightMap& levelled,
                          const Track& track,
                          const std::string& path,
                          const PreviewOptions& options) {
  internal::WriteFileAtomically(
      path, EncodeTrackPreviewPng(levelled, track, options));
}

}  // namespace wearscar::scan
