#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>

#include "wearscar/force/cycles.h"
#include "wearscar/force/force_record.h"
#include "wearscar/force/slope.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/fit_mu.h"
#include "wearscar/scan/track.h"

namespace wearscar::fusion {

// The force-side profile: spring displacement f = P / S along the plate
// coordinate, averaged over a range of cycles in bins of x (gross slip only).
struct ForceProfile {
  Eigen::VectorXd x_mm;
  Eigen::VectorXd forward_mm;  // NaN where a bin is empty
  Eigen::VectorXd reverse_mm;
  Eigen::VectorXd
      mean_mm;  // mean of the two directions (either when one is NaN)
  int first_cycle = 0, last_cycle = 0;  // inclusive range used
  // Variance of mean_mm that the noise leaves, averaged over the bins: per
  // bin and direction, from the second differences of the cycles' means
  // (the track's change over the cycles is no noise), over the cycles.
  double noise_variance_mm2 = 0.0;
};

struct ForceProfileOptions {
  int cycles = 50;  // the last N cycles (closest in time to a post-test scan)
  int first_cycle = -1;  // explicit range instead, when >= 0
  int last_cycle = -1;
  double step_mm = 0.01;  // bin width
  bool IsValid(std::string* why) const;
};

ForceProfile ComputeForceProfile(const force::ForceRecord& record,
                                 const force::CycleSet& cycles,
                                 double spring_n_per_mm,
                                 const ForceProfileOptions& options = {});

// The same from the record's depth channel (height = -depth), per
// direction. Throws FusionError without one.
ForceProfile ComputeDepthProfile(const force::ForceRecord& record,
                                 const force::CycleSet& cycles,
                                 const ForceProfileOptions& options = {},
                                 double depth_sign = 1.0);

// The sliding path's height from the friction alone, for rigs whose P
// does not follow the track (a dead weight): on the wear-scar model the
// two directions at the same x see Q/P = tan(theta + s phi), k = tan
// theta, mu = tan phi, so theta is the mean of atan(Q/P) forward and
// reverse; k binned over the compared cycles' gross slip where both
// directions slid, integrated along x, about its mean (forward_mm =
// reverse_mm = mean_mm). Circular for a verdict on its own (an effect that
// is the same in both directions enters it as slope); it aligns the scan
// and is compared with it. Throws FusionError when too few positions were
// slid both ways.
ForceProfile ComputeFrictionProfile(const force::ForceRecord& record,
                                    const force::CycleSet& cycles,
                                    const ForceProfileOptions& options = {});

// Plate x maps to the scan's along-track coordinate s = flip * x + shift.
struct Alignment {
  double shift_mm = 0.0;
  bool flipped = false;
  double correlation = 0.0;  // normalised cross-correlation at the optimum
  // The same corrected for the noise left in the force profile (Spearman's
  // disattenuation, r / sqrt(1 - noise variance / variance of f), at most
  // 1): what the correlation would be with a noise-free force profile.
  double correlation_noise_corrected = 0.0;
  double correlation_forward = 0.0, correlation_reverse = 0.0;
  double scale = 0.0;  // least squares f = scale * h + offset
  double offset_mm = 0.0;
  // std(f) / std(h) over the overlap, f's variance less what its noise
  // contributes (ForceProfile::noise_variance_mm2)
  double amplitude_ratio = 0.0;
  // Its 95% interval (delete-a-block jackknife along the overlap); NaN when
  // the overlap is too short for the blocks.
  double amplitude_ratio_low = std::numeric_limits<double>::quiet_NaN();
  double amplitude_ratio_high = std::numeric_limits<double>::quiet_NaN();
  int overlap_samples = 0;
  // The waviness: both profiles less their running mean over
  // AlignOptions::waviness_window_mm, the groove's envelope (common to
  // every track of a case) removed, its rings and texture (each
  // specimen's own) kept. Its correlation corrected for the force
  // profile's noise (at most 1), and the force profile's waviness variance
  // over that noise's: what tells this specimen's scan from another's.
  double waviness_correlation = std::numeric_limits<double>::quiet_NaN();
  double waviness_to_noise = std::numeric_limits<double>::quiet_NaN();
  // The waviness's best correlation (corrected as waviness_correlation)
  // with the scan shifted elsewhere: more than a waviness window from the
  // best shift, as far as the profiles overlap on min_overlap_fraction
  // (FindWavinessRunnerUp; NaN where not sought).
  // Rings of one width line up again a period away; where they do, another
  // specimen whose rings fall a fraction of a period apart lines up as
  // well as this one's (ScanIdentity::lines_up_twice), and only
  // the track's place against the stroke tells them apart.
  double waviness_runner_up = std::numeric_limits<double>::quiet_NaN();
  double waviness_runner_up_shift_mm = std::numeric_limits<double>::quiet_NaN();
  std::string message = "not run";
  // The search's outcome: shift, flip, correlation, scale, points.
  std::string BriefReport() const { return message; }

