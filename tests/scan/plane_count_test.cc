// RANSAC's inlier count by columns (CountWithinPlane, which the
// levelling's plane model uses) against PCL's own portable count, point
// for point: on points placed a few float steps either side of the
// threshold, where any other order of the sum would count differently,
// and on the clouds of real scans with planes drawn from their points.
#define PCL_NO_PRECOMPILE
#include "plane_count.h"

#include <gtest/gtest.h>
#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/sac_model_plane.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "wearscar/samples/virtual_tribometer.h"
#include "wearscar/scan/read_scan.h"

namespace wearscar::scan {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// PCL's plane model, its portable count made callable.
class PclPlane : public pcl::SampleConsensusModelPlane<pcl::PointXYZ> {
 public:
  explicit PclPlane(const Cloud::ConstPtr& cloud)
      : SampleConsensusModelPlane(cloud) {
    // Collinear draws are skipped quietly.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  std::size_t Count(const Eigen::VectorXf& plane, double threshold) const {
    return countWithinDistanceStandard(plane, threshold);
  }
};

struct Columns {
  std::vector<float> x, y, z;
  explicit Columns(const Cloud& cloud) {
    for (const auto& p : cloud) {
      x.push_back(p.x);
      y.push_back(p.y);
      z.push_back(p.z);
    }
  }
  std::size_t Count(const Eigen::VectorXf& plane, double threshold) const {
    const float m[4] = {plane[0], plane[1], plane[2], plane[3]};
    return CountWithinPlane(
        x.data(), y.data(), z.data(), x.size(), m, threshold);
  }
};

// The valid pixels of a map as RANSAC gets them, every `stride`th.
Cloud::Ptr CloudOf(const HeightMap& m, int stride) {
  Cloud::Ptr cloud(new Cloud);
  for (Eigen::Index r = 0; r < m.rows(); r += stride) {
    for (Eigen::Index c = 0; c < m.cols(); c += stride) {
      if (!m.valid(r, c)) continue;
      cloud->push_back(pcl::PointXYZ(static_cast<float>(c * m.dx_mm),
                                     static_cast<float>(r * m.dy_mm),
                                     m.height_mm(r, c)));
    }
  }
  return cloud;
}

// Planes through three points of the cloud, as RANSAC draws them.
std::vector<Eigen::VectorXf> PlanesThrough(const PclPlane& model,
                                           std::size_t points,
                                           int count,
                                           unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(points) - 1);
  std::vector<Eigen::VectorXf> planes;
  while (static_cast<int>(planes.size()) < count) {
    const pcl::Indices three = {pick(rng), pick(rng), pick(rng)};
    Eigen::VectorXf plane;
    if (model.computeModelCoefficients(three, plane)) planes.push_back(plane);
  }
  return planes;
}

TEST(PlaneCount, PointsAFewFloatStepsFromTheThresholdCountAsInPcl) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 10.0f), v(-1.0f, 1.0f);
  const double threshold = 0.005;  // not a float: the comparison in double
  long differed_from_other_order = 0, compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // A plane a x + b y + c z + d = 0 with a unit normal, tilted.
    Eigen::Vector3f n(0.05f * v(rng), 0.05f * v(rng), 1.0f);
    n.normalize();
    Eigen::VectorXf plane(4);
    plane << n[0], n[1], n[2], 0.3f * v(rng);
    // Points whose distance is +-threshold, then moved a few float steps
    // along z either way.
    Cloud::Ptr cloud(new Cloud);
    for (int i = 0; i < 400; ++i) {
      const float x = u(rng), y = u(rng);
      const float side = i % 2 ? 1.0f : -1.0f;
      float z = (static_cast<float>(side * threshold) - plane[0] * x -
                 plane[1] * y - plane[3]) /
                plane[2];
      for (int step = 0; step < (i / 2) % 7; ++step)
        z = std::nextafter(z, (i / 14) % 2 ? INFINITY : -INFINITY);
      cloud->push_back(pcl::PointXYZ(x, y, z));
    }
    const PclPlane pcl_model(cloud);
    const Columns columns(*cloud);
    const std::size_t pcl_count = pcl_model.Count(plane, threshold);
    EXPECT_EQ(columns.Count(plane, threshold), pcl_count) << "trial " << trial;
    ++compared;
    // The same points summed in another order: the boundary is fine
    // enough that the order shows (what makes this test able to fail).
    std::size_t other = 0;
    for (const auto& p : *cloud) {
      const float s =
          ((plane[0] * p.x + plane[1] * p.y) + plane[2] * p.z) + plane[3];
      other += std::abs(s) < threshold ? 1 : 0;
    }
    differed_from_other_order += other != pcl_count;
  }
  EXPECT_GT(differed_from_other_order, compared / 4)
      << differed_from_other_order << " of " << compared;
}

TEST(PlaneCount, PlanesDrawnOnAScansCloudCountAsInPcl) {
  samples::SimulationOptions o = samples::PaperCase("B-RL-L");
  o.cycles = 20;
  const samples::SimulatedTest t = samples::Simulate(o);
  const Cloud::Ptr cloud = CloudOf(t.scan, 3);
  const PclPlane model(cloud);
  const Columns columns(*cloud);
  for (const Eigen::VectorXf& plane :
       PlanesThrough(model, cloud->size(), 200, 1)) {
    for (double threshold : {0.001, 0.005, 0.02})
      ASSERT_EQ(columns.Count(plane, threshold), model.Count(plane, threshold))
          << plane.transpose() << " threshold " << threshold;
  }
}

TEST(PlaneCount, PlanesDrawnOnRealScansCountAsInPcl) {
  const std::string shared = WEARSCAR_SHARED_DATA;
  if (!std::filesystem::exists(shared)) {
    GTEST_SKIP() << "../shared/data is absent: real instrument files not "
                    "available";
  }
  for (const char* file : {"keyence/vr6100_test_1.zon",
                           "keyence/60um_50E_30-50shots_depthpro.vk6",
                           "x3p/ISO5436-sample4_bin.x3p",
                           "other/sur-3.sur",
                           "other/plu-1.plu"}) {
    SCOPED_TRACE(file);
    const HeightMap m = ReadScan(shared + "/" + file);
    const int stride =
        std::max(1, static_cast<int>(std::sqrt(m.ValidCount() / 60000.0)));
    const Cloud::Ptr cloud = CloudOf(m, stride);
    const PclPlane model(cloud);
    const Columns columns(*cloud);
    for (const Eigen::VectorXf& plane :
         PlanesThrough(model, cloud->size(), 100, 2)) {
      ASSERT_EQ(columns.Count(plane, 0.005), model.Count(plane, 0.005))
          << plane.transpose();
    }
  }
}

}  // namespace
}  // namespace wearscar::scan
