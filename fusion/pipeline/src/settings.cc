#include "wearscar/fusion/settings.h"

#include <fmt/format.h>

#include <algorithm>

#include "scan_settings.h"

namespace wearscar::fusion {
namespace {

using internal::ScanFileSettings;
using internal::TrackSettings;

using support::FlagSetting;
using support::IntegerSetting;
using support::NumberSetting;
using support::SettingError;
using support::TextSetting;
using S = support::Setting<TestSettings>;
using T = TestSettings;

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

// A unit of the force file, checked as the reader checks it.
S UnitSetting(std::string name,
              std::string help,
              std::string force::ReadForceOptions::*field) {
  return {std::move(name),
          "Force file",
          std::move(help),
          "TEXT",
          ~0u,
          [field](T* t, const std::string& text) {
            force::ReadForceOptions probe;
            probe.*field = text;
            std::string why;
            if (!probe.IsValid(&why))
              throw SettingError(fmt::format("found '{}': {}", text, why));
            t->read_force.*field = text;
          },
          [](const T&) { return std::string(); }};
}

// --columns time=NAME,x=NAME:UNIT,...: the column overrides and units (a
// column name may hold a colon; the unit is after the last one).
void ApplyColumns(const std::string& columns, force::ReadForceOptions* r) {
  std::string rest = columns;
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    const std::string item = rest.substr(0, comma);
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    const size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    const std::string value =
        eq == std::string::npos ? "" : item.substr(eq + 1);
    std::string* slot = key == "time"    ? &r->time_column
                        : key == "x"     ? &r->x_column
                        : key == "q"     ? &r->tangential_column
                        : key == "p"     ? &r->normal_column
                        : key == "depth" ? &r->depth_column
                                         : nullptr;
    std::string column = value, unit;
    const size_t colon = value.rfind(':');
    if (colon != std::string::npos && colon > 0 && colon + 1 < value.size()) {
      column = value.substr(0, colon);
      unit = value.substr(colon + 1);
    }
    if (!slot || column.empty()) {
      throw SettingError(fmt::format(
          "found '{}' in '{}'; expected time=, x=, q=, p= or depth= followed "
          "by a column name or #N (and :UNIT)",
          item,
          columns));
    }
    *slot = column;
    if (unit.empty()) continue;
    std::string* unit_slot = key == "time"    ? &r->time_unit
                             : key == "x"     ? &r->x_unit
                             : key == "depth" ? &r->depth_unit
                                              : &r->force_unit;
    if (!unit_slot->empty() && *unit_slot != unit) {
      throw SettingError(fmt::format(
          "'{}' gives unit '{}' but another setting says '{}'; expected one "
          "unit for both forces",
          item,
          unit,
          *unit_slot));
    }
    *unit_slot = unit;
  }
}

// --notch: comma-separated frequencies, Hz.
S NotchSetting(const char* group) {
  return {"notch",
          group,
          "Periodic lines to remove from Q and P before the analysis, Hz, "
          "comma-separated (mains pick-up: 50 or 60): a sinusoid fitted in "
          "blocks of about 2 s and subtracted; lines the drive does not make "
          "are warned about without it",
          "TEXT",
          ~0u,
          [](T* t, const std::string& text) {
            t->fuse.notch_hz.clear();
            size_t at = 0;
            while (at <= text.size()) {
              const size_t comma = std::min(text.find(',', at), text.size());
              t->fuse.notch_hz.push_back(support::ParseNumber(
                  std::string_view(text).substr(at, comma - at), 0.001, 1e6));
              at = comma + 1;
            }
          },
          [](const T&) { return std::string(); }};
}

std::vector<S> ForceFileSettings() {
  const char* g = "Force file";
  auto column = [g](const char* name, const char* help, auto member) {
    return TextSetting<T>(name, g, help, [member](T& t) -> std::string& {
      return t.read_force.*member;
    });
  };
  using R = force::ReadForceOptions;
  return {
      column("time-column",
             "Time column name or #N; none: the clock from the file's "
             "sampling rate or --rate",
             &R::time_column),
      column("x-column", "Displacement column name or #N", &R::x_column),
      column("q-column",
             "Friction force column name or #N",
             &R::tangential_column),
      column("p-column", "Normal force column name or #N", &R::normal_column),
      column("depth-column",
             "Depth column (the ball's vertical position: penetration "
             "depth, Z, LVDT) name or #N; none: read none",
             &R::depth_column),
      UnitSetting("x-unit",
                  "Unit of the displacement (mm, um, m); default: the "
                  "file's, else inferred from a plausible stroke with a "
                  "warning",
                  &R::x_unit),
      UnitSetting("force-unit",
                  "Unit of both forces (N, mN, kN, gf); default: the "
                  "file's, else inferred",
                  &R::force_unit),
      UnitSetting("time-unit",
                  "Unit of the time column (s, ms, min); default: the "
                  "file's, else inferred",
                  &R::time_unit),
      {"columns",
       g,
       "Column overrides in one go: time=NAME,x=NAME,q=NAME,p=NAME,"
       "depth=NAME (names or #N; any subset), each optionally with its "
       "unit: x=Pos:um",
       "TEXT",
       ~0u,
       [](T* t, const std::string& text) {
         ApplyColumns(text, &t->read_force);
       },
       [](const T&) { return std::string(); }},
      NotchSetting(g),
      NumberSetting<T>(
          "rate",
          g,
          "Sampling rate (Hz) when there is no time "
          "column",
          0,
          1e8,
          [](T& t) -> double& { return t.read_force.sampling_rate_hz; }),
      FlagSetting<T>("lenient",
                     g,
                     "Drop isolated bad rows with a warning",
                     [](T& t) -> bool& { return t.read_force.lenient; }),
      FlagSetting<T>(
          "force-channels-as-given",
          g,
          "Read Q and P as they are even when |Q| exceeds |P| on most "
          "samples or the load changes sign (refused otherwise as swapped "
          "channels)",
          [](T& t) -> bool& { return t.read_force.channels_as_given; }),
  };
}

std::vector<S> SlopeSettings() {
  const char* g = "Method";
  auto slope = [](T& t) -> force::SlopeOptions& {
    return t.fuse.analysis.friction.slope;
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
            ParseKEstimate(v, &t->fuse.analysis.friction.k_estimate);
          },
          [](const T& t) {
            return std::string(
                KEstimateName(t.fuse.analysis.friction.k_estimate));
          }),
      IntegerSetting<T>("ensemble-cycles",
                        g,
                        "Cycles averaged for the ensemble slope (odd)",
                        1,
                        10001,
                        [](T& t) -> int& {
                          return t.fuse.analysis.friction.ensemble.cycles;
                        }),
      NumberSetting<T>("ensemble-span",
                       g,
                       "Span of x of the ensemble slope's local fit, mm",
                       1e-3,
                       10,
                       [](T& t) -> double& {
                         return t.fuse.analysis.friction.ensemble.span_mm;
                       }),
      FlagSetting<T>(
          "no-k-noise-correction",
          g,
          "Keep mu-hat's second-order bias from the noise in the "
          "ensemble's k (about -3 mu var(k noise); removed by "
          "default)",
          [](T& t) -> bool& {
            return t.fuse.analysis.friction.correct_k_noise_bias;
          },
          false),
  };
}

