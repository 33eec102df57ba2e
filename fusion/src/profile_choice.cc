// Where the force side's profile of the sliding path comes from: the
// choice between P/S and the friction (a rig without a spring) and its
// words.

#include "profile_choice.h"

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

namespace internal {

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

// How far P's repeatable slope is from nothing, in its standard errors
// (the k split's repeatable rms against its noise over the root of the
// independent cycles: the ensemble's neighbouring cycles share their
// noise); NaN without the split.
double ProfileSignificance(const ForceAnalysis& force) {
  const double n = static_cast<double>(force.fit_force.size()) /
                   std::max(1, force.correlated_cycles);
  if (!(force.k_noise_rms > 0) || !std::isfinite(force.k_signal_rms) || n < 2)
    return NAN;
  return force.k_signal_rms / (force.k_noise_rms / std::sqrt(std::max(1.0, n)));
}

// auto: the friction's profile when P carries none (a dead weight) -- its
// repeatable slope insignificant and P/S varying far less than the track
// the scan shows -- else the spring's. Sets the result's source and why.
ProfileSource ChooseProfile(const TestResult& r, const FuseOptions& o) {
  const double sig = r.p_slope_significance;
  const double ratio = r.scan ? r.scan->alignment.amplitude_ratio : NAN;
  if (std::isfinite(sig) && sig < o.dead_weight_significance &&
      ratio < o.dead_weight_ratio)
    return ProfileSource::kFriction;
  return ProfileSource::kSpring;
}

// `spring_ratio`: P/S's amplitude against the scanned profile, as the
// choice read it (NaN when no choice was made).
std::string ProfileReason(const TestResult& r,
                          const FuseOptions& o,
                          bool chosen,
                          double spring_ratio) {
  const double sig = r.p_slope_significance;
  const std::string p_says =
      std::isfinite(sig)
          ? fmt::format(
                "P's repeatable slope is {:.1f} standard errors from nothing "
                "(over {} cycles, {} of them sharing their noise)",
                sig,
                r.force.fit_force.size(),
                r.force.correlated_cycles)
          : std::string("P's slope was not split into signal and noise");
  if (r.profile_source == ProfileSource::kDepth) {
    const bool turned = r.depth_agreement < -0.5;
    return fmt::format(
        "profile from the depth channel '{}' ({}{}, penetration positive: k "
        "= -d(depth)/dx), no spring: {}{}",
        r.depth_column,
        r.depth_is_penetration ? "read as a penetration by its name"
                               : "a height by its name, turned over",
        std::isfinite(r.depth_agreement)
            ? fmt::format("; its profile against the friction's r = {:.2f}{}",
                          r.depth_agreement,
                          turned
                              ? ": it runs the other way, so it was turned over"
                              : "")
            : std::string(),
        !chosen ? std::string("--profile-from depth")
        : std::isfinite(r.spring_depth_agreement)
            ? fmt::format(
                  "{}, but P/S's profile follows the depth's by r = {:.2f} "
                  "only (below {:.2f}): P's variation is not the track's (a "
                  "dead weight with Q's crosstalk into P?)",
                  p_says,
                  r.spring_depth_agreement,
                  o.spring_depth_agreement)
            : p_says + ": a dead-weight or force-controlled rig",
        "; the spring is neither needed nor used");
  }
  if (r.profile_source == ProfileSource::kFriction) {
    const std::string why =
        chosen ? fmt::format(
                     "{} and P/S varies {:.2f}x the scanned profile (below "
                     "{:.2f}): a dead-weight or force-controlled rig",
                     p_says,
                     spring_ratio,
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
  return fmt::format("profile from the spring, P/S{}: {}",
                     chosen ? "" : " (--profile-from spring)",
                     p_says);
}

}  // namespace internal
}  // namespace wearscar::fusion
