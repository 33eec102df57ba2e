#include "summaries.h"

#include <fmt/format.h>

#include <cmath>

#include "output.h"

namespace wearscar::app {

namespace {

// "(95%: low-high)", or nothing without an interval.
std::string Interval95(const fusion::Statistic& s) {
  if (!std::isfinite(s.low)) return "";
  return fmt::format("(95%: {:.4f}-{:.4f})", s.low, s.high);
}

// "J 0.125 (of J^2: noise 91%, excess 9%; ...)": the parts of J's square,
// which add up, and their values as the verdict reads them.
std::string CostText(double cost, const fusion::CostSplit& split) {
  const double f2 = split.floor * split.floor, e2 = split.excess * split.excess;
  if (!(f2 + e2 > 0)) return fmt::format("J {:.3f}", cost);
  return fmt::format(
      "J {:.3f} (of J^2 {:.0f}% noise, floor {:.3f}, and {:.0f}% repeating "
      "misfit, excess {:.3f})",
      cost,
      100 * f2 / (f2 + e2),
      split.floor,
      100 * e2 / (f2 + e2),
      split.excess);
}

// The other window's number beside the one quoted: every cycle after
// running-in, when the quoted cycles are fewer.
void SayEveryCycleAfterRunningIn(const fusion::TestResult& r) {
  const auto& m = r.mismatch;
  const int after = r.force.running_in.cycles;
  const int n = static_cast<int>(r.force.cycles.cycles.size());
  if (!m.JudgesForceSlope() || r.ForceFits().mu_hat.count == 0 ||
      (m.first_cycle == after && m.last_cycle == n - 1))
    return;
  Say("  every cycle after running-in ({}-{}): mu-hat {:.4f} {}\n",
      after + 1,
      n,
      r.ForceFits().mu_hat.mean,
      Interval95(r.ForceFits().mu_hat));
}

}  // namespace

void PrintSummary(const std::string& name, const fusion::TestResult& r) {
  const auto& m = r.mismatch;
  // The fit quoted (k from P, or from the scan with --slope scan) first,
  // the other below as a comparison.
  auto fit_line = [&](bool from_p) {
    const fusion::Statistic& mu = from_p ? m.mu_force : m.mu_scan;
    const std::string label =
        !from_p ? "mu-hat, k from scan"
                : fmt::format("mu-hat, {:<11}", r.profile.SlopeName());
    if (from_p && r.profile.FromFriction()) {
      Say("  {}  not used (P carries no profile: a dead weight)\n", label);
      return;
    }
    if (mu.count == 0) {
      Say("  {}  not fitted (--slope {})\n", label, from_p ? "scan" : "force");
      return;
    }
    Say("  {}  {:.4f} {}, sd {:.4f}   {}\n",
        label,
        mu.mean,
        Interval95(mu),
        mu.sd,
        from_p ? CostText(m.cost_force.mean, m.split_force)
               : CostText(m.cost_scan.mean, m.split_scan));
    if (from_p) Say("    {}\n", r.ForceFits().slope_estimate);
  };
  const bool quoted_from_p = m.JudgesForceSlope() || !m.has_scan;
  Say("{}: {}\n  {} cycles, compared over cycles {}-{} ({}); {}\n",
      name,
      fusion::Headline(r),
      r.force.cycles.cycles.size(),
      m.first_cycle + 1,
      m.last_cycle + 1,
      r.window.why,
      r.force.running_in.rule);
  SayEveryCycleAfterRunningIn(r);
  fit_line(quoted_from_p);
  Say("  verdict: {}\n", r.verdict.Summary());
  Say("  for comparison, not to quote:\n");
  if (m.has_scan) {
    fit_line(!quoted_from_p);
    const auto& a = r.scan->alignment;
    Say("  profiles ({} and the scan): r = {:.3f}, {}, amplitude ratio "
        "{:.2f}, shift {:.3f} mm{}{}\n",
        r.profile.ShortProfileName(),
        a.correlation,
        std::isfinite(a.waviness_correlation) && a.waviness_to_noise >= 1
            ? fmt::format("waviness r = {:.2f} ({:.1f}x its noise)",
                          a.waviness_correlation,
                          a.waviness_to_noise)
            : std::string("no waviness above the noise to compare"),
        a.amplitude_ratio,
        a.shift_mm,
        a.flipped ? " (the scan's x runs against the stroke's: flipped)" : "",
        std::isfinite(m.k_rms_difference)
            ? fmt::format(", RMS(k_{} - k_scan) {:.3f}",
                          r.profile.ShortChannelName(),
                          m.k_rms_difference)
            : std::string());
  }
  Say("  mu mean {:.4f} {}, mu energy {:.4f} {} (classic COFs, biased on a "
      "wavy track)\n",
      m.mu_mean.mean,
      Interval95(m.mu_mean),
      m.mu_energy.mean,
      Interval95(m.mu_energy));
  if (const fusion::LugreFit* lugre = r.units.Find<fusion::LugreFit>())
    Say("  LuGre, cycle {}: {}\n", r.detail_cycle + 1, lugre->BriefReport());
  for (const auto& a : r.assumptions) Say("  assumed: {}\n", a);
  for (const auto& w : r.warnings) {
    if (CurrentPrintMode() == PrintMode::kText) {
      Say("  warning: {}\n", w);
    } else {
      fmt::print(stderr, "wearscar: warning: {}: {}\n", name, w);
    }
  }
}

namespace {

// "c_p_N_per_mm = 7.5 +- 0.2, ..."
std::string ParameterText(const fusion::CandidateResult& c) {
  if (c.parameters.size() > 4) {
    return fmt::format("a shape of {} knots (below)", c.parameters.size());
  }
  std::string s;
  for (size_t i = 0; i < c.parameters.size(); ++i) {
    s += fmt::format("{}{} = {:.4g} +- {:.2g}",
                     i ? ", " : "",
                     c.parameter_names[i],
                     c.parameters[i],
                     c.uncertainties[i]);
  }
  return s;
}

}  // namespace

void PrintDiagnosis(const std::string& name,
                    const fusion::Diagnosis& d,
                    bool from_scan) {
  const int span = d.cycles.back() - d.cycles.front() + 1;
  Say("{}: diagnosis on {} cycles {} {}-{}, slope from {}, depth from the "
      "{}\n",
      name,
      d.cycles.size(),
      static_cast<int>(d.cycles.size()) == span ? "of" : "spread over",
      d.cycles.front() + 1,
      d.cycles.back() + 1,
      d.slope_source,
      from_scan ? "scan" : "force side");
  Say("where the wear-scar model misses: {}\n", d.before.where);
  Say("  split by the direction of sliding at the same x: direction-odd "
      "{:.3f} N rms (friction along the track, ploughing, a viscous or "
      "Stribeck term), direction-even {:.3f} N rms (a scale of k, a "
      "pick-up; a lag and an asymmetry add to both); repeatable {:.3f} N "
      "({:.0f} standard errors above its noise)\n",
      d.before.odd_rms_n,
      d.before.even_rms_n,
      d.before.repeatable_rms_n,
      d.before.repeatable_z);
  for (const auto& l : d.lines)
    Say("  a periodic line the drive does not make: {}\n", l.Describe());
  Say("\n");
  Say("{:<5} {:<34} {:>10} {:>10} {:>7} {:>8} {:>9}  {}\n",
      "step",
      "best candidate",
      "J before",
      "J after",
      "gain",
      "cycles+",
      "dBIC",
      "parameters");
  for (size_t i = 0; i < d.steps.size(); ++i) {
    const auto& c = d.steps[i].chosen;
    Say("{:<5} {:<34} {:>10.4f} {:>10.4f} {:>6.0f}% {:>7.0f}% {:>9.1f}  {} "
        "{}\n",
        i + 1,
        c.effect,
        c.heldout_before,
        c.heldout_after,
        100 * c.relative_gain,
        100 * c.improved_fraction,
        c.delta_bic,
        ParameterText(c),
        c.accepted                ? "NAMED"
        : !c.contradicted.empty() ? "(contradicted by the channels: stop)"
        : c.plausible             ? "(rejected: stop)"
                      : "(a resistance fitted negative, implausible: stop)");
  }
  for (const auto& step : d.steps) {
    if (!step.note.empty()) Say("  ({})\n", step.note);
  }
  Say("\n{}\n", d.BriefReport());
  if (!d.along_track.empty()) {
    const auto& a = d.along_track;
    Say("friction along the track, mu_eff/mu - 1 at x (mm):");
    for (Eigen::Index i = 0; i < a.a.size(); ++i)
      Say("{} {:+.2f}:{:+.3f}", i % 6 == 0 ? "\n " : "", a.x_mm[i], a.a[i]);
    Say("\n  it follows the groove's depth with r = {:.2f} and the depth's "
        "short-wave texture with r = {:.2f} (friction following wear, the "
        "wood's bands, or neither)\n",
        a.correlation_depth,
        a.correlation_texture);
    if (std::isfinite(a.correlation_map))
      Say("  and the friction map's steady pattern, bin by bin, with r = "
          "{:.2f}\n",
          a.correlation_map);
  }
  if (!d.named.empty()) Say("after: {}\n", d.after.where);
}

}  // namespace wearscar::app
