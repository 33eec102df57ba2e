// The words a test's result says of itself: its headline and the names of
// the force side's profile and slope.

#include "wearscar/fusion/result.h"

#include <fmt/format.h>

#include <cmath>

namespace wearscar::fusion {

const char* ProfileDecision::ChannelName() const {
  return FromDepth() ? "the depth" : "P";
}

std::string ProfileDecision::SlopeName() const {
  return std::string("k from ") + ChannelName();
}

const char* ProfileDecision::ShortChannelName() const {
  return FromDepth() ? "depth" : "P";
}

const char* ProfileDecision::ShortProfileName() const {
  return FromDepth() ? "depth" : FromFriction() ? "friction profile" : "P/S";
}

std::string ProfileDecision::ProfileName() const {
  return FromDepth()      ? "the depth channel's profile"
         : FromFriction() ? "the profile from the friction"
                          : "the spring displacement";
}

const SlopeFits& TestResult::ForceFits() const {
  static const SlopeFits kNone{};
  if (const DepthFits* d = units.Find<DepthFits>()) return *d;
  if (const SpringFits* s = units.Find<SpringFits>()) return *s;
  return kNone;
}

const ScanFits& TestResult::ScanSlopeFits() const {
  return units.Get<ScanFits>();
}

CycleWindow QuotedWindow(const TestResult& r, const ScanAnalysis* scan) {
  const int n = static_cast<int>(r.force.cycles.cycles.size());
  const ForceProfileOptions& given = r.options.force_profile;
  const int running_in = r.force.running_in.cycles;
  CycleWindow w{running_in, n - 1, ""};
  if (given.first_cycle >= 0) {
    w.first = given.first_cycle;
    w.last = given.last_cycle >= 0 ? given.last_cycle : n - 1;
    w.why = "as given";
  } else {
    if (scan) {
      w.first = scan->force_profile.first_cycle;
      w.last = scan->force_profile.last_cycle;
    }
    w.why = w.first > running_in ? fmt::format("the last {} after running-in",
                                               w.last - w.first + 1)
            : running_in > 0     ? "every cycle after running-in"
                                 : "every cycle: no running-in";
    if (scan) w.why += ", whose track the scan shows";
  }
  return w;
}

Quote QuoteOf(const TestResult& r) {
  const MismatchReport& m = r.mismatch;
  const bool from_p = m.JudgesForceSlope();
  const Statistic& mu = from_p ? m.mu_force : m.mu_scan;
  Quote q;
  q.k_from = from_p ? r.profile.ChannelName() : "the scan";
  if (mu.count == 0) {
    q.status = "not fitted";
    q.reason =
        "no mu-hat was fitted (too few sliding samples per cycle; see the "
        "warnings)";
  } else if (!r.verdict.not_judged.empty()) {
    q.status = "not judged";
    q.reason =
        "not judged, P carries no profile and nothing else gives the slope "
        "(no scan, no depth channel)";
  } else if (!r.verdict.explained) {
    q.status = "not explained";
    q.reason =
        "not explained by wear-scar interaction, the model misses an effect";
  } else {
    q.status = r.verdict.screen.empty() ? "explained" : "not settled";
    q.mu = mu.mean;
    q.low = mu.low;
    q.high = mu.high;
  }
  return q;
}

std::string Headline(const TestResult& r) {
  const MismatchReport& m = r.mismatch;
  const bool from_p = m.JudgesForceSlope();
  const Statistic& mu = from_p ? m.mu_force : m.mu_scan;
  const Quote q = QuoteOf(r);
  if (q.status == "not explained") {
    return fmt::format(
        "no mu to quote: {} (reasons below; `wearscar diagnose` names it); "
        "mu-hat {:.4f} and mu energy {:.4f} are for comparison only",
        q.reason,
        mu.mean,
        m.mu_energy.mean);
  }
  if (!q.Quoted()) return "no mu to quote: " + q.reason;
  const std::string interval =
      std::isfinite(mu.low)
          ? fmt::format(" (95%: {:.4f}-{:.4f})", mu.low, mu.high)
          : std::string();
  // A spring the scan contradicts is why the scan's k is quoted: said here.
  const SpringCheck& spring = m.Spring();
  const std::string source =
      from_p && !r.options.spring_from_friction.empty()
          ? fmt::format(
                "{} at S = {:.3g} N/mm, the stiffness the friction's path "
                "implies{}",
                m.force_slope_name,
                spring.used_n_per_mm,
                r.options.spring_from_friction.rfind("cannot tell", 0) == 0
                    ? " (or an elastic part: the data cannot tell)"
                    : "")
      : from_p ? m.force_slope_name
      : spring.contradicted && m.cost_force.count > 0
          ? fmt::format(
                "the scan (the spring's stiffness appears to be {}{:.3g} "
                "N/mm, not the {:g} used)",
                spring.changing_groove.Held() ? "" : "at most ",
                spring.ImpliedStiffness(),
                spring.used_n_per_mm)
      : spring.undecided && m.cost_force.count > 0
          ? fmt::format(
                "the scan (cannot tell a spring of {:.3g} N/mm from an "
                "elastic part: give --spring, or record from the first "
                "contact)",
                spring.ImpliedStiffness())
          : std::string("the scan");
  return fmt::format("mu = {:.4f}{}: mu-hat, k from {}, cycles {}-{} ({}); {}",
                     mu.mean,
                     interval,
                     source,
                     m.first_cycle + 1,
                     m.last_cycle + 1,
                     r.window.why,
                     r.verdict.screen.empty()
                         ? "explained by wear-scar interaction"
                         : "within the verdict's limits, but not settled: " +
                               r.verdict.screen);
}

}  // namespace wearscar::fusion
