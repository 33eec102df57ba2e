#pragma once
// What the comparison of the two sides finds (MismatchReport): read by the
// rules that judge it (the verdict, the scan's identity, the screen), each
// in a file of its own, none of which this header includes.

#include <cmath>
#include <memory>
#include <string>

#include "wearscar/fusion/analysis.h"
#include "wearscar/fusion/spring_check.h"

namespace wearscar::fusion {

struct ScanIdentity;   // scan_identity.h
struct ScreenFinding;  // screen.h

// Differences between the force-side and the scan-side view of one test,
// over a range of cycles (the paper's Fig. 8, 14 and 16 quantities).
struct MismatchReport {
  bool has_scan = false;
  // What the scan's profile was compared with, for the verdict's words.
  std::string force_profile_name = "the spring displacement";
  // Where the force side's k came from: "P" (P/S) or "the depth"
  // (ProfileDecision::ChannelName), and whether mu-hat with it is judged
  // (not with the friction's circular profile: the scan's k is).
  std::string force_slope_name = "P";
  bool force_slope_judged = true;
  int first_cycle = 0, last_cycle = 0;
  double correlation = 0.0;                  // aligned profiles
  double correlation_noise_corrected = 0.0;  // Alignment's
  // The waviness's (Alignment::waviness_*): the scan's identity, judged
  // against P/S or the depth channel's profile, whose errors are their
  // noise (not the friction's profile, integrated from the friction).
  double waviness_correlation = 0.0, waviness_to_noise = 0.0;
  // Alignment::waviness_runner_up and its shift: the waviness lining up
  // elsewhere as well.
  double waviness_runner_up = NAN, waviness_runner_up_shift_mm = NAN;
  bool identity_judged = false;
  // The worn track's length and width in the scan (NaN: placed by hand,
  // running off the scanned field, or found with low confidence),
  // the scan's pixel, and this test's stroke (peak to peak): a sphere
  // sliding over the stroke wears a track from the stroke's ends to at
  // most its contact's radius beyond each.
  double track_length_mm = NAN, track_width_mm = NAN, scan_pixel_mm = 0.0;
  double stroke_mm = NAN;
  // Where the alignment put the track's centre against the stroke's (the
  // shift less the one that puts one on the other), mm; NaN where the
  // track's length is not judged. This specimen's track lies where the
  // stroke ran; another specimen's can match P/S's waviness only shifted.
  double centre_offset_mm = NAN;
  // The same from the sphere's reversals (the end walls fitted with its
  // radius, scan::FitTrackEnds): the stroke's centre against theirs (one
  // wall and half the stroke where the field cut the other), mm, NaN
  // without a wall; the walls found (0-2) and, with both, the stroke they
  // span.
  double ends_offset_mm = NAN, ends_stroke_mm = NAN;
  int walls = 0;
  double amplitude_ratio = 0.0;     // std(f) / std(h)
  double k_rms_difference = 0.0;    // RMS of k_force - k_scan over gross slip
  Statistic mu_force, mu_scan;      // mu-hat with each slope
  Statistic cost_force, cost_scan;  // J with each slope
  Statistic mu_mean, mu_energy;     // classic methods
  double mu_force_minus_scan = 0.0;
  Statistic mu_force_minus_mean;    // per-cycle differences, Fig. 16 (a)
  Statistic mu_force_minus_energy;  // Fig. 16 (b)
  // J split into its noise floor and the excess noise does not explain,
  // with k from P and with k from the scan (SplitCost).
  CostSplit split_force, split_scan;
  // mu-hat (the slope the verdict judges) minus mu_energy, with its 95%
  // interval over the compared cycles.
  Interval method_difference;
  // The amplitude ratio's 95% interval (Alignment).
  double amplitude_ratio_low = 0.0, amplitude_ratio_high = 0.0;
  // Whether P/S is the path the friction shows at the stiffness used (k
  // from P only): an elastic part, a stiffness the data contradict, or
  // one they cannot tell from an elastic part. The spring check's analysis
  // unit (fusion/units) runs it on the comparison; this is its result,
  // shared (null before it ran, or where it did not). Spring() reads it,
  // an unjudged check where there is none.
  std::shared_ptr<const SpringCheck> spring_check;
  const SpringCheck& Spring() const {
    static const SpringCheck kNone{};
    return spring_check ? *spring_check : kNone;
  }
  // Whether the scan is this test's and this specimen's: the scan
  // identity's analysis unit (fusion/units) decides it on the comparison
  // (JudgeScanIdentity); this is its result, shared (null before it ran
  // or without a scan). Identity() reads it, nothing doubted where none.
  std::shared_ptr<const ScanIdentity> scan_identity;
  const ScanIdentity& Identity() const;  // scan_identity.cc
  // The screen's finding (screen.h), decided by its unit before the
  // verdict; shared (null before it ran). Screen() reads it, nothing
  // screened where none.
  std::shared_ptr<const ScreenFinding> screen;
  const ScreenFinding& Screen() const;  // screen.cc
  // mu-hat with the force side's k is what the verdict judges and the
  // headline quotes: fitted, and not scaled by a spring the data
  // contradict or cannot tell from an elastic part (then the scan's k is,
  // which needs neither).
  bool JudgesForceSlope() const {
    const SpringCheck& spring = Spring();
    return cost_force.count > 0 &&
           !((spring.contradicted || spring.undecided) && cost_scan.count > 0);
  }
};

}  // namespace wearscar::fusion
