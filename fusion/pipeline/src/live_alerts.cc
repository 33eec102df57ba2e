// LiveAnalysis's judgements as cycles are reported: where k comes from,
// running-in, steady, the verdict, periodic lines, the depth; the events
// they raise.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "wearscar/fusion/error.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/live.h"
#include "wearscar/fusion/verdict.h"
#include "wearscar/support/numbers.h"

namespace wearscar::fusion {
namespace {

// Straight-line slope of values[first, last] against their index.
double TrendPerCycle(const std::vector<double>& v, size_t first, size_t last) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  for (size_t i = first; i <= last; ++i) {
    if (!std::isfinite(v[i])) continue;
    const double x = static_cast<double>(i);
    sx += x;
    sy += v[i];
    sxx += x * x;
    sxy += x * v[i];
    n += 1;
  }
  const double d = n * sxx - sx * sx;
  return n >= 3 && d > 0 ? (n * sxy - sx * sy) / d : support::kNaN;
}

double MeanOf(const std::vector<double>& v, size_t first, size_t last) {
  double s = 0;
  int n = 0;
  for (size_t i = first; i <= last; ++i) {
    if (std::isfinite(v[i])) {
      s += v[i];
      ++n;
    }
  }
  return n > 0 ? s / n : support::kNaN;
}

}  // namespace

// Where k comes from, as fuse decides it on the latest cycles
// (DecideForceProfile): a depth channel once fuse's rule takes it (said;
// the verdict's and the noise split's cycles fitted with k from P are
// dropped, so that they judge the new slope alone), and P's slope's
// significance for the verdict. Too few cycles: k from P stays.
void LiveAnalysis::DecideSlope(bool may_switch) {
  decided_at_ = static_cast<int>(reported_.size());
  ProfileDecision d;
  try {
    d = DecideForceProfile(LatestRows(), options_);
  } catch (const force::ForceError&) {
    return;  // too few cycles yet
  } catch (const FusionError&) {
    return;
  }
  p_significance_ = d.p_slope_significance;
  FrictionFitOptions& friction = options_.analysis.friction;
  depth_decided_ = d.FromDepth();
  if (!may_switch || !d.FromDepth() || friction.k_from_depth) return;
  ApplyProfile(d, &friction);
  recent_fits_.clear();
  recent_energy_.clear();
  recent_mean_.clear();
  misfits_.clear();
  template_ = Template();
  k_noise_estimates_.clear();
  verdict_state_ = -1;
  Raise("profile",
        fmt::format("k from the depth channel from cycle {} on: {}",
                    decided_at_ + 1,
                    d.reason));
}

void LiveAnalysis::Raise(const std::string& kind,
                         std::string message,
                         bool good) {
  LiveEvent e;
  e.kind = kind;
  e.good = good;
  e.cycle = reported_.empty() ? 0 : reported_.back().cycle;
  e.time_s = reported_.empty() ? 0.0 : reported_.back().end_time_s;
  e.message = std::move(message);
  events_.push_back(std::move(e));
}

std::vector<LiveEvent> LiveAnalysis::TakeEvents() {
  std::vector<LiveEvent> e;
  e.swap(events_);
  return e;
}

void LiveAnalysis::UpdateRunningIn() {
  const int n = static_cast<int>(mu_mean_series_.size());
  const int given = options_.analysis.running_in_cycles;
  if (given >= 0) {
    running_in_ = std::min(given, n);
    if (!running_in_ended_ && n > given) {
      running_in_ended_ = true;
      Raise("running-in",
            fmt::format("running-in ended: {} cycles (given)", given));
    }
    return;
  }
  // The whole series so far; beyond 2000 cycles every 50th cycle (the
  // detection's cost grows with the series).
  if (n > 2000 && n % 50 != 0) return;
  const RunningIn ri =
      DetectRunningIn(mu_mean_series_, options_.analysis.running_in_tolerance);
  // The detection moves by a cycle or two as cycles come: held when it
  // stays within 3 cycles.
  if (running_in_seen_ >= 0 && std::abs(ri.cycles - running_in_seen_) <= 3) {
    ++running_in_same_;
  } else {
    running_in_seen_ = ri.cycles;
    running_in_same_ = 0;
  }
  // Said when the detection has held for 10 cycles, with twice its
  // running-in after it, on a trend that is itself flat (over the steady
  // window it changes by less than half the steady band: early in a test the
  // "steady" half is still running in); said again when it moves on by
  // more than half the steady window.
  const bool flat =
      std::abs(ri.steady_slope) * live_.steady_cycles < 0.5 * live_.steady_band;
  const bool held =
      flat && running_in_same_ >= 10 && n >= std::max(30, 2 * ri.cycles + 10);
  if (!held) return;
  if (!running_in_ended_) {
    running_in_ended_ = true;
    running_in_ = ri.cycles;
    Raise("running-in",
          fmt::format("running-in ended: {} cycles ({})", ri.cycles, ri.rule));
  } else if (ri.cycles > running_in_ + live_.steady_cycles / 2) {
    running_in_ = ri.cycles;
    Raise(
        "running-in",
        fmt::format("running-in revised: {} cycles ({})", ri.cycles, ri.rule));
  }
}

