// Where the force side's profile of the sliding path comes from: the one
// decision (P/S, the depth channel, or the friction on a rig without a
// spring), the figures it reads and its words.

#include "wearscar/fusion/profile_decision.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "wearscar/fusion/align.h"
#include "wearscar/fusion/error.h"

namespace wearscar::fusion {

const char* ProfileSourceName(ProfileSource source) {
  switch (source) {
    case ProfileSource::kSpring:
      return "spring";
    case ProfileSource::kFriction:
      return "friction";
    case ProfileSource::kDepth:
      return "depth";
    case ProfileSource::kAuto:
      break;
  }
  return "auto";
}

bool ParseProfileSource(const std::string& name, ProfileSource* source) {
  if (name == "auto") {
    *source = ProfileSource::kAuto;
  } else if (name == "spring") {
    *source = ProfileSource::kSpring;
  } else if (name == "friction") {
    *source = ProfileSource::kFriction;
  } else if (name == "depth") {
    *source = ProfileSource::kDepth;
  } else {
    return false;
  }
  return true;
}

namespace {

// Pearson r of two profiles' means over the bins both hold.
double ProfileCorrelation(const ForceProfile& d, const ForceProfile& f) {
  double md = 0, mf = 0;
  int k = 0;
  const Eigen::Index bins = std::min(d.x_mm.size(), f.x_mm.size());
  auto both = [&](Eigen::Index i) {
    return std::isfinite(d.mean_mm[i]) && std::isfinite(f.mean_mm[i]);
  };
  for (Eigen::Index i = 0; i < bins; ++i) {
    if (!both(i)) continue;
    md += d.mean_mm[i];
    mf += f.mean_mm[i];
    ++k;
  }
  if (k < 3) return NAN;
  md /= k;
  mf /= k;
  double sd = 0, sf = 0, sdf = 0;
  for (Eigen::Index i = 0; i < bins; ++i) {
    if (!both(i)) continue;
    const double a = d.mean_mm[i] - md, b = f.mean_mm[i] - mf;
    sd += a * a;
    sf += b * b;
    sdf += a * b;
  }
  return sd > 0 && sf > 0 ? sdf / std::sqrt(sd * sf) : NAN;
}

// The last cycles after running-in (at most ForceProfileOptions::cycles).
ForceProfileOptions LastCycles(const ForceAnalysis& force) {
  ForceProfileOptions o;
  const int n = static_cast<int>(force.cycles.cycles.size());
  o.first_cycle =
      std::max(n - o.cycles, std::min(force.running_in.cycles, n - 1));
  o.last_cycle = n - 1;
  return o;
}

}  // namespace

double DepthAgreement(const force::ForceRecord& record,
                      const ForceAnalysis& force) {
  if (force.cycles.cycles.empty()) return NAN;
  const ForceProfileOptions o = LastCycles(force);
  try {
    return ProfileCorrelation(ComputeDepthProfile(record, force.cycles, o),
                              ComputeFrictionProfile(record, force.cycles, o));
  } catch (const FusionError&) {
    return NAN;
  }
}

double SpringDepthAgreement(const force::ForceRecord& record,
                            const ForceAnalysis& force,
                            double spring_n_per_mm) {
  if (force.cycles.cycles.empty() || !record.has_depth()) return NAN;
  const ForceProfileOptions o = LastCycles(force);
  try {
    return ProfileCorrelation(
        ComputeDepthProfile(record, force.cycles, o),
        ComputeForceProfile(record, force.cycles, spring_n_per_mm, o));
  } catch (const FusionError&) {
    return NAN;
  }
}

// The ensemble's neighbouring cycles share their noise: the root of the
// independent cycles.
double ProfileSignificance(const SlopeFits& force) {
  const double n = static_cast<double>(force.cycles.size()) /
                   std::max(1, force.correlated_cycles);
  if (!(force.k_noise_rms > 0) || !std::isfinite(force.k_signal_rms) || n < 2)
    return NAN;
  return force.k_signal_rms / (force.k_noise_rms / std::sqrt(std::max(1.0, n)));
}

void ApplyProfile(const ProfileDecision& d, FrictionFitOptions* friction) {
  friction->k_from_depth = d.FromDepth();
  if (d.FromDepth()) friction->depth_sign = d.depth_sign;
}

PSlope ClassifyPSlope(double significance, const FuseOptions& options) {
  if (!std::isfinite(significance)) return PSlope::kNotSplit;
  return significance < options.dead_weight_significance ? PSlope::kNoise
                                                         : PSlope::kVaries;
}

std::string PSlopeNoiseText(double significance) {
  if (!std::isfinite(significance))
    return "P's slope was not split into signal and noise (k per cycle), so "
           "it is not shown to vary along the stroke beyond its noise";
  return fmt::format(
      "P does not vary along the stroke beyond its noise ({:.1f} standard "
      "errors)",
      significance);
}

namespace {

std::string PSays(const ProfileDecision& d, ProfileEvidence* e) {
  const double sig = d.p_slope_significance;
  if (!std::isfinite(sig))
    return "P's slope was not split into signal and noise";
  return fmt::format(
      "P's repeatable slope is {:.1f} standard errors from nothing (over {} "
      "cycles, {} of them sharing their noise)",
      sig,
      e->FittedCycles(),
      e->CorrelatedCycles());
}

std::string DepthReason(const ProfileDecision& d,
                        const FuseOptions& o,
                        const std::string& p_says) {
  const bool chosen = d.given == ProfileSource::kAuto;
  return fmt::format(
      "profile from the depth channel '{}' ({}{}, penetration positive: k "
      "= -d(depth)/dx), no spring: {}{}",
      d.depth_column,
      d.depth_is_penetration ? "read as a penetration by its name"
                             : "a height by its name, turned over",
      std::isfinite(d.depth_agreement)
          ? fmt::format("; its profile against the friction's r = {:.2f}{}",
                        d.depth_agreement,
                        d.depth_sign < 0
                            ? ": it runs the other way, so it was turned over"
                            : "")
          : std::string(),
      !chosen ? std::string("--profile-from depth")
      : std::isfinite(d.spring_depth_agreement)
          ? fmt::format(
                "{}, but P/S's profile follows the depth's by r = {:.2f} "
                "only (below {:.2f}): P's variation is not the track's (a "
                "dead weight with Q's crosstalk into P?)",
                p_says,
                d.spring_depth_agreement,
                o.spring_depth_agreement)
          : p_says + ": a dead-weight or force-controlled rig",
      "; the spring is neither needed nor used");
}

std::string FrictionReason(const ProfileDecision& d,
                           const FuseOptions& o,
                           const std::string& p_says) {
  const std::string why =
      d.given == ProfileSource::kAuto
          ? fmt::format(
                "{} and P/S varies {:.2f}x {} (below {:.2f}): a "
                "dead-weight or force-controlled rig",
                p_says,
                d.spring_amplitude_ratio,
                d.ratio_against_friction ? "the path the friction shows"
                                         : "the scanned profile",
                o.dead_weight_ratio)
          : std::string("--profile-from friction");
  return fmt::format(
      "profile from the friction, no spring: {}; the spring is neither "
      "needed nor used. k = tan((atan(Q_f/P) + atan(Q_r/P))/2) at each x "
      "over the compared cycles, integrated along the stroke: circular for "
      "a verdict on its own, it aligns the scan and is compared with it; "
      "mu-hat takes k from the scan",
      why);
}

// auto's choice: the depth channel when P carries no profile or one that
// is not the track's, the friction when P carries none and the scan shows
// a track, else the spring.
ProfileSource AutoSource(ProfileEvidence* e,
                         const FuseOptions& o,
                         ProfileDecision* d) {
  const PSlope p = ClassifyPSlope(d->p_slope_significance, o);
  const bool p_varies = p == PSlope::kVaries;
  if (e->HasDepthChannel() && e->ForceSlopeFitted()) {
    if (p_varies) d->spring_depth_agreement = e->SpringDepthAgreement();
    if (!p_varies ||
        std::abs(d->spring_depth_agreement) < o.spring_depth_agreement)
      return ProfileSource::kDepth;
  }
  if (!e->HasScan() || p != PSlope::kNoise) return ProfileSource::kSpring;
  d->spring_amplitude_ratio = e->SpringPathRatio();
  d->ratio_against_friction = std::isfinite(d->spring_amplitude_ratio);
  if (!d->ratio_against_friction)
    d->spring_amplitude_ratio = e->SpringAmplitudeRatio();
  return d->spring_amplitude_ratio < o.dead_weight_ratio
             ? ProfileSource::kFriction
             : ProfileSource::kSpring;
}

}  // namespace

ProfileDecision DecideProfile(ProfileEvidence* e, const FuseOptions& o) {
  ProfileDecision d;
  d.given = o.profile_from;
  if (e->HasDepthChannel()) {
    d.depth_column = e->DepthColumn();
    d.depth_is_penetration = e->DepthIsPenetration();
  }
  if (d.given == ProfileSource::kDepth && !e->HasDepthChannel()) {
    throw FusionError(
        "--profile-from depth, but the force file has no depth channel; "
        "name its column with --columns depth=NAME:UNIT");
  }
  if (d.given == ProfileSource::kFriction && !e->HasScan()) {
    throw FusionError(
        "--profile-from friction needs a scan of the track: the slope from "
        "the friction alone is circular, and nothing else gives k");
  }
  // P's significance is read wherever P/S is fitted (every source but a
  // depth given): the result reports it.
  if (d.given != ProfileSource::kDepth)
    d.p_slope_significance = e->PSlopeSignificance();
  d.used = d.given == ProfileSource::kAuto ? AutoSource(e, o, &d) : d.given;
  if (d.FromDepth()) {
    d.depth_agreement = e->DepthAgreement();
    if (d.depth_agreement < -o.depth_turn_agreement) d.depth_sign = -1.0;
  }
  const std::string p_says = PSays(d, e);
  d.reason = d.FromDepth() ? DepthReason(d, o, p_says)
             : d.FromFriction()
                 ? FrictionReason(d, o, p_says)
                 : fmt::format("profile from the spring, P/S{}: {}",
                               d.given == ProfileSource::kAuto
                                   ? ""
                                   : " (--profile-from spring)",
                               p_says);
  return d;
}

}  // namespace wearscar::fusion
