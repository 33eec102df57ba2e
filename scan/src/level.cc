#include "wearscar/scan/level.h"

#include <fmt/format.h>
// PCL's RANSAC and plane model from its headers, not from
// libpcl_sample_consensus (see cmake/WearscarDependencies.cmake).
#define PCL_NO_PRECOMPILE
#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_plane.h>

#include <Eigen/Dense>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "plane_count.h"
#include "wearscar/support/check.h"

namespace wearscar::scan {
namespace {

constexpr int kMaxOrder = 3;
constexpr int kMaxTerms = (kMaxOrder + 1) * (kMaxOrder + 2) / 2;
using Terms = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxTerms, 1>;

// Monomials x^i y^j with i + j <= order, in the documented order (no heap).
Terms Monomials(double x, double y, int order) {
  Terms m((order + 1) * (order + 2) / 2);
  double xp[kMaxOrder + 1], yp[kMaxOrder + 1];
  xp[0] = yp[0] = 1.0;
  for (int i = 1; i <= order; ++i) {
    xp[i] = xp[i - 1] * x;
    yp[i] = yp[i - 1] * y;
  }
  int k = 0;
  for (int d = 0; d <= order; ++d) {
    for (int j = 0; j <= d; ++j) m[k++] = xp[d - j] * yp[j];
  }
  return m;
}

// Subtracts the surface from every valid pixel: per row, the polynomial in
// x with y folded in, then Horner's rule along the row.
void SubtractSurface(const Eigen::VectorXd& coef, int order, HeightMap* map) {
  double px[kMaxOrder + 1];
  for (Eigen::Index r = 0; r < map->rows(); ++r) {
    const double y = static_cast<double>(r) * map->dy_mm;
    for (int i = 0; i <= order; ++i) {
      px[i] = 0.0;
      double yj = 1.0;
      for (int j = 0; i + j <= order; ++j) {
        const int d = i + j;
        px[i] += coef[d * (d + 1) / 2 + j] * yj;
        yj *= y;
      }
    }
    float* row = &map->height_mm(r, 0);
    const std::uint8_t* ok = &map->valid(r, 0);
    for (Eigen::Index c = 0; c < map->cols(); ++c) {
      if (!ok[c]) continue;
      const double x = static_cast<double>(c) * map->dx_mm;
      double z = px[order];
      for (int i = order - 1; i >= 0; --i) z = z * x + px[i];
      row[c] -= static_cast<float>(z);
    }
  }
}

}  // namespace

bool LevelOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (polynomial_order < 1 || polynomial_order > 3)
    return fail("polynomial_order must be 1-3");
  if (!(ransac_threshold_mm > 0))
    return fail("ransac_threshold_mm must be > 0");
  if (ransac_iterations < 1) return fail("ransac_iterations must be >= 1");
  if (max_points < 10) return fail("max_points must be >= 10");
  return true;
}

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// PCL's plane model with its inlier count, nearly all of RANSAC's time,
// over the cloud's coordinates held column by column (CountWithinPlane:
// PCL's arithmetic to the bit, several points a step, where PCL's own
// portable count takes one through an index list; docs/performance.md).
// The planes drawn, their counts and the plane kept are PCL's own.
class ColumnPlaneModel final
    : public pcl::SampleConsensusModelPlane<pcl::PointXYZ> {
 public:
  explicit ColumnPlaneModel(const Cloud::ConstPtr& cloud)
      : SampleConsensusModelPlane(cloud) {
    x_.reserve(cloud->size());
    y_.reserve(cloud->size());
    z_.reserve(cloud->size());
    for (const auto& p : *cloud) {
      x_.push_back(p.x);
      y_.push_back(p.y);
      z_.push_back(p.z);
    }
  }

  std::size_t countWithinDistance(const Eigen::VectorXf& model_coefficients,
                                  double threshold) const override {
    // The columns hold the whole cloud in order: PCL's own count for any
    // other index list.
    if (!isModelValid(model_coefficients) || indices_->size() != x_.size()) {
      return SampleConsensusModelPlane::countWithinDistance(model_coefficients,
                                                            threshold);
    }
    const float plane[4] = {model_coefficients[0],
                            model_coefficients[1],
                            model_coefficients[2],
                            model_coefficients[3]};
    return CountWithinPlane(
        x_.data(), y_.data(), z_.data(), x_.size(), plane, threshold);
  }

 private:
  std::vector<float> x_, y_, z_;
};