SteadyTest JudgeSteady(const std::vector<double>& mu,
                       int cycles,
                       double band,
                       int planned_cycles) {
  SteadyTest t;
  const size_t n = mu.size(), w = static_cast<size_t>(cycles);
  if (n < 2 * w) return t;
  const double per_cycle = TrendPerCycle(mu, n - w, n - 1);
  t.trend = per_cycle * static_cast<double>(w - 1);
  t.shift = MeanOf(mu, n - w, n - 1) - MeanOf(mu, n - 2 * w, n - w - 1);
  t.mean = MeanOf(mu, n - w, n - 1);
  const int done = static_cast<int>(n);
  t.cycles_left = std::max(0, planned_cycles - done);
  t.drift = per_cycle * t.cycles_left;
  t.steady = std::abs(t.trend) < band && std::abs(t.shift) < band &&
             !(std::abs(t.drift) >= band);
  return t;
}

void LiveAnalysis::UpdateSteady() {
  const size_t w = static_cast<size_t>(live_.steady_cycles);
  if (reported_.size() < 2 * w) return;
  // Once steady, it stays so until the trend or the shift leaves the band
  // widened by half (no alert flickering at the band's edge).
  const double band = steady_ ? 1.5 * live_.steady_band : live_.steady_band;
  const SteadyTest t = JudgeSteady(
      mu_hat_series_, live_.steady_cycles, band, live_.planned_cycles);
  const double per_cycle = t.trend / static_cast<double>(w - 1);
  steady_run_ = t.steady ? steady_run_ + 1 : 0;
  if (!steady_ && steady_run_ < live_.steady_hold_cycles) return;
  if (t.steady == steady_) return;
  steady_ = t.steady;
  // Its premise over the cycles left, said.
  const std::string premise =
      live_.planned_cycles > 0
          ? fmt::format(
                "{:+.6f} a cycle, {:+.4f} over the {} cycles left of "
                "those planned",
                per_cycle,
                t.drift,
                t.cycles_left)
          : fmt::format(
                "{:+.6f} a cycle; over the cycles left unknown: give "
                "--planned-cycles for that to be checked",
                per_cycle);
  Raise("steady",
        steady_
            ? fmt::format("mu-hat steady: {:.4f} over the last {} cycles "
                          "(trend {:+.4f}, shift from the {} before "
                          "{:+.4f}, both within +-{:.4f}, and so for {} "
                          "cycles; {}): the test could stop",
                          t.mean,
                          w,
                          t.trend,
                          w,
                          t.shift,
                          band,
                          steady_run_,
                          premise)
            : fmt::format("mu-hat no longer steady: trend {:+.4f}, shift "
                          "{:+.4f} over the last {} cycles, {:+.4f} over "
                          "the {} cycles {} at that trend (beyond "
                          "+-{:.4f})",
                          t.trend,
                          t.shift,
                          w,
                          t.drift,
                          t.cycles_left,
                          live_.planned_cycles > 0 ? "left" : "left (unknown)",
                          band),
        steady_);
}

void LiveAnalysis::UpdateVerdict() {
  // Over the latest cycles, from 20 on: running-in is not waited for (the
  // wear-scar model holds while the friction settles; its misfit is what
  // the verdict judges), and the words say when it has not been seen to end.
  const int n = static_cast<int>(reported_.size());
  const int k = std::min<int>(n, static_cast<int>(recent_fits_.size()));
  if (n < std::min(20, live_.verdict_cycles) || k < 10) return;
  const std::vector<MuFit> fits(recent_fits_.end() - k, recent_fits_.end());
  std::vector<double> mu, cost, diff, energy, mean;
  for (int i = 0; i < k; ++i) {
    const MuFit& f = fits[i];
    const double e = recent_energy_[recent_energy_.size() - k + i];
    mu.push_back(f.converged ? f.mu_hat : support::kNaN);
    cost.push_back(f.converged ? f.cost : support::kNaN);
    diff.push_back(f.converged ? f.mu_hat - e : support::kNaN);
    energy.push_back(e);
    mean.push_back(recent_mean_[recent_mean_.size() - k + i]);
  }
  MismatchReport r;
  r.first_cycle = n - k;
  r.last_cycle = n - 1;
  r.mu_force = Summarise(mu, 0);
  r.cost_force = Summarise(cost, 0);
  r.mu_energy = Summarise(energy, 0);
  r.mu_mean = Summarise(mean, 0);
  r.split_force = SplitCost(fits, 0, k - 1);
  r.method_difference = MeanInterval(diff, 0, k - 1);
  ProfileDecision used;  // the channel's name as fuse says it
  used.used = options_.analysis.friction.k_from_depth ? ProfileSource::kDepth
                                                      : ProfileSource::kSpring;
  r.force_slope_name = used.ChannelName();
  const Verdict v = Judge(r, options_.verdict);
  if (!v.explained && !options_.analysis.friction.k_from_depth) {
    // P's significance now; a depth channel that gives the slope P does
    // not is taken before the next cycles are fitted (Analyse).
    if (decided_at_ < 0 || n - decided_at_ >= 10) DecideSlope(false);
    if (depth_decided_) return;
  }
  // As fuse's verdict without a scan: where P's slope is within its
  // noise, k from P is noise on a rig without a spring.
  const bool noise =
      !v.explained && !options_.analysis.friction.k_from_depth &&
      ClassifyPSlope(p_significance_, options_) == PSlope::kNoise;
  const int state = noise ? 2 : v.explained ? 1 : 0;
  verdict_text_ = fmt::format(
      "over cycles {}-{}{}: {}",
      n - k + 1,
      n,
      running_in_ended_ ? "" : " (running-in not seen to end yet)",
      noise ? fmt::format("not judged: {} over the latest cycles, so k "
                          "from P is noise if the rig has no spring, and no "
                          "depth channel gives the slope; `wearscar fuse` "
                          "with the track's scan judges the test (what k "
                          "from P missed: {})",
                          PSlopeNoiseText(p_significance_),
                          fmt::join(v.reasons, "; "))
            : v.Summary());
  if (state == verdict_state_) return;
  const bool turned = verdict_state_ >= 0;
  verdict_state_ = state;
  Raise(
      "verdict",
      fmt::format("{}{}", turned ? "the verdict turned: " : "", verdict_text_),
      state == 1);
}