// The stencil of the derivative of P.
std::vector<S> StencilSettings() {
  const char* g = "Method";
  auto slope = [](T& t) -> force::SlopeOptions& {
    return t.fuse.analysis.friction.slope;
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
            return DerivativeWord(t.fuse.analysis.friction.slope.method);
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
           t->fuse.analysis.running_in_cycles = -1;
           return;
         }
         try {
           t->fuse.analysis.running_in_cycles =
               static_cast<int>(support::ParseInteger(text, 0, 10000000));
         } catch (const SettingError&) {
           throw SettingError(fmt::format(
               "found '{}'; expected auto or a number of cycles >= 0", text));
         }
       },
       [](const T& t) {
         const int n = t.fuse.analysis.running_in_cycles;
         return n < 0 ? std::string("auto") : std::to_string(n);
       }},
      NumberSetting<T>(
          "running-in-tolerance",
          g,
          "Band around the steady friction trend that ends "
          "running-in (auto)",
          1e-9,
          1,
          [](T& t) -> double& { return t.fuse.analysis.running_in_tolerance; }),
      NumberSetting<T>(
          "mu-max",
          g,
          "Upper end of the mu search",
          1e-3,
          10,
          [](T& t) -> double& { return t.fuse.analysis.friction.fit.mu_max; }),
  };
}

std::vector<S> VerdictSettings() {
  const char* g = "Verdict";
  auto verdict = [](T& t) -> VerdictOptions& { return t.fuse.verdict; };
  return {
      ChoiceSetting(
          "verdict-cost",
          g,
          "Verdict on J: excess (the part of J this test's noise "
          "does not explain, --max-excess) | paper (J itself, "
          "--max-cost)",
          {"excess", "paper"},
          [](T* t, const std::string& v) {
            ParseCostCriterion(v, &t->fuse.verdict.cost_criterion);
          },
          [](const T& t) {
            return std::string(
                CostCriterionName(t.fuse.verdict.cost_criterion));
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
          [](T& t) -> bool& { return t.fuse.fit_lugre; },
          false),
      NumberSetting<T>("lugre-fc",
                       g,
                       "LuGre F_c, N (0 = from the cycle)",
                       0,
                       1e5,
                       [](T& t) -> double& { return t.fuse.lugre.coulomb_n; }),
      NumberSetting<T>("lugre-fs",
                       g,
                       "LuGre F_s, N (0 = from the cycle)",
                       0,
                       1e5,
                       [](T& t) -> double& { return t.fuse.lugre.static_n; }),
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
            t->fuse.force_profile.*f =
                static_cast<int>(support::ParseInteger(text, 1, 10000000)) - 1;
          },
          [f](const T& t) {
            const int c = t.fuse.force_profile.*f;
            return c < 0 ? std::string() : std::to_string(c + 1);
          }};
}