// Every stride-th valid pixel each way (at most about max_points), as
// points in mm.
Cloud::Ptr SampleCloud(const HeightMap& map, int max_points) {
  const Eigen::Index stride = std::max<Eigen::Index>(
      1,
      static_cast<Eigen::Index>(
          std::sqrt(static_cast<double>(map.ValidCount()) / max_points)));
  Cloud::Ptr cloud(new Cloud);
  // Sized once: growing by doubling wrote every point again.
  cloud->reserve(
      static_cast<std::size_t>(((map.rows() + stride - 1) / stride) *
                               ((map.cols() + stride - 1) / stride)));
  for (Eigen::Index r = 0; r < map.rows(); r += stride) {
    for (Eigen::Index c = 0; c < map.cols(); c += stride) {
      if (!map.valid(r, c)) continue;
      cloud->push_back(pcl::PointXYZ(static_cast<float>(c * map.dx_mm),
                                     static_cast<float>(r * map.dy_mm),
                                     map.height_mm(r, c)));
    }
  }
  return cloud;
}

// The RANSAC plane's inliers (PCL's model draws with a fixed seed:
// deterministic).
std::vector<int> PlaneInliers(const Cloud::Ptr& cloud,
                              const LevelOptions& options,
                              const std::string& source) {
  // PCL prints to stderr ("Sample points too similar or collinear!", once
  // per failed draw): wearscar reports through LevelSummary instead.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  pcl::SampleConsensusModelPlane<pcl::PointXYZ>::Ptr model(
      new ColumnPlaneModel(cloud));
  pcl::RandomSampleConsensus<pcl::PointXYZ> ransac(model);
  ransac.setDistanceThreshold(options.ransac_threshold_mm);
  ransac.setMaxIterations(options.ransac_iterations);
  std::vector<int> inliers;
  if (!ransac.computeModel() ||
      (ransac.getInliers(inliers), inliers.size() < 3)) {
    throw ScanError(fmt::format(
        "{}: no plane found on the unworn area (RANSAC, threshold {} mm)",
        source,
        options.ransac_threshold_mm));
  }
  return inliers;
}

// Least squares of the chosen order, trimmed: start on the RANSAC inliers,
// then keep the points within 2.5 RMS of the current surface (this drops
// the shallow groove edges that a fixed band lets in, and follows curved
// specimens for orders 2-3). The coefficients; the RMS and the inliers in
// `summary`.
Eigen::VectorXd TrimmedSurface(const Cloud& cloud,
                               std::vector<int> inliers,
                               int order,
                               LevelSummary* summary) {
  const int terms = (order + 1) * (order + 2) / 2;
  Eigen::VectorXd coef;
  // The passes' systems in the top rows of one matrix (inliers are points
  // of the cloud: never more rows than it has).
  Eigen::MatrixXd design(static_cast<Eigen::Index>(cloud.size()), terms);
  Eigen::VectorXd heights(static_cast<Eigen::Index>(cloud.size()));
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr;
  std::vector<int> next;
  next.reserve(cloud.size());
  for (int pass = 0; pass < 4; ++pass) {
    const auto rows = static_cast<Eigen::Index>(inliers.size());
    auto a = design.topRows(rows);
    auto b = heights.head(rows);
    for (size_t i = 0; i < inliers.size(); ++i) {
      const auto& p = cloud[inliers[i]];
      a.row(static_cast<Eigen::Index>(i)) =
          Monomials(p.x, p.y, order).transpose();
      b[static_cast<Eigen::Index>(i)] = p.z;
    }
    coef = qr.compute(a).solve(b);
    summary->rms_mm =
        std::sqrt((a * coef - b).squaredNorm() / static_cast<double>(b.size()));
    const double band = std::max(2.5 * summary->rms_mm, 1e-9);
    next.clear();
    for (int i = 0; i < static_cast<int>(cloud.size()); ++i) {
      const auto& p = cloud[i];
      if (std::abs(Monomials(p.x, p.y, order).dot(coef) - p.z) < band)
        next.push_back(i);
    }
    if (next.size() < static_cast<size_t>(terms) || next == inliers) break;
    inliers.swap(next);
  }
  summary->inliers = static_cast<int>(inliers.size());
  return coef;
}

}  // namespace