  // The two frames (COLMAP's a_from_b naming): the plate's x along the
  // stroke (the force record's) and the scan's s along the track from its
  // centre. s = scan_from_plate(x) = (flipped ? -x : x) + shift_mm.
  double ScanFromPlate(double x_mm) const {
    return (flipped ? -x_mm : x_mm) + shift_mm;
  }
  double PlateFromScan(double s_mm) const {
    return flipped ? shift_mm - s_mm : s_mm - shift_mm;
  }
};

struct AlignOptions {
  double max_shift_mm = 1.5;
  double step_mm = 0.01;              // resampling grid
  double min_overlap_fraction = 0.6;  // of the force profile's valid points
  bool allow_flip = true;
  int ratio_blocks = 10;  // jackknife blocks for the amplitude ratio's interval
  double waviness_window_mm = 0.4;  // Alignment::waviness_correlation
  // The waviness's shortest wavelength: P/S's features shorter than a
  // twentieth of a millimetre are no track's (a sphere's contact spans a
  // millimetre) but a sensor's resolution over positions each cycle
  // samples alike.
  double waviness_shortest_mm = 0.05;
  bool IsValid(std::string* why) const;
};

// Normalised cross-correlation over shift and orientation, sub-sample shift
// by a parabola through the peak, least-squares scale on the overlap.
// Throws FusionError when the profiles cannot overlap enough.
Alignment AlignProfiles(const ForceProfile& force_profile,
                        const scan::WearProfile& scan_profile,
                        const AlignOptions& options = {});

// Alignment::waviness_runner_up and its shift for an alignment made by
// AlignProfiles of the same profiles (a search over every shift: asked
// for only where the track's place against the stroke is not known).
void FindWavinessRunnerUp(const ForceProfile& force_profile,
                          const scan::WearProfile& scan_profile,
                          const AlignOptions& options,
                          Alignment* alignment);

// Slope of the sliding path from the scan in plate coordinates,
// k_scan(x) = dh/dx, with the chosen derivative (window in scan samples).
// Only the scan over the stroke [stroke_min_mm, stroke_max_mm] (plate x, the
// sphere centre's excursion) is differentiated, with Savitzky-Golay windows
// shifted inward at its ends: the groove's end walls beyond the stroke,
// which the sphere never climbs, would otherwise tilt k near the reversals
// and bias mu-hat low (by 0.002 on a 0.2 mm deep track). The profile covers
// the stroke; the scan sample just beyond each end repeats the end's slope.
PlateProfile ScanSlopeInPlate(
    const scan::WearProfile& scan_profile,
    const Alignment& alignment,
    const force::DerivativeOptions& derivative,
    double stroke_min_mm = -std::numeric_limits<double>::infinity(),
    double stroke_max_mm = std::numeric_limits<double>::infinity());

// The scan profile resampled at plate coordinates x (NaN outside).
Eigen::VectorXd ScanHeightAtPlate(
    const scan::WearProfile& scan_profile,
    const Alignment& alignment,
    const Eigen::Ref<const Eigen::VectorXd>& x_mm);

}  // namespace wearscar::fusion
