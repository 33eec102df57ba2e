#pragma once

#include <Eigen/Core>
#include <string>

#include "wearscar/scan/height_map.h"

namespace wearscar::scan {

struct LevelOptions {
  // Polynomial reference surface: 1 = plane, 2 or 3 = curved specimen.
  int polynomial_order = 1;
  // RANSAC plane: inlier distance, mm (the worn track lies far below).
  double ransac_threshold_mm = 0.005;
  int ransac_iterations = 500;
  // Points given to RANSAC and the least-squares fit (subsampled evenly).
  int max_points = 60000;
  std::uint64_t seed = 42;

  bool IsValid(std::string* why) const;
};

// The fitted reference: z = sum c_ij x^i y^j (x, y in mm from the map's
// origin), i + j <= order, coefficients in the order (0,0), (1,0), (0,1),
// (2,0), (1,1), (0,2), ...
struct LevelSummary {
  int order = 1;
  Eigen::VectorXd coefficients;
  int inliers = 0;  // points within the threshold of the RANSAC plane
  int points_used = 0;
  double rms_mm = 0.0;  // residual RMS on the inliers
  std::string message = "not run";
  // "order 1 on 57605 of 59200 points, RMS 0.00027 mm" (Ceres style).
  std::string BriefReport() const { return message; }
  // Plane form for order 1: z = z0 + dzdx x + dzdy y.
  double z0_mm() const {
    return coefficients.size() > 0 ? coefficients[0] : 0.0;
  }
  double dzdx() const {
    return coefficients.size() > 1 ? coefficients[1] : 0.0;
  }
  double dzdy() const {
    return coefficients.size() > 2 ? coefficients[2] : 0.0;
  }
};

// Fits the reference on the unworn area (PCL RANSAC plane, then least
// squares of the chosen order on its inliers, mask-aware) and subtracts it
// in place. Throws ScanError when too few valid pixels exist.
// Requires map != nullptr and map->IsConsistent().
LevelSummary LevelHeightMap(HeightMap* map, const LevelOptions& options = {});

struct SpikeOptions {
  int kernel = 5;              // median window, pixels (3 or 5)
  double threshold_mm = 0.01;  // |z - median| beyond this is a spike
  bool IsValid(std::string* why) const;
};

// Marks spikes invalid (NaN); returns how many. Run after levelling.
// Requires map != nullptr and map->IsConsistent(). Throws ScanError for
// invalid options.
int RemoveSpikes(HeightMap* map, const SpikeOptions& options = {});

// A copy with invalid pixels filled for display only (OpenCV inpainting);
// the analysis keeps NaN.
HeightMap::Heights FilledForDisplay(const HeightMap& map);

}  // namespace wearscar::scan