LevelSummary LevelHeightMap(HeightMap* map, const LevelOptions& options) {
  WEARSCAR_CHECK(map != nullptr && map->IsConsistent(),
                 "LevelHeightMap needs a consistent map");
  std::string why;
  if (!options.IsValid(&why)) throw ScanError("level options: " + why);
  LevelSummary summary;
  summary.order = options.polynomial_order;
  const Eigen::Index valid = map->ValidCount();
  if (valid < 10) {
    throw ScanError(
        fmt::format("{}: {} valid pixels; at least 10 are needed to level",
                    map->metadata.source,
                    valid));
  }
  const Cloud::Ptr cloud = SampleCloud(*map, options.max_points);
  summary.points_used = static_cast<int>(cloud->size());
  const int order = options.polynomial_order;
  summary.coefficients =
      TrimmedSurface(*cloud,
                     PlaneInliers(cloud, options, map->metadata.source),
                     order,
                     &summary);
  SubtractSurface(summary.coefficients, order, map);
  summary.message =
      fmt::format("order {} fitted on {} of {} points, RMS {:.2g} mm",
                  order,
                  summary.inliers,
                  summary.points_used,
                  summary.rms_mm);
  return summary;
}

bool SpikeOptions::IsValid(std::string* why) const {
  if ((kernel != 3 && kernel != 5) || !(threshold_mm > 0)) {
    if (why) *why = "the spike kernel must be 3 or 5 and the threshold > 0";
    return false;
  }
  return true;
}

int RemoveSpikes(HeightMap* map, const SpikeOptions& options) {
  WEARSCAR_CHECK(map != nullptr && map->IsConsistent(),
                 "RemoveSpikes needs a consistent map");
  std::string why;
  if (!options.IsValid(&why)) throw ScanError("spike options: " + why);
  const int rows = static_cast<int>(map->rows()),
            cols = static_cast<int>(map->cols());
  // OpenCV views the row-major Eigen memory; NaN is replaced by 0 (the
  // levelled reference) for the median only.
  cv::Mat z(rows, cols, CV_32F);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      z.at<float>(r, c) = map->valid(r, c) ? map->height_mm(r, c) : 0.0f;
    }
  }
  cv::Mat median;
  cv::medianBlur(z, median, options.kernel == 3 ? 3 : 5);
  int removed = 0;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!map->valid(r, c)) continue;
      if (std::abs(map->height_mm(r, c) - median.at<float>(r, c)) >
          options.threshold_mm) {
        map->height_mm(r, c) = NAN;
        map->valid(r, c) = 0;
        ++removed;
      }
    }
  }
  return removed;
}

HeightMap::Heights FilledForDisplay(const HeightMap& map) {
  const int rows = static_cast<int>(map.rows()),
            cols = static_cast<int>(map.cols());
  cv::Mat z(rows, cols, CV_32F), mask(rows, cols, CV_8U), out;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const bool ok = map.valid(r, c);
      z.at<float>(r, c) = ok ? map.height_mm(r, c) : 0.0f;
      mask.at<std::uint8_t>(r, c) = ok ? 0 : 255;
    }
  }
  cv::inpaint(z, mask, out, 3, cv::INPAINT_TELEA);
  HeightMap::Heights filled(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) filled(r, c) = out.at<float>(r, c);
  }
  return filled;
}

}  // namespace wearscar::scan
