#include "wearscar/fusion/verdict.h"

#include <fmt/format.h>

#include <cmath>

#include "interval_text.h"

namespace wearscar::fusion {

const char* CostCriterionName(CostCriterion c) {
  return c == CostCriterion::kPaperJ ? "paper" : "excess";
}

bool ParseCostCriterion(const std::string& text, CostCriterion* c) {
  if (text == "excess" || text == "noise") {
    *c = CostCriterion::kNoiseExcess;
  } else if (text == "paper") {
    *c = CostCriterion::kPaperJ;
  } else {
    return false;
  }
  return true;
}

bool VerdictOptions::IsValid(std::string* why) const {
  if (!(screen_excess_to_floor > 0)) {
    if (why) *why = "screen_excess_to_floor must be > 0";
    return false;
  }
  if (!(max_cost > 0) || !(max_cost_excess > 0) || !(max_amplitude_ratio > 0) ||
      !(min_correlation > -1) || !(max_method_difference > 0) ||
      !(min_waviness_to_noise > 0) || !(min_waviness_correlation > -1) ||
      !(track_length_tolerance >= 0) || !(max_centre_offset > 0) ||
      !(max_centre_offset_agreed > 0) || !(min_waviness_twin > -1)) {
    if (why) *why = "verdict thresholds must be positive (correlation > -1)";
    return false;
  }
  return true;
}

bool DataWarningOptions::IsValid(std::string* why) const {
  if (min_samples_per_stroke < 0 ||
      !(max_fallback_fraction >= 0 && max_fallback_fraction <= 1) ||
      !(elastic_share > 0 && elastic_share < 1)) {
    if (why) *why = "data warning limits out of range";
    return false;
  }
  return true;
}

std::string Verdict::Summary() const {
  if (explained) {
    return screen.empty() ? "explained by wear-scar interaction"
                          : "explained by wear-scar interaction, but " + screen;
  }
  if (!not_judged.empty()) return "not judged: " + not_judged;
  std::string s = "not explained by wear-scar interaction: ";
  for (size_t i = 0; i < reasons.size(); ++i) s += (i ? "; " : "") + reasons[i];
  return s;
}

namespace internal {

std::string IntervalText(double low, double high, const char* format) {
  if (!std::isfinite(low) || !std::isfinite(high)) return "";
  return fmt::format(fmt::runtime(std::string(" (95% interval ") + format +
                                  " to " + format + ")"),
                     low,
                     high);
}

}  // namespace internal

namespace {

using internal::IntervalText;

// The scan's criteria: the amplitude ratio and the profiles' correlation.
std::vector<std::string> ScanReasons(const MismatchReport& r,
                                     const VerdictOptions& o) {
  std::vector<std::string> reasons;
  if (!r.has_scan) return reasons;
  const bool has_interval = std::isfinite(r.amplitude_ratio_low);
  const double ratio_low =
      has_interval ? r.amplitude_ratio_low : r.amplitude_ratio;
  // Where the spring check judged P/S against the friction's path, it
  // says what P/S's amplitude is (a stiffness, an elastic part or either);
  // the scan's amplitude against P/S is a finding only without it (the
  // depth channel's profile).
  if (!r.Spring().judged && ratio_low > o.max_amplitude_ratio) {
    reasons.push_back(fmt::format(
        "{} varies {:.2f}x as much as the scanned profile{} (limit {:.2f}): "
        "part of the normal displacement is not worn geometry",
        r.force_profile_name,
        r.amplitude_ratio,
        IntervalText(r.amplitude_ratio_low, r.amplitude_ratio_high, "{:.2f}"),
        o.max_amplitude_ratio));
  }
  const std::vector<std::string> identity = r.Identity().Reasons();
  reasons.insert(reasons.end(), identity.begin(), identity.end());
  if (r.correlation_noise_corrected < o.min_correlation) {
    reasons.push_back(fmt::format(
        "the aligned profiles correlate at r = {:.2f} ({:.2f} corrected for "
        "the noise of the force profile) < {:.2f}",
        r.correlation,
        r.correlation_noise_corrected,
        o.min_correlation));
  }
  return reasons;
}

// Why the scan may not be this test's, while the force side alone passes:
// the track's length first (another stroke), then where the track's
// centre aligned and its waviness (another specimen), then the profiles'
// correlation.
std::string ScanDoubt(const MismatchReport& r, const VerdictOptions& o) {
  const ScanIdentity& id = r.Identity();
  if (id.another_test || ((id.foreign || id.moved) &&
                          r.correlation_noise_corrected >= o.min_correlation))
    return id.Doubt();
  const char* judged =
      "; the verdict is judged on the force side (check that the scan is "
      "this specimen's)";
  return fmt::format(
      "the scan may belong to another test: its profile correlates with P/S "
      "at r = {:.2f} ({:.2f} corrected) < {:.2f} while the force side alone "
      "is explained{}",
      r.correlation,
      r.correlation_noise_corrected,
      o.min_correlation,
      judged);
}

// mu-hat against the energy method: flagged when the whole interval of
// their difference lies beyond the limit (one value: the value itself).
std::vector<std::string> MethodReasons(const MismatchReport& r,
                                       const VerdictOptions& o,
                                       bool from_force,
                                       const char* source) {
  const Statistic& mu = from_force ? r.mu_force : r.mu_scan;
  const Interval& d = r.method_difference;
  const double nearest = d.low > 0 ? d.low : (d.high < 0 ? d.high : 0.0);
  if (!(mu.count > 0 && d.count > 0 &&
        std::abs(nearest) > o.max_method_difference))
    return {};
  return {
      fmt::format("the methods disagree: mu-hat {:.4f} ({}) vs energy "
                  "method {:.4f}, difference {:+.4f}{} beyond +-{:.3f} "
                  "(mean method {:.4f})",
                  mu.mean,
                  source,
                  r.mu_energy.mean,
                  d.mean,
                  IntervalText(d.low, d.high, "{:+.4f}"),
                  o.max_method_difference,
                  r.mu_mean.mean)};
}

}  // namespace

Verdict Judge(const MismatchReport& r, const VerdictOptions& o) {
  Verdict v;
  // J and mu-hat from the force-side slope when it was fitted and its
  // spring is not contradicted, else from the scan's (--slope scan).
  const bool from_force = r.JudgesForceSlope();
  const Statistic& cost = from_force ? r.cost_force : r.cost_scan;
  const CostSplit& split = from_force ? r.split_force : r.split_scan;
  const std::string source =
      from_force ? "k from " + r.force_slope_name : "k from the scan";
  if (o.cost_criterion == CostCriterion::kPaperJ) {
    if (cost.count > 0 && cost.mean > o.max_cost) {
      v.reasons.push_back(
          fmt::format("J = {:.3f} after running-in ({}) exceeds {:.2f} (the "
                      "paper's criterion; its noise floor is {:.3f})",
                      cost.mean,
                      source,
                      o.max_cost,
                      split.floor));
    }
  } else if (split.cycles > 0 && split.excess_low > o.max_cost_excess) {
    v.reasons.push_back(fmt::format(
        "J = {:.3f} ({}) exceeds what the measurement noise explains: noise "
        "floor {:.3f}, excess {:.3f}{} above the limit {:.2f}",
        split.cost,
        source,
        split.floor,
        split.excess,
        IntervalText(split.excess_low, split.excess_high, "{:.3f}"),
        o.max_cost_excess));
  }
  // An elastic part the track's growth splits off P/S: the physics, with
  // or without a scan.
  if (r.Spring().elastic)
    v.reasons.push_back(r.Spring().DescribeElastic(r.force_profile_name));
  // The scan's criteria are judged only when the scan can be this test's:
  // a profile unlike P/S's while the force side alone passes is a doubt
  // about the scan (scan_doubt), not a verdict on the physics.
  const std::vector<std::string> scan_reasons = ScanReasons(r, o);
  const bool profiles_differ =
      r.has_scan && (r.correlation_noise_corrected < o.min_correlation ||
                     r.Identity().Doubted());
  const std::vector<std::string> method_reasons =
      MethodReasons(r, o, from_force, source.c_str());
  const bool force_side_passes = v.reasons.empty() && method_reasons.empty();
  if (profiles_differ && from_force && force_side_passes) {
    v.scan_doubt = ScanDoubt(r, o);
  } else {
    v.reasons.insert(v.reasons.end(), scan_reasons.begin(), scan_reasons.end());
  }
  v.reasons.insert(
      v.reasons.end(), method_reasons.begin(), method_reasons.end());
  v.explained = v.reasons.empty();
  // With the scan's k the excess holds the track's growth over the
  // compared cycles too (the scan shows the last one's): not screened.
  if (v.explained && from_force) v.screen = r.Screen().finding;
  return v;
}

std::vector<std::string> DataWarnings(const ForceAnalysis& force,
                                      const SlopeFits& fits,
                                      const MismatchReport& r,
                                      const DataWarningOptions& o) {
  std::vector<std::string> w;
  const auto& cycles = force.cycles.cycles;
  if (!cycles.empty()) {
    double samples = 0;
    for (const auto& c : cycles) {
      samples += static_cast<double>(c.forward.end - c.forward.begin) +
                 static_cast<double>(c.reverse.end - c.reverse.begin);
    }
    samples /= 2.0 * static_cast<double>(cycles.size());
    if (samples < o.min_samples_per_stroke) {
      w.push_back(fmt::format(
          "{:.0f} samples per stroke (fewer than {}): the slope of P is "
          "taken over few points and smooths the track's features; sample "
          "faster or use the ensemble estimate over more cycles",
          samples,
          o.min_samples_per_stroke));
    }
    const double halves = 2.0 * static_cast<double>(cycles.size());
    if (force.slip_fallbacks > o.max_fallback_fraction * halves) {
      w.push_back(fmt::format(
          "gross slip was found by the central-fraction fallback on {} of {} "
          "half cycles: the loops show no clear stick-to-slip transition",
          force.slip_fallbacks,
          static_cast<long>(halves)));
    }
  }
  if (r.force_slope_judged && std::isfinite(fits.k_noise_rms) &&
      std::isfinite(fits.k_signal_rms) &&
      fits.k_noise_rms > fits.k_signal_rms) {
    w.push_back(fmt::format(
        "k from {} is mostly noise: its noise {:.4f} exceeds the part that "
        "repeats from cycle to cycle, {:.4f} (rms); mu-hat is corrected for "
        "the bias such noise brings and J is judged against its noise floor, "
        "so the number to quote stands, but a scan's k is the better check "
        "of it",
        r.force_slope_name,
        fits.k_noise_rms,
        fits.k_signal_rms));
  }
  const double ratio_low = std::isfinite(r.amplitude_ratio_low)
                               ? r.amplitude_ratio_low
                               : r.amplitude_ratio;
  const SpringCheck& spring = r.Spring();
  if (spring.judged && !spring.elastic &&
      spring.elastic_share_low > o.elastic_share) {
    w.push_back(fmt::format(
        "{} carries a small elastic part, below the verdict's limit: {:.0f}% "
        "of the worn track's profile at the end (95% interval {:.0f}-{:.0f}%) "
        "does not follow the path's growth that the friction shows; it moves "
        "the sphere without tilting the contact",
        r.force_profile_name,
        100 * spring.elastic_share,
        100 * spring.elastic_share_low,
        100 * spring.elastic_share_high));
  }
  if (r.has_scan && ratio_low > 1 + o.elastic_share && !spring.judged) {
    w.push_back(fmt::format(
        "{} varies {:.2f}x as much as the scanned profile: an elastic part "
        "of about {:.0f}% of the profile moves the sphere without tilting "
        "the contact",
        r.force_profile_name,
        r.amplitude_ratio,
        100 * (r.amplitude_ratio - 1)));
  }
  return w;
}

}  // namespace wearscar::fusion
