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

}  // namespace

namespace {

// The one coefficient to report, and why that one.
std::string Quotable(const fusion::TestResult& r) {
  const auto& m = r.mismatch;
  const bool from_p = m.mu_force.count > 0;
  const fusion::Statistic& mu = from_p ? m.mu_force : m.mu_scan;
  if (mu.count == 0) return "nothing: no mu-hat was fitted";
  if (!r.verdict.explained) {
    return fmt::format(
        "no wear-scar mu-hat: the verdict says the model misses an effect "
        "(see the warnings; `wearscar diagnose` names it); the classic COF "
        "of this test is mu energy {:.4f}",
        m.mu_energy.mean);
  }
  return fmt::format(
      "mu-hat = {:.4f} {} (k from {}, after running-in){}",
      mu.mean,
      Interval95(mu),
      from_p ? "P" : "the scan",
      m.has_scan && from_p && m.mu_scan.count > 0
          ? fmt::format("; k from the scan gives {:.4f}", m.mu_scan.mean)
          : "");
}

}  // namespace

void PrintSummary(const std::string& name, const fusion::TestResult& r) {
  const auto& m = r.mismatch;
  Say("{}: {} cycles; compared over cycles {}-{}\n  {}\n",
      name,
      r.force.cycles.cycles.size(),
      m.first_cycle + 1,
      m.last_cycle + 1,
      r.force.running_in.rule);
  if (m.mu_force.count > 0) {
    Say("  mu-hat, k from P     {:.4f} {}, sd {:.4f}   J {:.3f} (noise "
        "floor {:.3f} and excess {:.3f}, which add as squares)\n",
        m.mu_force.mean,
        Interval95(m.mu_force),
        m.mu_force.sd,
        m.cost_force.mean,
        m.split_force.floor,
        m.split_force.excess);
    Say("    {}\n", r.force.slope_estimate);
  } else {
    Say("  mu-hat, k from P     not fitted (--slope scan)\n");
  }
  if (m.has_scan) {
    if (m.mu_scan.count > 0) {
      Say("  mu-hat, k from scan  {:.4f} {}, sd {:.4f}   J {:.3f} (noise "
          "floor {:.3f} and excess {:.3f}, which add as squares)\n",
          m.mu_scan.mean,
          Interval95(m.mu_scan),
          m.mu_scan.sd,
          m.cost_scan.mean,
          m.split_scan.floor,
          m.split_scan.excess);
    } else {
      Say("  mu-hat, k from scan  not fitted (--slope force)\n");
    }
    const auto& a = r.scan->alignment;
    Say("  profiles: r = {:.3f}, amplitude ratio {:.2f}, shift {:.3f} mm{}, "
        "RMS(k_P - "
        "k_scan) {:.3f}\n",
        a.correlation,
        a.amplitude_ratio,
        a.shift_mm,
        a.flipped ? " (the scan's x runs against the stroke's: flipped)" : "",
        m.k_rms_difference);
  }
  Say("  mu mean {:.4f} {}, mu energy {:.4f} {}\n",
      m.mu_mean.mean,
      Interval95(m.mu_mean),
      m.mu_energy.mean,
      Interval95(m.mu_energy));
  if (r.lugre) {
    Say("  LuGre, cycle {}: {}\n", r.detail_cycle + 1, r.lugre->BriefReport());
  }
  Say("  verdict: {}\n", r.verdict.Summary());
  Say("  to quote: {}\n", Quotable(r));
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
  Say("{}: diagnosis on {} cycles ({}-{}), slope from each cycle's binned P "
      "profile, "
      "depth from the {}\n",
      name,
      d.cycles.size(),
      d.cycles.front() + 1,
      d.cycles.back() + 1,
      from_scan ? "scan" : "force side");
  Say("where the wear-scar model misses: {}\n\n", d.before.where);
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
        c.accepted ? "NAMED" : "(rejected: stop)");
  }
  Say("\n{}\n", d.BriefReport());
  if (!d.named.empty()) Say("after: {}\n", d.after.where);
}

}  // namespace wearscar::app