std::vector<S> CompareSettings() {
  auto verdict = [](T& t) -> VerdictOptions& { return t.fuse.verdict; };
  return {
      ChoiceSetting(
          "slope",
          "Method",
          "Slope of the sliding path for mu-hat: force (k = dP/dx "
          "/ S), scan (the aligned centreline) or both",
          {"force", "scan", "both"},
          [](T* t, const std::string& v) {
            ParseSlopeChoice(v, &t->fuse.slopes);
          },
          [](const T& t) {
            return std::string(SlopeChoiceName(t.fuse.slopes));
          }),
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
            ParseProfileSource(v, &t->fuse.profile_from);
          },
          [](const T& t) {
            return std::string(ProfileSourceName(t.fuse.profile_from));
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
      IntegerSetting<T>(
          "compare-cycles",
          "Scan",
          "Compare the scan with the last N cycles",
          1,
          10000000,
          [](T& t) -> int& { return t.fuse.force_profile.cycles; }),
      FlagSetting<T>("scan-slope-history",
                     "Scan",
                     "Scale the scan's slope of each cycle by that cycle's "
                     "waviness from the spring over the final one, so the "
                     "scan-side mu-hat does not carry the track's growth "
                     "(borrows from the force side: the two slopes are then "
                     "not independent)",
                     [](T& t) -> bool& { return t.fuse.scan_slope_history; }),
  };
}

std::vector<S> LevelSettings() {
  const char* g = "Scan";
  return {
      IntegerSetting<T>(
          "level-order",
          g,
          "Reference surface order (1-3)",
          1,
          3,
          [](T& t) -> int& { return t.fuse.level.polynomial_order; }),
      NumberSetting<T>(
          "band",
          g,
          "Centreline band width, mm",
          0,
          100,
          [](T& t) -> double& { return t.fuse.profile.band_width_mm; }),
      NumberSetting<T>(
          "sphere-radius",
          g,
          "Radius of the sphere that rides the track, mm: k from the scan is "
          "the slope of its path on the scanned surface (0: the centreline's)",
          0,
          999,
          [](T& t) -> double& { return t.fuse.sphere.radius_mm; }),
      ChoiceSetting(
          "scan-derivative",
          g,
          "Slope of the scan: savgol | central",
          {"savgol", "central"},
          [](T* t, const std::string& v) {
            force::ParseDerivativeMethod(v, &t->fuse.scan_slope.method);
          },
          [](const T& t) { return DerivativeWord(t.fuse.scan_slope.method); }),
      IntegerSetting<T>("scan-window",
                        g,
                        "Scan slope window, scan samples",
                        3,
                        100000,
                        [](T& t) -> int& { return t.fuse.scan_slope.window; }),
  };
}

std::vector<S> AllSettings() {
  std::vector<S> all;
  auto add = [&all](unsigned sections, std::vector<S> part) {
    for (S& s : part) all.push_back(In(sections, std::move(s)));
  };
  add(kForceFileSettings, ForceFileSettings());
  add(kSlopeSettings, SlopeSettings());
  add(kSlopeSettings, StencilSettings());
  add(kSlopeSettings, RunningInSettings());
  add(kVerdictSettings, VerdictSettings());
  add(kLugreSettings, LugreSettings());
  add(kCompareSettings, CompareSettings());
  add(kLevelTrackSettings, LevelSettings());
  add(kLevelTrackSettings, TrackSettings<T>([](T& t) -> scan::TrackOptions& {
        return t.fuse.track;
      }));
  add(kScanFileSettings,
      ScanFileSettings<T>(
          [](T& t) -> scan::ReadScanOptions& { return t.read_scan; }));
  return all;
}

}  // namespace

const std::vector<support::Setting<TestSettings>>& TestSettingList() {
  static const std::vector<S> list = AllSettings();
  return list;
}

TestSettings MakeTestSettings(
    const std::vector<std::pair<std::string, std::string>>& given) {
  TestSettings t;
  support::ApplySettings(TestSettingList(), given, &t);
  t.fuse.spring_given =
      std::any_of(given.begin(), given.end(), [](const auto& g) {
        return g.first == "spring";
      });
  const auto& fp = t.fuse.force_profile;
  if (fp.first_cycle >= 0 && fp.last_cycle >= 0 &&
      fp.first_cycle > fp.last_cycle) {
    throw support::SettingFailed(
        "compare-first",
        fmt::format("cycle {} is after the last compared cycle {}; expected "
                    "first <= last",
                    fp.first_cycle + 1,
                    fp.last_cycle + 1));
  }
  std::string why;
  if (!t.fuse.IsValid(&why) || !t.read_force.IsValid(&why) ||
      !t.read_scan.IsValid(&why)) {
    throw support::SettingFailed("", why);
  }
  return t;
}

}  // namespace wearscar::fusion
