// The scan side of the pipeline: the scan aligned with the force side's
// profile (the sphere's path or the centreline, ChoosePath) and its slope
// over the stroke (mu-hat with it: the unit "mu_fit_scan").

#include "scan_side.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "wearscar/fusion/compare_slopes.h"
#include "wearscar/fusion/forward_model.h"

namespace wearscar::fusion::internal {
namespace {

// How closely an alignment's scan profile follows the force side's: the
// waviness's correlation where it stands above its noise (what tells one
// track from another), else the whole profiles'.
double Follows(const Alignment& a, const VerdictOptions& v) {
  return a.waviness_to_noise >= v.min_waviness_to_noise &&
                 std::isfinite(a.waviness_correlation)
             ? a.waviness_correlation
             : a.correlation_noise_corrected;
}

// The premise that a rigid sphere of the radius given rides the scanned
// track, checked on which path the force side follows: the sphere's (kept
// unless the centreline follows it closer by more than `margin`) or the
// centreline's (a sphere that conforms to the track: k from the
// centreline, said).
void ChoosePath(const FuseOptions& options, ScanAnalysis* s) {
  Premise& p = s->rigid_sphere;
  p.rule = "k from the scan";
  p.statement = fmt::format(
      "a rigid sphere of radius {:g} mm rides the scanned track (its path, "
      "not the centreline, tilts the contact)",
      options.sphere.radius_mm);
  p.otherwise =
      "k from the scan is the centreline's slope: the force side's path "
      "follows the centreline, as a sphere that conforms to the track does";
  if (options.sphere.radius_mm <= 0) {
    p.evidence = "not checked: --sphere-radius 0 takes the centreline";
    s->centreline_used = true;
    return;
  }
  Alignment centre;
  try {
    centre = AlignProfiles(s->force_profile, s->centreline, options.align);
  } catch (const FusionError&) {
    p.state = Premise::State::kHeld;
    p.evidence = "the centreline could not be aligned";
    return;
  }
  constexpr double kMargin = 0.02;
  const double sphere = Follows(s->alignment, options.verdict);
  const double line = Follows(centre, options.verdict);
  p.evidence = fmt::format(
      "the force side's path follows the sphere's at r = {:.3f}, the "
      "centreline at r = {:.3f} ({})",
      sphere,
      line,
      s->alignment.waviness_to_noise >= options.verdict.min_waviness_to_noise
          ? "the waviness, corrected for noise"
          : "the whole profiles: the waviness is within its noise");
  if (line > sphere + kMargin) {
    p.state = Premise::State::kFailed;
    s->profile = s->centreline;
    s->alignment = centre;
    s->centreline_used = true;
  } else {
    p.state = Premise::State::kHeld;
    if (line > sphere - kMargin) s->centreline_alignment = centre;
  }
}

}  // namespace

// The force side's profile over the compared cycles (the last N, none of
// the running-in) from `source`, aligned with the prepared scan's
// sphere path or centreline (ChoosePath). Throws FusionError naming both
// files when they cannot be aligned.
ForceProfileOptions ComparedCycles(const ForceAnalysis& force,
                                   const FuseOptions& options) {
  ForceProfileOptions o = options.force_profile;
  const int n = static_cast<int>(force.cycles.cycles.size());
  if (o.first_cycle < 0 && n > 0) {
    o.first_cycle =
        std::max(n - o.cycles, std::min(force.running_in.cycles, n - 1));
    o.last_cycle = n - 1;
  }
  return o;
}

ScanAnalysis AlignScan(const force::ForceRecord& record,
                       const ForceAnalysis& force,
                       ScanAnalysis s,
                       const FuseOptions& options,
                       ProfileSource source,
                       double depth_sign) {
  const ForceProfileOptions fpo = ComparedCycles(force, options);
  s.force_profile =
      source == ProfileSource::kFriction
          ? ComputeFrictionProfile(record, force.cycles, fpo)
      : source == ProfileSource::kDepth
          ? ComputeDepthProfile(record, force.cycles, fpo, depth_sign)
          : ComputeForceProfile(record,
                                force.cycles,
                                options.analysis.friction.slope.spring_n_per_mm,
                                fpo);
  try {
    s.alignment = AlignProfiles(s.force_profile, s.profile, options.align);
    ChoosePath(options, &s);
    // Where the track's place is not known, whether its waviness would
    // tell a twin whose rings fall a fraction of a period apart.
    if (!s.track.PlaceKnown())
      FindWavinessRunnerUp(
          s.force_profile, s.profile, options.align, &s.alignment);
  } catch (const FusionError& e) {
    // Name both files and the figures that decide the overlap: a wrong
    // pixel size shrinks the scan, a wrong x unit stretches the stroke.
    const scan::HeightMap& map = s.Levelled();
    throw FusionError(fmt::format(
        "{}: {} (the scan: {} x {} pixels of {:.4g} um, {:.3g} x {:.3g} mm, "
        "track {:.3g} mm long; the stroke of {}: {:.3g} mm); check the scan's "
        "pixel size and the force file's x unit",
        map.metadata.source,
        e.what(),
        map.cols(),
        map.rows(),
        1e3 * map.dx_mm,
        map.cols() * map.dx_mm,
        map.rows() * map.dy_mm,
        s.track.length_mm,
        record.metadata.source,
        force.cycles.stroke_mm));
  }
  return s;
}

// The scan's slope in plate coordinates over the stroke.
PlateProfile ScanSlopeOverTheStroke(const force::ForceRecord& record,
                                    const ForceAnalysis& force,
                                    const FuseOptions& options,
                                    const ScanAnalysis& s) {
  // The sphere's excursion over the complete cycles bounds the sliding
  // path: the scan beyond it is the groove's end walls.
  double stroke_min = -std::numeric_limits<double>::infinity();
  double stroke_max = std::numeric_limits<double>::infinity();
  if (!force.cycles.cycles.empty()) {
    // Isolated gaps in x are allowed: finite samples only.
    std::tie(stroke_min, stroke_max) =
        force::CyclesXRange(record.x_mm, force.cycles);
  }
  return ScanSlopeInPlate(
      s.profile, s.alignment, options.scan_slope, stroke_min, stroke_max);
}

}  // namespace wearscar::fusion::internal
