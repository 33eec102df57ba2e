#include "wearscar/fusion/fuse_settings.h"

#include <fmt/format.h>

#include <algorithm>

namespace wearscar::fusion {
namespace {

using support::FlagSetting;
using support::IntegerSetting;
using support::NumberSetting;
using support::SettingError;
using support::TextSetting;
using S = support::Setting<FuseOptions>;
using T = FuseOptions;

// The word a derivative method is written with.
std::string DerivativeWord(force::DerivativeMethod m) {
  return m == force::DerivativeMethod::kSavitzkyGolay ? "savgol" : "central";
}

S In(unsigned sections, S s) {
  s.sections = sections;
  return s;
}

// A text setting with a fixed set of words, parsed into the struct.
S ChoiceSetting(std::string name,
                std::string group,
                std::string help,
                std::vector<std::string> choices,
                std::function<void(T*, const std::string&)> set,
                std::function<std::string(const T&)> show) {
  return {std::move(name),
          std::move(group),
          std::move(help),
          "TEXT",
          ~0u,
          [set, choices](T* t, const std::string& text) {
            set(t, support::ParseChoice(text, choices));
          },
          std::move(show)};
}

std::vector<S> SlopeSettings() {
  const char* g = "Method";
  auto slope = [](T& t) -> force::SlopeOptions& {
    return t.analysis.friction.slope;
  };
  return {
      NumberSetting<T>(
          "spring",
          g,
          "Loading spring stiffness S, N/mm",
          1e-6,
          1e6,
          [slope](T& t) -> double& { return slope(t).spring_n_per_mm; }),
      ChoiceSetting(
          "k-estimate",
          g,
          "Slope of P: ensemble (P(x) averaged over neighbouring "
          "cycles) | cycle (each cycle's own P, the paper)",
          {"ensemble", "cycle"},
          [](T* t, const std::string& v) {
            ParseKEstimate(v, &t->analysis.friction.k_estimate);
          },
          [](const T& t) {
            return std::string(KEstimateName(t.analysis.friction.k_estimate));
          }),
      IntegerSetting<T>(
          "ensemble-cycles",
          g,
          "Cycles averaged for the ensemble slope (odd)",
          1,
          10001,
          [](T& t) -> int& { return t.analysis.friction.ensemble.cycles; }),
      NumberSetting<T>(
          "ensemble-span",
          g,
          "Span of x of the ensemble slope's local fit, mm",
          1e-3,
          10,
          [](T& t) -> double& { return t.analysis.friction.ensemble.span_mm; }),
      FlagSetting<T>(
          "no-k-noise-correction",
          g,
          "Keep mu-hat's second-order bias from the noise in the "
          "ensemble's k (about -3 mu var(k noise); removed by "
          "default)",
          [](T& t) -> bool& {
            return t.analysis.friction.correct_k_noise_bias;
          },
          false),
  };
}

// The stencil of the derivative of P.
std::vector<S> StencilSettings() {
  const char* g = "Method";
  auto slope = [](T& t) -> force::SlopeOptions& {
    return t.analysis.friction.slope;
  };
  return {
      NumberSetting<T>("window-ms",
                       g,
                       "Smoothing window of P in time, ms (cycle estimate; "
                       "5 ms = the paper's 10 samples at 2 kHz)",
                       1e-3,
                       1e4,
                       [slope](T& t) -> double& { return slope(t).window_ms; }),
      {"window",
       g,
       "Smoothing window of P in samples instead of --window-ms (the "
       "paper: 10)",
       "INTEGER",
       ~0u,
       [slope](T* t, const std::string& text) {
         slope(*t).window =
             static_cast<int>(support::ParseInteger(text, 0, 100000));
       },
       [](const T&) { return std::string(); }},
      NumberSetting<T>(
          "difference-ms",
          g,
          "Half span of the central difference, ms (0.5 ms = "
          "the paper's Eq. 5 at 2 kHz)",
          1e-3,
          1e4,
          [slope](T& t) -> double& { return slope(t).half_span_ms; }),
      ChoiceSetting(
          "derivative",
          g,
          "Slope of P: central (paper Eq. 5) | savgol",
          {"central", "savgol"},
          [slope](T* t, const std::string& v) {
            force::ParseDerivativeMethod(v, &slope(*t).method);
          },
          [](const T& t) {
            return DerivativeWord(t.analysis.friction.slope.method);
          }),
      NumberSetting<T>(
          "min-span",
          g,
          "Widen the difference stencil to span at least this "
          "x, mm (0 = paper)",
          0,
          10,
          [slope](T& t) -> double& { return slope(t).min_span_mm; }),
  };
}

std::vector<S> RunningInSettings() {
  const char* g = "Method";
  return {
      {"running-in",
       g,
       "Running-in cycles excluded from statistics: a number, or auto (the "
       "friction settles within --running-in-tolerance of the steady trend)",
       "TEXT",
       ~0u,
       [](T* t, const std::string& text) {
         if (text == "auto") {
           t->analysis.running_in_cycles = -1;
           return;
         }
         try {
           t->analysis.running_in_cycles =
               static_cast<int>(support::ParseInteger(text, 0, 10000000));
         } catch (const SettingError&) {
           throw SettingError(fmt::format(
               "found '{}'; expected auto or a number of cycles >= 0", text));
         }
       },
       [](const T& t) {
         const int n = t.analysis.running_in_cycles;
         return n < 0 ? std::string("auto") : std::to_string(n);
       }},
      NumberSetting<T>(
          "running-in-tolerance",
          g,
          "Band around the steady friction trend that ends "
          "running-in (auto)",
          1e-9,
          1,
          [](T& t) -> double& { return t.analysis.running_in_tolerance; }),
      NumberSetting<T>(
          "mu-max",
          g,
          "Upper end of the mu search",
          1e-3,
          10,
          [](T& t) -> double& { return t.analysis.friction.fit.mu_max; }),
  };
}

std::vector<S> VerdictSettings() {
  const char* g = "Verdict";
  auto verdict = [](T& t) -> VerdictOptions& { return t.verdict; };
  return {
      ChoiceSetting(
          "verdict-cost",
          g,
          "Verdict on J: excess (the part of J this test's noise "
          "does not explain, --max-excess) | paper (J itself, "
          "--max-cost)",
          {"excess", "paper"},
          [](T* t, const std::string& v) {
            ParseCostCriterion(v, &t->verdict.cost_criterion);
          },
          [](const T& t) {
            return std::string(CostCriterionName(t.verdict.cost_criterion));
          }),
      NumberSetting<T>(
          "max-excess",
          g,
          "Verdict: largest J above its noise floor (lower end "
          "of its 95% interval)",
          1e-9,
          100,
          [verdict](T& t) -> double& { return verdict(t).max_cost_excess; }),
      NumberSetting<T>(
          "max-cost",
          g,
          "Verdict with --verdict-cost paper: largest J after "
          "running-in",
          1e-9,
          100,
          [verdict](T& t) -> double& { return verdict(t).max_cost; }),
      NumberSetting<T>("max-method-difference",
                       g,
                       "Verdict: largest |mu-hat - mu_energy| (its whole 95% "
                       "interval beyond it)",
                       1e-9,
                       10,
                       [verdict](T& t) -> double& {
                         return verdict(t).max_method_difference;
                       }),
  };
}

std::vector<S> LugreSettings() {
  const char* g = "Method";
  return {
      FlagSetting<T>(
          "no-lugre",
          g,
          "Skip the LuGre comparison",
          [](T& t) -> bool& { return t.fit_lugre; },
          false),
      NumberSetting<T>("lugre-fc",
                       g,
                       "LuGre F_c, N (0 = from the cycle)",
                       0,
                       1e5,
                       [](T& t) -> double& { return t.lugre.coulomb_n; }),
      NumberSetting<T>("lugre-fs",
                       g,
                       "LuGre F_s, N (0 = from the cycle)",
                       0,
                       1e5,
                       [](T& t) -> double& { return t.lugre.static_n; }),
  };
}

// A cycle counted from 1 in the text, from 0 in the struct (-1: not set).
S CycleSetting(std::string name,
               std::string help,
               int ForceProfileOptions::*f) {
  return {std::move(name),
          "Scan",
          std::move(help),
          "INTEGER",
          ~0u,
          [f](T* t, const std::string& text) {
            t->force_profile.*f =
                static_cast<int>(support::ParseInteger(text, 1, 10000000)) - 1;
          },
          [f](const T& t) {
            const int c = t.force_profile.*f;
            return c < 0 ? std::string() : std::to_string(c + 1);
          }};
}

std::vector<S> CompareSettings() {
  auto verdict = [](T& t) -> VerdictOptions& { return t.verdict; };
  return {
      ChoiceSetting(
          "slope",
          "Method",
          "Slope of the sliding path for mu-hat: force (k = dP/dx "
          "/ S), scan (the aligned centreline) or both",
          {"force", "scan", "both"},
          [](T* t, const std::string& v) { ParseSlopeChoice(v, &t->slopes); },
          [](const T& t) { return std::string(SlopeChoiceName(t.slopes)); }),
      ChoiceSetting(
          "profile-from",
          "Method",
          "The force side's profile of the sliding path: spring (P/S), depth "
          "(the depth channel, k = -d depth/dx), friction (the two "
          "directions' Q at the same x, for a dead-weight rig; needs a scan) "
          "or auto (spring unless P's slope is insignificant, then depth when "
          "logged, else friction when P does not follow the scanned track)",
          {"auto", "spring", "depth", "friction"},
          [](T* t, const std::string& v) {
            ParseProfileSource(v, &t->profile_from);
          },
          [](const T& t) {
            return std::string(ProfileSourceName(t.profile_from));
          }),
      CycleSetting("compare-first",
                   "Compare from this cycle (from 1; with --compare-last) "
                   "instead of the last N",
                   &ForceProfileOptions::first_cycle),
      CycleSetting("compare-last",
                   "Last cycle compared",
                   &ForceProfileOptions::last_cycle),
      NumberSetting<T>("max-amplitude-ratio",
                       "Verdict",
                       "Verdict: largest std(P/S) / std(scan profile) (lower "
                       "end of its 95% interval)",
                       1e-9,
                       1e3,
                       [verdict](T& t) -> double& {
                         return verdict(t).max_amplitude_ratio;
                       }),
      NumberSetting<T>(
          "min-correlation",
          "Verdict",
          "Verdict: smallest correlation of the aligned profiles",
          -1,
          1,
          [verdict](T& t) -> double& { return verdict(t).min_correlation; }),
      IntegerSetting<T>("compare-cycles",
                        "Scan",
                        "Compare the scan with the last N cycles",
                        1,
                        10000000,
                        [](T& t) -> int& { return t.force_profile.cycles; }),
      FlagSetting<T>("scan-slope-history",
                     "Scan",
                     "Scale the scan's slope of each cycle by that cycle's "
                     "waviness from the spring over the final one, so the "
                     "scan-side mu-hat does not carry the track's growth "
                     "(borrows from the force side: the two slopes are then "
                     "not independent)",
                     [](T& t) -> bool& { return t.scan_slope_history; }),
  };
}

std::vector<S> LevelSettings() {
  const char* g = "Scan";
  return {
      IntegerSetting<T>("level-order",
                        g,
                        "Reference surface order (1-3)",
                        1,
                        3,
                        [](T& t) -> int& { return t.level.polynomial_order; }),
      NumberSetting<T>("band",
                       g,
                       "Centreline band width, mm",
                       0,
                       100,
                       [](T& t) -> double& { return t.profile.band_width_mm; }),
      NumberSetting<T>(
          "sphere-radius",
          g,
          "Radius of the sphere that rides the track, mm: k from the scan is "
          "the slope of its path on the scanned surface (0: the centreline's)",
          0,
          999,
          [](T& t) -> double& { return t.sphere.radius_mm; }),
      ChoiceSetting(
          "scan-derivative",
          g,
          "Slope of the scan: savgol | central",
          {"savgol", "central"},
          [](T* t, const std::string& v) {
            force::ParseDerivativeMethod(v, &t->scan_slope.method);
          },
          [](const T& t) { return DerivativeWord(t.scan_slope.method); }),
      IntegerSetting<T>("scan-window",
                        g,
                        "Scan slope window, scan samples",
                        3,
                        100000,
                        [](T& t) -> int& { return t.scan_slope.window; }),
  };
}

}  // namespace

const std::vector<support::Setting<FuseOptions>>& FuseSettingList() {
  static const std::vector<S> list = [] {
    std::vector<S> all;
    auto add = [&all](unsigned sections, std::vector<S> part) {
      for (S& s : part) all.push_back(In(sections, std::move(s)));
    };
    add(kSlopeSettings, SlopeSettings());
    add(kSlopeSettings, StencilSettings());
    add(kSlopeSettings, RunningInSettings());
    add(kVerdictSettings, VerdictSettings());
    add(kLugreSettings, LugreSettings());
    add(kCompareSettings, CompareSettings());
    add(kLevelTrackSettings, LevelSettings());
    return all;
  }();
  return list;
}

}  // namespace wearscar::fusion