// What becomes of a line found after `reported` cycles: removed from the
// cycles fitted after it, as fuse removes it, or kept (--notch).
std::string LiveAnalysis::LineHandling(int reported) const {
  if (!options_.notch_hz.empty())
    return ": the live fits carry it (--notch names the lines removed)";
  if (!options_.notch_found_lines)
    return ": the live fits carry it (--notch none)";
  if (reported == 0)
    return ", removed from Q and P before the cycles are fitted, as "
           "`wearscar fuse` removes it (--notch none keeps it)";
  return fmt::format(
      ", removed from Q and P before the cycles from {} on are fitted, as "
      "`wearscar fuse` removes it (the {} before carry it; --notch none "
      "keeps it)",
      reported + 1,
      reported);
}

// Over the window (the drive's rate from its cycles), as soon as it holds
// three cycles and then every periodic_every cycles, before the new
// cycles are fitted: a line found is said once and, as fuse removes it
// (FuseOptions::notch_found_lines), taken out of the cycles fitted from
// then on (WithoutLines), at the frequency the latest (longest) window
// finds; the cycles reported before it carry it.
void LiveAnalysis::SeekPeriodicLines(int cycles_in_window) {
  const int n = static_cast<int>(reported_.size());
  if (!(period_s_ > 0) || cycles_in_window < 3 ||
      (lines_sought_at_ >= 0 && n - lines_sought_at_ < live_.periodic_every))
    return;
  lines_sought_at_ = n;
  force::PeriodicLineOptions o;
  o.power_of_two = true;  // the window's length varies: one plan for all
  for (const force::PeriodicLine& line :
       force::FindPeriodicLines(buffer_, 1.0 / period_s_, o)) {
    const auto seen = std::find_if(
        lines_seen_hz_.begin(), lines_seen_hz_.end(), [&](double f) {
          return std::abs(f - line.frequency_hz) < 0.5;
        });
    if (seen != lines_seen_hz_.end()) {
      *seen = line.frequency_hz;
      continue;
    }
    lines_seen_hz_.push_back(line.frequency_hz);
    Raise("periodic",
          fmt::format("a periodic line in the forces over the last {} "
                      "cycles: {} (interference the drive does not make){}",
                      cycles_in_window,
                      line.Describe(),
                      LineHandling(n)));
  }
}

const force::ForceRecord& LiveAnalysis::WithoutLines(
    force::ForceRecord* copy) const {
  // As fuse: the lines given, or else those found.
  const std::vector<double>& lines =
      !options_.notch_hz.empty()   ? options_.notch_hz
      : options_.notch_found_lines ? lines_seen_hz_
                                   : options_.notch_hz;
  if (lines.empty()) return buffer_;
  *copy = buffer_;
  for (const double f : lines) force::NotchLine(copy, f);
  return *copy;
}

void LiveAnalysis::UpdateDepth(const LiveCycle& c) {
  if (std::isnan(live_.max_depth_mm) || depth_raised_ ||
      !(c.depth_mm > live_.max_depth_mm))
    return;
  depth_raised_ = true;
  Raise("depth",
        fmt::format("the track is {:.4f} mm deep from the spring (P/S peak to "
                    "valley), beyond the limit {:.4f} mm",
                    c.depth_mm,
                    live_.max_depth_mm));
}

}  // namespace wearscar::fusion
