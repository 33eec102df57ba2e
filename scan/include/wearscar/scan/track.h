#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "wearscar/scan/height_map.h"

namespace wearscar::scan {

// The worn track: an axis through its centre. The along-track coordinate s
// runs along (cos angle, sin angle) from the centre; across w runs at +90°.
struct Track {
  double centre_x_mm = 0.0;
  double centre_y_mm = 0.0;
  double angle_deg = 0.0;  // in (-90, 90]
  double length_mm = 0.0;
  double width_mm = 0.0;  // where the depth exceeds the detection threshold
  double max_depth_mm = 0.0;
  // Mean depth along the axis over the central 80% of the length (the
  // groove bottom where the stroke is fully worn).
  double mean_depth_mm = 0.0;
  double volume_mm3 = 0.0;  // worn volume below the reference
  int pixels = 0;
  double elongation = 0.0;  // sqrt of the PCA eigenvalue ratio
  // Confidence: the roughness of the surface outside the track (robust sd,
  // 1.4826 MAD of the levelled heights) and the mean depth over it. A
  // depression barely deeper than the roughness, or barely elongated, may
  // be texture rather than wear (low_confidence, with the reason).
  double roughness_mm = 0.0;
  double depth_to_roughness = 0.0;
  bool low_confidence = false;
  bool manual = false;
  // Some of its pixels lie on the field's border: the track may run on
  // beyond the scan, its length and width being the field's.
  bool reaches_edge = false;
  // Where the track lies is known from its outline: found (not placed by
  // hand), with confidence, inside the field.
  bool PlaceKnown() const {
    return !manual && !reaches_edge && !low_confidence;
  }
  std::string message = "not run";
  // How it was found (pixels, elongation, threshold, confidence) or placed.
  std::string BriefReport() const { return message; }
};

struct TrackOptions {
  double smoothing_sigma_px = 2.0;
  // A pixel belongs to the track when it lies deeper than
  // max(min_depth_mm, depth_fraction * the depth_quantile of the depths).
  double min_depth_mm = 0.004;
  double depth_fraction = 0.25;
  double depth_quantile = 0.995;
  int morphology_px = 5;        // open then close with an ellipse
  double min_elongation = 2.0;  // length/width of an accepted component
  int min_component_px = 10;    // smaller components are not candidates
  // Length and width of the track between these quantiles of its pixels'
  // positions along and across the axis (robust to stray pixels).
  double length_quantile = 0.002;
  double width_quantile = 0.005;
  // A track is found with low confidence below these (a warning).
  double confident_depth_to_roughness = 3.0;
  double confident_elongation = 3.0;
  // Manual placement instead of detection (angle in degrees).
  bool manual = false;
  double centre_x_mm = 0.0, centre_y_mm = 0.0, angle_deg = 0.0;
  double manual_length_mm = 0.0;  // 0 = to the edges of the field

  bool IsValid(std::string* why) const;
};

// Finds the largest elongated depression of a levelled map (smoothing,
// threshold, morphology, connected components, PCA). Throws NoTrackError
// (a ScanError) when no track is found.
// Requires levelled.IsConsistent().
Track FindTrack(const HeightMap& levelled, const TrackOptions& options = {});

// No track in the map: everything that does not need one still stands.
class NoTrackError : public ScanError {
 public:
  using ScanError::ScanError;
};

// Heights along the track axis.
struct WearProfile {
  Eigen::VectorXd s_mm;           // along the axis from the track centre
  Eigen::VectorXd height_mm;      // band average; NaN where no valid sample
  Eigen::VectorXi valid_samples;  // samples behind each point
  double band_width_mm = 0.0;
  double step_mm = 0.0;
  // The variance of height_mm that the surface's texture across the band
  // leaves (the band's two halves' difference over the profile, a
  // quarter of its variance): 0 without a band.
  double noise_variance_mm2 = 0.0;
};

// A quarter of the variance of the two halves' difference, per point (NaN
// where a half is missing): the noise variance of their mean.
double HalvesNoiseVariance(const Eigen::VectorXd& first_half,
                           const Eigen::VectorXd& second_half);

struct ProfileOptions {
  double step_mm = 0.0;        // 0 = the scan pitch
  double band_width_mm = 0.1;  // averaged across the track
  double extend_mm = 0.0;      // beyond the track ends
  bool IsValid(std::string* why) const;
};

// Centreline profile: bilinear samples (NaN-aware) averaged over the band.
// Requires levelled.IsConsistent().
WearProfile ExtractCentreline(const HeightMap& levelled,
                              const Track& track,
                              const ProfileOptions& options = {});

// Cross-section across the track at along-track position s (mm), over
// +-half_width_mm.
WearProfile ExtractCrossSection(const HeightMap& levelled,
                                const Track& track,
                                double s_mm,
                                double half_width_mm,
                                double step_mm = 0.0);

// Bilinear height at (x, y) mm; NaN when any of the four pixels is invalid
// or the point is outside.
double SampleBilinear(const HeightMap& map, double x_mm, double y_mm);

}  // namespace wearscar::scan
